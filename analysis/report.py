#!/usr/bin/env python3
"""Gather every experiment's summary.json "report" section into results/REPORT.md, and the
same report as results/REPORT.html with the experiments' runs in embedded 3D viewers
(analysis/report_html.py; `--physik BINARY` writes the viewer pages first).

The settings table at the top takes the engine's parameters from results/params.json
(`physik params --json`). Each summary may carry:
  "report": {"title": str, "claims": [{"claim", "measured", "holds"}], "notes": [str],
             "figures": [png names relative to the experiment folder], "settings": {...},
             "tables": [{"title": str, "columns": [str], "rows": [[cell, ...]]}]}
"""
import argparse
import datetime
import json
import os
import re
import sys
import textwrap

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import report_html  # noqa: E402


def collect(results):
    sections = []
    for name in sorted(os.listdir(results)):
        path = os.path.join(results, name, "summary.json")
        if not os.path.isfile(path):
            continue
        summary = json.load(open(path))
        rep = summary.get("report", {})
        for c in rep.get("claims", []):
            if not is_verdict(c.get("holds", "")):
                raise SystemExit("%s: claim '%s': holds '%s' is not a verdict (yes, no, partly or "
                                 "n/a, with a reason in parentheses); the reason belongs in "
                                 "measured" % (path, c.get("claim", "")[:80], c.get("holds")))
        sections.append((name, summary, rep))
    order = summary_order(results)
    sections.sort(key=lambda s: order.get(s[0], 1000))
    return sections


def summary_order(results):
    """Run order written by scripts/reproduce.sh, when present."""
    path = os.path.join(results, "order.txt")
    if not os.path.isfile(path):
        return {}
    return {line.strip(): k for k, line in enumerate(open(path)) if line.strip()}


# The paper's settings beside ours. Names, values and units come from the engine's parameter
# table (`physik params --json`, which scripts/reproduce.sh writes to results/params.json). In a
# cell, {name} is the parameter's value and unit: in the "paper" column the `paper` preset's, in
# "used here" the default preset's; {name:%} is a fraction as a percentage; {name@runs} the
# values the experiments report in their settings. The rest is what the paper says and why.
PAPER_SETTINGS = [
    # (setting: table names or text, paper, used here, why; None = the damping sweep's finding)
    ("dt", "{dt} (captions imply 5 ms)", "{dt}", "the text's value; 5 ms per step contradicts dt = 0.05"),
    ("damping", "{damping}", "{damping} (the original code's)", None),
    ("control_k", "{control_k}", "{control_k@runs} in every paper scene", "as the paper"),
    ("joint_eps", "{joint_eps}", "{joint_eps}", "as the paper"),
    ("max_passes", "not stated", "{max_passes} (the original code's)", "the original's value"),
    ("torsion_k, torsion_tolerance", "not stated",
     "{torsion_k}, {torsion_tolerance:%} inside each limit (the original's)", "the original's values"),
    ("control_cap", "not stated", "{control_cap} (the original hard-codes 1)", "the original's value"),
    ("free_rods", "independent rods (text)", "{free_rods} (the original code's: FK from the root)",
     "free rods drift apart at first order in dt (docs/engine.md); both are available"),
    ("knee/elbow range", "0..120 deg (text)", "0..160 deg", "the paper's own rig file says 160"),
]


def value_text(row, value):
    """A parameter's value with its unit, as the report writes it: 0.05 s, 5 n^2, 1 rig unit."""
    if row["kind"] in ("boolean", "choice"):
        return str(value).lower() if row["kind"] == "boolean" else value
    if value == 0 and row.get("zero_means"):
        return row["zero_means"]
    text = "%g" % value
    unit = row["unit"]
    if unit in ("", "1"):
        return text
    if value == 1 and unit.endswith("units"):
        unit = unit[:-1]
    return text + " " + unit


def fill(template, table, preset, runs):
    """Replace {name}, {name:%} and {name@runs} in a settings cell."""
    rows = {r["name"]: r for r in table["params"]}

    def one(match):
        name, how = match.group(1), match.group(2) or ""
        if name not in rows:
            raise KeyError("report settings: no parameter '%s' in params.json" % name)
        row = rows[name]
        if how == ":%":
            return "%g%%" % (100 * row["defaults"][preset])
        if how == "@runs":
            seen = sorted({s[name] for s in runs if name in s}, key=str)
            return " / ".join(value_text(row, v) for v in seen) or "(no run reports it)"
        return value_text(row, row["defaults"][preset])

    return re.sub(r"\{(\w+)(:%|@runs)?\}", one, template)


PAPER_SCENES_PRESET = "original"  # the preset every paper scene names (models/scenes)


