#!/usr/bin/env python3
"""Fig 6: the limited elbow at rest for each spring law and target (side view y-z)."""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import physik_plot as pp  # noqa: E402


def plot(folder):
    s = pp.load_summary(folder)
    panels = []
    for c in s["cases"]:
        panels.append({"bones": pp.read_bones_csv(os.path.join(folder, c["final_frame"])),
                       "title": "%s: over-bend %.1f deg\n(peak %.1f)" % (c["case"], c["final_overbend_deg"],
                                                                      c["peak_overbend_deg"])})
    return pp.pose_panels(panels, os.path.join(folder, "fig6_elbow.png"), views=("side",),
                          suptitle="Fig 6: elbow limited to 90..180 deg")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("folder")
    print("  wrote", plot(ap.parse_args(argv).folder))


if __name__ == "__main__":
    main()
