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


def render(sections):
    out = ["# PhysIK reproduction report", "",
           "Written by `analysis/report.py` from `results/*/summary.json` on %s. Every number below "
           "was measured by the run that wrote this file (`make reproduce`)." %
           datetime.datetime.now().strftime("%Y-%m-%d %H:%M"), ""]
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
    text = render(collect(args.results))
    path = os.path.join(args.results, "REPORT.md")
    with open(path, "w") as f:
        f.write(text)
    print("wrote", path)


if __name__ == "__main__":
    main()