def settings_section(results, sections=()):
    why_damping = "c = 20 diverges with dt = 0.05 on pinhead (see the damping sweep)"
    path = os.path.join(results, "damping_sweep", "summary.json")
    if os.path.isfile(path):
        for c in json.load(open(path)).get("report", {}).get("claims", []):
            if "c = 20" in c["claim"]:
                why_damping = "measured: " + c["measured"]
    out = ["## Settings: the paper's and ours", ""]
    params_path = os.path.join(results, "params.json")
    if not os.path.isfile(params_path):
        return out + ["(no params.json here: `physik params --json > %s` writes the table this "
                      "section is made from)" % params_path, ""]
    table = json.load(open(params_path))
    runs = [rep["settings"] for _, _, rep in sections if rep.get("settings")]
    names = {r["name"] for r in table["params"]}
    out += ["| setting | paper | used here | why |", "|---|---|---|---|"]
    for name, paper, used, why in PAPER_SETTINGS:
        label = ", ".join("`%s`" % n if n in names else n for n in name.split(", "))
        out.append("| %s | %s | %s | %s |" % (
            label, fill(paper, table, "paper", runs),
            fill(used, table, PAPER_SCENES_PRESET, runs), why or why_damping))
    out.append("")
    return out


LINE_MAX = 600  # characters in any line of REPORT.md (analysis/tests checks it)
WRAP = 100  # prose wraps at this width; a table row cannot wrap and is a bullet when too long


def wrapped(text, first="", rest=""):
    """text in lines of at most WRAP characters, broken at spaces only (a line break reads as a
    space, so never at a hyphen), the first line after `first`, the others after `rest`."""
    return textwrap.wrap(text, width=WRAP, initial_indent=first, subsequent_indent=rest,
                         break_long_words=False, break_on_hyphens=False) or [first.rstrip()]


def pieces(text):
    """text cut at its "; " outside parentheses: the items of a measured list."""
    out, depth, start = [], 0, 0
    for k, ch in enumerate(text):
        depth += {"(": 1, ")": -1}.get(ch, 0)
        if depth == 0 and text.startswith("; ", k):
            out.append(text[start:k])
            start = k + 2
    return [p for p in out + [text[start:]] if p.strip()]


def table_lines(table):
    """A report table as markdown: its title in bold, then the columns and rows; a table with a
    row longer than LINE_MAX as one bullet per row ("column: cell; ..."), wrapped."""
    cols = table["columns"]
    for row in table["rows"]:
        if len(row) != len(cols):
            raise ValueError("table '%s': a row has %d cells for %d columns" %
                             (table["title"], len(row), len(cols)))
    rows = ["| " + " | ".join(str(c) for c in row) + " |" for row in table["rows"]]
    if all(len(r) <= LINE_MAX for r in rows):
        return (["**%s**" % table["title"], "", "| " + " | ".join(cols) + " |",
                 "|" + "---|" * len(cols)] + rows + [""])
    out = ["**%s**" % table["title"], ""]
    for row in table["rows"]:
        out += wrapped("; ".join("%s: %s" % (c, v) for c, v in zip(cols, row)), "- ", "  ")
    return out + [""]


ROW_MAX = 200  # characters in a row of the summary table; the full claim is in its section


def shorten(text, limit):
    """text within limit characters: whole when it fits, else cut at the last clause or word
    boundary that fits, with an ellipsis (the section below gives it whole)."""
    if len(text) <= limit:
        return text
    head = text[:max(limit - 1, 1)]
    for sep in ("; ", ": ", ", ", " "):
        k = head.rfind(sep)
        if k >= limit // 2:
            return head[:k].rstrip(" ;:,") + "\u2026"
    return head + "\u2026"


def final_parenthetical(text):
    """The index where text's closing parenthetical starts ("... (far target, cap c = 1)"), or
    None: what tells apart the rows of one claim made per case."""
    if not text.endswith(")"):
        return None
    depth = 0
    for k in range(len(text) - 1, -1, -1):
        depth += {")": 1, "(": -1}.get(text[k], 0)
        if depth == 0:
            return k
    return None


def shorten_claim(text, limit):
    """A claim within limit characters, keeping its closing parenthetical when that is short."""
    k = final_parenthetical(text)
    if len(text) <= limit or k is None or len(text) - k > limit // 2:
        return shorten(text, limit)
    tail = text[k:]
    return shorten(text[:k].rstrip(), limit - len(tail) - 1) + " " + tail


VERDICTS = ("yes", "no", "partly", "n/a")


def is_verdict(holds):
    """A holds cell is a verdict word, alone or with a reason in parentheses (experiments/report.h
    check_verdict): "no (a run diverged)", never a sentence."""
    word, paren, rest = holds.partition(" (")
    return word in VERDICTS and (not paren or (len(rest) > 1 and rest.endswith(")")))


def verdict(holds):
    """The verdict word of a claim's holds cell ("partly (only in the transient)" -> partly)."""
    return holds.split(" (", 1)[0]


