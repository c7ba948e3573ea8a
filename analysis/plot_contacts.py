#!/usr/bin/env python3
"""Contacts: PhysIK's final poses of the contacts experiment's runs (the drops on the floor, the
hand pulled through the torso with and without self-collision, Fig 11 on a seat, Fig 7's linear
cannon), from results/contacts/runs/; the seat and the floor from summary.json."""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import physik_plot as pp  # noqa: E402

RUNS = [("drop_flat", "dropped lying flat"), ("drop_tilted", "dropped turned 60 deg"),
        ("hand_no_self_collision", "hand through torso: off"),
        ("hand_self_collision", "hand through torso: self-collision"), ("sit", "Fig 11 on a seat"),
        ("cannon_paper", "linear cannon: paper's scheme"),
        ("cannon_implicit_no_self_collision", "linear cannon: implicit, off"),
        ("cannon_implicit_self_collision", "linear cannon: implicit, self-collision")]


def scenery(folder, name):
    """The sit run's seat and floor (summary.json "sit"); nothing for the other runs."""
    path = os.path.join(folder, "summary.json")
    if name != "sit" or not os.path.exists(path):
        return {}
    sit = pp.load_summary(folder).get("sit", {})
    if "seat_center" not in sit:
        return {}
    return {"boxes": [(sit["seat_center"], sit["seat_half_extents"])], "floor": sit.get("floor_height")}


def plot(folder):
    panels = []
    for name, title in RUNS:
        path = os.path.join(folder, "runs", name, "final_pose.csv")
        if os.path.exists(path):
            panels.append({"bones": pp.read_bones_csv(path), "title": title, **scenery(folder, name)})
    return pp.pose_panels(panels, os.path.join(folder, "contacts_poses.png"),
                          views=("front", "side"), suptitle="Contacts: final poses (PhysIK)")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("folder", help="results/contacts")
    print("  wrote", plot(ap.parse_args(argv).folder))


if __name__ == "__main__":
    main()
