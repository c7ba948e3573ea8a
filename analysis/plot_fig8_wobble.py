#!/usr/bin/env python3
"""Fig 8: the hand tip's distance to its target over time."""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import physik_plot as pp  # noqa: E402


def plot(folder):
    t = pp.read_table(os.path.join(folder, "trajectory.csv"))
    hand = sorted(c for c in t if c.startswith("residual_"))[-1]
    return pp.curves([(t["step"], [max(r, 1e-12) for r in t[hand]], "hand tip residual")],
                     os.path.join(folder, "fig8_wobble.png"), "step", "distance to target",
                     "Fig 8: does the hand tip keep oscillating?", logy=True)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("folder")
    print("  wrote", plot(ap.parse_args(argv).folder))


if __name__ == "__main__":
    main()
