#!/usr/bin/env python3
"""Gather every experiment's summary.json "report" section into results/REPORT.md.

Each summary may carry:
  "report": {"title": str, "claims": [{"claim", "measured", "holds"}], "notes": [str],
             "figures": [png names relative to the experiment folder], "settings": {...}}
"""
import argparse
import datetime
import json
import os


def collect(results):
    sections = []
    for name in sorted(os.listdir(results)):
        path = os.path.join(results, name, "summary.json")
        if not os.path.isfile(path):
            continue
        summary = json.load(open(path))
        rep = summary.get("report", {})
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


PAPER_SETTINGS = [
    # (setting, paper, used, why)
    ("dt", "0.05 s (captions imply 5 ms)", "0.05 s", "the text's value; 5 ms per step contradicts dt = 0.05"),
    ("damping c", "20 N s/m", "3 N s/m (the original code's)", None),
    ("control spring k", "30 N/m", "30 N/m in every paper scene", "as the paper"),
    ("joint eps", "0.001", "0.001", "as the paper"),
    ("pass cap", "not stated", "5 n^2 (the original code's)", "the original's value"),
    ("torsion k, band", "not stated", "10 N m/rad, 10% inside each limit (the original's)", "the original's values"),
    ("cap c of capped springs", "not stated", "1 rig unit (the original hard-codes 1)", "the original's value"),
    ("integration", "independent rods (text)", "articulated (the original code's)",
     "free rods drift apart at first order in dt (see README); both are available"),
    ("knee/elbow range", "0..120 deg (text)", "0..160 deg", "the paper's own rig file says 160"),
]


def settings_section(results):
    why_damping = "c = 20 diverges with dt = 0.05 on pinhead (see the damping sweep)"
    path = os.path.join(results, "damping_sweep", "summary.json")
    if os.path.isfile(path):
        for c in json.load(open(path)).get("report", {}).get("claims", []):
            if "c = 20" in c["claim"]:
                why_damping = "measured: " + c["measured"]
    out = ["## Settings: the paper's and ours", "",
           "| setting | paper | used here | why |", "|---|---|---|---|"]
    for name, paper, used, why in PAPER_SETTINGS:
        out.append("| %s | %s | %s | %s |" % (name, paper, used, why or why_damping))
    out.append("")
    return out


def render(sections, results=None):
    out = ["# PhysIK reproduction report", "",
           "Written by `analysis/report.py` from `results/*/summary.json` on %s. Every number below "
           "was measured by the run that wrote this file (`make reproduce`)." %
           datetime.datetime.now().strftime("%Y-%m-%d %H:%M"), ""]
    figures = [(n, f) for n, _, rep in sections for f in rep.get("figures", [])]
    if figures:
        out += ["Figures: " + ", ".join("[%s](%s/%s)" % (f, n, f) for n, f in figures), ""]
    if results:
        out += settings_section(results)
    claims = [(n, c) for n, _, rep in sections for c in rep.get("claims", [])]
    out += ["## Claims", "", "| experiment | paper claim | measured | holds |", "|---|---|---|---|"]
    for name, c in claims:
        out.append("| %s | %s | %s | %s |" % (name, c["claim"], c["measured"], c["holds"]))
    out.append("")
    for name, summary, rep in sections:
        out += ["## %s" % rep.get("title", name), ""]
        settings = rep.get("settings")
        if settings:
            out.append("Settings: " + ", ".join("%s = %s" % kv for kv in settings.items()))
            out.append("")
        for note in rep.get("notes", []):
            out.append("- " + note)
        if rep.get("notes"):
            out.append("")
        for fig in rep.get("figures", []):
            rel = os.path.join(name, fig)
            out.append("![%s](%s)" % (fig, rel))
        out.append("")
    return "\n".join(out) + "\n"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("results", help="the results/ folder")
    args = ap.parse_args(argv)
    text = render(collect(args.results), args.results)
    path = os.path.join(args.results, "REPORT.md")
    with open(path, "w") as f:
        f.write(text)
    print("wrote", path)


if __name__ == "__main__":
    main()
