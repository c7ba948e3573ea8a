#!/usr/bin/env python3
"""Contacts: PhysIK's final poses of the contacts experiment's runs (the drops on the floor, the
hand pulled through the torso with and without self-collision, Fig 11 on a seat, Fig 7's linear
cannon), from results/contacts/runs/, the seat and the floor from summary.json; and the coils (a
long chain dropped in a helix onto the floor, and laid in a flat spiral) at their last step."""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.collections import LineCollection  # noqa: E402

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


def segments(bones, i, j):
    return [[(b["head"][i], b["head"][j]), (b["tail"][i], b["tail"][j])] for b in bones]


COILS = [("coil", "dropped in a helix"), ("coil_laid", "laid in a flat spiral")]


def plot_coil(folder):
    """Each coil's last pose from above (bones coloured by height) and from the front."""
    runs = [(os.path.join(folder, "runs", name, "final_pose.csv"), title) for name, title in COILS]
    runs = [(path, title) for path, title in runs if os.path.exists(path)]
    if not runs:
        return None
    fig, axes = plt.subplots(len(runs), 2, figsize=(11, 5 * len(runs)), squeeze=False,
                             gridspec_kw={"width_ratios": [3, 2]})
    for (path, title), (top, front) in zip(runs, axes):
        bones = pp.read_bones_csv(path)
        height = [0.5 * (b["head"][2] + b["tail"][2]) for b in bones]
        for ax, (i, j, xl, yl) in ((top, (0, 1, "x", "y")), (front, (0, 2, "x", "z"))):
            lines = LineCollection(segments(bones, i, j), linewidths=1.5, cmap="viridis")
            lines.set_array(height)
            ax.add_collection(lines)
            ax.autoscale()
            ax.set_aspect("equal", adjustable="datalim")
            ax.set_xlabel(xl)
            ax.set_ylabel(yl)
            ax.grid(True, lw=0.3)
        fig.colorbar(top.collections[0], ax=top, label="height of the bone's centre (rig units)")
        top.set_title("%d bones %s: from above" % (len(bones), title), fontsize=9)
        front.set_title("from the front", fontsize=9)
    fig.suptitle("Contacts: the coils at their last step (PhysIK)")
    return pp.save(fig, os.path.join(folder, "contacts_coil.png"))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("folder", help="results/contacts")
    folder = ap.parse_args(argv).folder
    print("  wrote", plot(folder))
    coil = plot_coil(folder)
    if coil:
        print("  wrote", coil)


if __name__ == "__main__":
    main()
