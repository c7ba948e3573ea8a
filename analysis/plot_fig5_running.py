#!/usr/bin/env python3
"""Fig 5: the running pose from 8 control points, front and side, targets marked."""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import physik_plot as pp  # noqa: E402


def plot(folder):
    s = pp.load_summary(folder)
    targets = [tuple(c["target"]) for c in s["control_points"]]
    bones = pp.read_bones_csv(os.path.join(folder, s["final_frame"]))
    rest = pp.read_bones_csv(os.path.join(folder, s["frames"][0]))
    return pp.pose_panels(
        [{"bones": rest, "title": "rest", "targets": targets},
         {"bones": bones, "title": "after %d steps" % s["summary"]["steps_run"], "targets": targets}],
        os.path.join(folder, "fig5_running.png"), suptitle="Fig 5: running pose (x = targets)")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("folder")
    print("  wrote", plot(ap.parse_args(argv).folder))


if __name__ == "__main__":
    main()
