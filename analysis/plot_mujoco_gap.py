#!/usr/bin/env python3
"""PhysIK vs MuJoCo: the endpoint gap over time per scene and mode, and the final poses drawn
side by side (PhysIK black, MuJoCo blue)."""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import physik_plot as pp  # noqa: E402


def plot(folder):
    t = pp.read_table(os.path.join(folder, "gap_over_time.csv"))
    keys = sorted(set(zip(t["scene"], t["mode"])))
    series = []
    for scene, mode in keys:
        idx = [i for i in range(len(t["step"])) if t["scene"][i] == scene and t["mode"][i] == mode]
        series.append(([t["step"][i] for i in idx], [max(t["gap"][i], 1e-12) for i in idx],
                       "%s %s" % (scene, mode)))
    gap = pp.curves(series, os.path.join(folder, "mujoco_gap.png"), "step",
                    "largest endpoint gap (rig units)", "PhysIK vs MuJoCo", logy=True)
    s = pp.load_summary(folder)
    panels = []
    for row in s["rows"]:
        panels.append({"bones": pp.read_bones_csv(os.path.join(folder, row["physik_csv"])),
                       "label": "PhysIK", "title": "%s\n%s" % (row["scene"], row["mode"]),
                       "overlay": [{"bones": pp.read_bones_csv(os.path.join(folder, row["mujoco_csv"])),
                                    "color": "tab:blue", "label": "MuJoCo"}]})
    poses = pp.pose_panels(panels, os.path.join(folder, "mujoco_poses.png"), views=("front", "side"),
                           size=2.8, suptitle="final poses: PhysIK (black) and MuJoCo (blue)")
    return gap, poses


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("folder")
    for p in plot(ap.parse_args(argv).folder):
        print("  wrote", p)


if __name__ == "__main__":
    main()