def summary_row(name, c):
    """One summary-table row of at most ROW_MAX characters: experiment, claim, verdict and a
    measured phrase, the claim and the phrase shortened to fit."""
    claim = "`%s` " % c["name"] + c["claim"] if c.get("name") else c["claim"]
    frame = "| %s |  | %s |  |" % (name, verdict(c["holds"]))
    room = ROW_MAX - len(frame)
    claim = shorten_claim(claim, max(room - min(len(c["measured"]), 70), room // 2))
    return "| %s | %s | %s | %s |" % (name, claim, verdict(c["holds"]),
                                     shorten(c["measured"], room - len(claim)))


def headline_lines(sections, readme):
    """The README's headline claim (<!-- headline: experiment/name -->) and its verdict here."""
    if not readme or not os.path.isfile(readme):
        return []
    m = re.search(r"<!-- headline: ([a-z0-9_]+)/([a-z0-9-]+) -->", open(readme).read())
    if not m:
        return []
    found = [c for n, _, rep in sections if n == m.group(1) for c in rep.get("claims", [])
             if c.get("name") == m.group(2)]
    if not found:
        return ["README's headline cites claim `%s/%s`, which this run did not report." %
                m.groups(), ""]
    return wrapped("README's headline cites claim `%s/%s`: **%s** (%s)." %
                   (m.group(1), m.group(2), found[0]["holds"], found[0]["measured"])) + [""]


def summary_section(sections, readme):
    out = ["## Summary", "", "Every claim, its verdict and a short measured phrase; the "
           "experiment's section has it whole.", ""]
    out += headline_lines(sections, readme)
    out += ["| experiment | claim | holds | measured |", "|---|---|---|---|"]
    for name, _, rep in sections:
        out += [summary_row(name, c) for c in rep.get("claims", [])]
    return out + [""]


def claims_lines(rep):
    """An experiment's claims, whole: claim, verdict with its reason, what was measured; where
    that is longer than a line, the measured list as short bullets under the claim."""
    out = []
    for c in rep.get("claims", []):
        named = " (`%s`)" % c["name"] if c.get("name") else ""
        head = "- **%s**%s: %s." % (c["claim"], named, c["holds"])
        if len(head) + 1 + len(c["measured"]) <= WRAP:
            out.append(head + " " + c["measured"])
            continue
        out += wrapped(head[2:], "- ", "  ")
        for item in pieces(c["measured"]):
            out += wrapped(item, "  - ", "    ")
    return out + ([""] if out else [])


def render(sections, results=None, readme=None):
    written = ("Written by `analysis/report.py` from `results/*/summary.json` on %s. Every number "
               "below was measured by the run that wrote this file (`make reproduce`)." %
               datetime.datetime.now().strftime("%Y-%m-%d %H:%M"))
    out = ["# PhysIK reproduction report", ""] + wrapped(written) + [""]
    out += summary_section(sections, readme)
    for name, summary, rep in sections:
        out += ['<a id="%s"></a>' % name, "", "## %s" % rep.get("title", name), ""]
        settings = rep.get("settings")
        if settings:
            out += wrapped("Settings: " + ", ".join("%s = %s" % kv for kv in settings.items()))
            out.append("")
        out += claims_lines(rep)
        for note in rep.get("notes", []):
            out += wrapped(note, "- ", "  ")
        if rep.get("notes"):
            out.append("")
        for table in rep.get("tables", []):
            out += table_lines(table)
        for fig in rep.get("figures", []):
            rel = os.path.join(name, fig)
            out.append("![%s](%s)" % (fig, rel))
        if results:
            out += motion_lines(results, name)
        out.append("")
    if results:
        out += settings_section(results, sections)
    return "\n".join(out) + "\n"


def motion_lines(results, name):
    """The experiment's animated GIF (analysis/animate.py) after its figures, and a link to its
    3D viewer page (analysis/report_html.py), where they exist."""
    out = []
    gif = os.path.join(name, "animation.gif")
    if os.path.isfile(os.path.join(results, gif)):
        out.append("![%s: animation](%s)" % (name, gif))
    pages = report_html.view_pages(results, name)
    if pages:
        runs = len(report_html.run_folders(results, name))
        links = ", ".join("[%s](%s) (%.1f MB)" % (p, p, os.path.getsize(os.path.join(results, p))
                                                  / 1e6) for p in pages)
        out += ["", "3D viewer of the %d run%s%s: %s (self-contained; REPORT.html embeds the "
                "first)" % (runs, "" if runs == 1 else "s",
                            ", a page per rig" if len(pages) > 1 else "", links)]
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("results", help="the results/ folder")
    ap.add_argument("--physik", help="the physik binary: write each experiment's viewer page "
                    "(<name>/view.html) from its run folders first")
    args = ap.parse_args(argv)
    readme = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "README.md")
    sections = collect(args.results)
    if args.physik:
        report_html.make_views(args.results, sections, args.physik)
    text = render(sections, args.results, readme)
    for name, content in (("REPORT.md", text),
                          ("REPORT.html", report_html.to_html(text, args.results))):
        path = os.path.join(args.results, name)
        with open(path, "w") as f:
            f.write(content)
        print("wrote", path)


if __name__ == "__main__":
    main()
