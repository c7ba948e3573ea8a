#!/usr/bin/env python3
"""Draw one pose: the front and side views of a final_pose.csv (written by `physik simulate` and
`physik solve`), with the scene's control-point targets as red crosses when --scene is given.

Run: /usr/bin/python3 analysis/plot_pose.py OUT/final_pose.csv [--scene SCENE.json] [--out PNG]
The drawing helpers are analysis/physik_plot.py's (the same stick figures as the paper figures).
"""
import argparse
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import physik_plot  # noqa: E402


def scene_targets(path):
    """The final target of every control point: its schedule's last jump, else its target."""
    with open(path) as f:
        scene = json.load(f)
    points = scene.get("control_points", [])
    targets = [p["target"] for p in points]
    names = [p.get("name", p.get("bone")) for p in points]
    for jump in sorted(scene.get("schedule", []), key=lambda j: j["step"]):
        who = jump["control_point"]
        k = who if isinstance(who, int) else names.index(who)
        targets[k] = jump["target"]
    return [tuple(t) for t in targets]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("pose", help="a final_pose.csv (bone, parent, head_x..z, tail_x..z)")
    ap.add_argument("--scene", help="the scene file, for its targets")
    ap.add_argument("--out", help="the PNG to write (default: beside the pose, pose.png)")
    args = ap.parse_args(argv)
    bones = physik_plot.read_bones_csv(args.pose)
    targets = scene_targets(args.scene) if args.scene else None
    out = args.out or os.path.join(os.path.dirname(os.path.abspath(args.pose)), "pose.png")
    fig, axes = physik_plot.plt.subplots(1, 2, figsize=(8, 4.5))
    for ax, view in zip(axes, ("front", "side")):
        physik_plot.draw_pose(ax, bones, view, targets=targets)
        ax.set_title("%s view" % view, fontsize=9)
    fig.suptitle(args.pose, fontsize=9)
    physik_plot.save(fig, out)
    print("wrote", out)


if __name__ == "__main__":
    main()
