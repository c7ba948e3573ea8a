#!/usr/bin/env python3
"""Fig 7: frames at the paper's steps for linear and capped springs; kinetic energy over time."""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import physik_plot as pp  # noqa: E402


def plot(folder):
    s = pp.load_summary(folder)
    rows = []
    for law in ("linear", "capped"):
        m = s["laws"][law]
        rows.append([{"bones": pp.read_bones_csv(os.path.join(folder, name)),
                      "title": "%s, step %d" % (law, step),
                      "color": "k" if law == "linear" else "tab:blue"}
                     for name, step in zip(m["frames"], m["frame_steps"])])
    frames = pp.pose_grid(rows, os.path.join(folder, "fig7_cannon_frames.png"), view="side",
                          suptitle="Fig 7: target 12 units ahead, -y (side view)")
    series = []
    for law in ("linear", "capped"):
        t = pp.read_table(os.path.join(folder, s["laws"][law]["csv"]))
        series.append((t["step"], [max(e, 1e-12) for e in t["kinetic_energy"]], law))
    energy = pp.curves(series, os.path.join(folder, "fig7_cannon_energy.png"), "step",
                       "kinetic energy (J)", "Fig 7: kinetic energy", logy=True)
    return frames, energy


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("folder")
    for p in plot(ap.parse_args(argv).folder):
        print("  wrote", p)


if __name__ == "__main__":
    main()
