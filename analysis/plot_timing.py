#!/usr/bin/env python3
"""Timing: microseconds per step and passes per step per scene, beside the paper's numbers."""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import physik_plot as pp  # noqa: E402


def plot(folder):
    rows = pp.load_summary(folder)["rows"]
    fig, (a, b) = pp.plt.subplots(1, 2, figsize=(10, 3.8))
    names = [r["scene"] for r in rows]
    a.barh(names, [r["us_per_step"] for r in rows], color="tab:blue")
    a.set_xlabel("microseconds per step (paper: 98 000 per frame)")
    b.barh(names, [r["passes_per_step_while_moving"] for r in rows], color="tab:orange", label="while moving")
    b.barh(names, [r["passes_per_step"] for r in rows], color="tab:green", alpha=0.6, label="whole run")
    b.axvline(20, color="k", ls="--", lw=1, label="paper ~20")
    b.set_xlabel("joint passes per step")
    b.legend(fontsize=8)
    return pp.save(fig, os.path.join(folder, "timing.png"))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("folder")
    print("  wrote", plot(ap.parse_args(argv).folder))


if __name__ == "__main__":
    main()
