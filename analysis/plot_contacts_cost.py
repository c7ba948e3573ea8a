#!/usr/bin/env python3
"""Contacts' step cost: the coils' microseconds per step against bones, log-log, with and without
the contacts, n log n through the ring's smallest size dashed; and the ratios against the
targets (pinhead 2x, the largest coils 5x). Reads the summary's rows; computes only the n log n
reference line."""
import argparse
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import physik_plot as pp  # noqa: E402
from matplotlib.ticker import ScalarFormatter  # noqa: E402

COLORS = {"flat_spiral": "tab:blue", "flat_ring": "tab:orange"}


def plot(folder):
    rows = pp.load_summary(folder)["rows"]
    coils = [r for r in rows if r["workload"] in COLORS]
    pinhead = [r for r in rows if r["workload"] == "pinhead"]
    missing = [w for w in ("pinhead", *COLORS) if not any(r["workload"] == w for r in rows)]
    if missing:
        raise ValueError("%s/summary.json: no %s rows" % (folder, ", ".join(missing)))
    fig, (a, b) = pp.plt.subplots(1, 2, figsize=(11, 4.2))
    for name, color in COLORS.items():
        pts = sorted((r["bones"], r["contacts_us"], r["no_contacts_us"]) for r in coils
                     if r["workload"] == name)
        n = [p[0] for p in pts]
        a.loglog(n, [p[1] for p in pts], "o-", color=color, label=name.replace("_", " ") + ", contacts")
        a.loglog(n, [p[2] for p in pts], "s:", color=color, alpha=0.6, label=name.replace("_", " ") + ", none")
        if name == "flat_ring":
            n0, t0 = pts[0][0], pts[0][1]
            a.loglog(n, [t0 * m * math.log(m) / (n0 * math.log(n0)) for m in n], "k--", lw=1,
                     label="n log n from the ring's first size")
    a.set_xticks(sorted({r["bones"] for r in coils}))
    a.get_xaxis().set_major_formatter(ScalarFormatter())
    a.minorticks_off()
    a.set_xlabel("bones")
    a.set_ylabel("us per step (thread CPU time)")
    a.legend(fontsize=7)
    a.grid(True, which="both", lw=0.3)
    largest = max(r["bones"] for r in coils)
    bars = [("pinhead", pinhead[0]["ratio"], 2.0)]
    bars += [("%s %d" % (r["workload"].replace("_", " "), r["bones"]), r["ratio"], 5.0)
             for r in coils if r["bones"] == largest]
    b.barh([x[0] for x in bars], [x[1] for x in bars], color="tab:green")
    for i, (_, _, target) in enumerate(bars):
        b.plot([target, target], [i - 0.4, i + 0.4], "r-", lw=2)
    b.set_xlabel("step with contacts / step without (red: the target)")
    return pp.save(fig, os.path.join(folder, "contacts_cost.png"))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("folder")
    print("  wrote", plot(ap.parse_args(argv).folder))


if __name__ == "__main__":
    main()
