#!/usr/bin/env python3
"""Contacts: PhysIK's final poses of the contacts experiment's runs (the drops on the floor, the
hand pulled through the torso with and without self-collision), from results/contacts/runs/."""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import physik_plot as pp  # noqa: E402

RUNS = [("drop_flat", "dropped lying flat"), ("drop_tilted", "dropped turned 60 deg"),
        ("hand_no_self_collision", "hand through torso: off"),
        ("hand_self_collision", "hand through torso: self-collision")]


def plot(folder):
    panels = []
    for name, title in RUNS:
        path = os.path.join(folder, "runs", name, "final_pose.csv")
        if os.path.exists(path):
            panels.append({"bones": pp.read_bones_csv(path), "title": title})
    return pp.pose_panels(panels, os.path.join(folder, "contacts_poses.png"),
                          views=("front", "side"), suptitle="Contacts: final poses (PhysIK)")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("folder", help="results/contacts")
    print("  wrote", plot(ap.parse_args(argv).folder))


if __name__ == "__main__":
    main()
