#!/usr/bin/env python3
"""Draw every rig's rest pose (paper Fig 4) from results/rest_poses/*.csv."""
import argparse
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import physik_plot  # noqa: E402


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("folder", help="results/rest_poses (holds summary.json and one CSV per rig)")
    args = ap.parse_args(argv)
    summary = json.load(open(os.path.join(args.folder, "summary.json")))
    for rig in summary["rigs"]:
        png = physik_plot.plot_rest_pose(os.path.join(args.folder, rig["csv"]),
                                         os.path.join(args.folder, rig["figure"]),
                                         "%s: %d bones, %d joints" % (rig["name"], rig["bones"], rig["joints"]))
        print("  wrote", png)


if __name__ == "__main__":
    main()
