#!/usr/bin/env python3
"""Draw solved poses (bones CSVs) for a by-eye comparison with the paper's Blender screenshots:
front and side views (analysis/physik_plot.py) and a 3D view from the camera of the paper's file
(shared/data/pinhead.blend: camera at (7.48, -6.51, 5.34) looking at the origin).

    /usr/bin/python3 blender/plot_pose.py --pose itasc.csv iTaSC --pose rest.csv rest \
        --scene models/scenes/fig9_outstretched.json --out itasc_fig9.png
"""
import argparse
import json
import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "analysis"))
sys.path.insert(0, HERE)
import physik_plot  # noqa: E402
from physik_plot import plt  # noqa: E402

CAMERA = (7.481, -6.508, 5.344)  # the paper file's camera (Blender units, world)
COLORS = ["tab:orange", "tab:blue", "tab:green", "tab:purple"]


def color_of(k, label):
    return "0.75" if label == "rest" else COLORS[k % len(COLORS)]


def draw_3d(ax, bones, color, label, targets):
    for k, b in enumerate(bones):
        xs, ys, zs = zip(b["head"], b["tail"])
        ax.plot(xs, ys, zs, "-", color=color, lw=2, label=label if k == 0 else None)
    for t in targets:
        ax.scatter([t[0]], [t[1]], [t[2]], marker="x", color="tab:red", s=40)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--pose", nargs=2, action="append", metavar=("CSV", "LABEL"), required=True)
    p.add_argument("--rig", help="rig file whose rest pose is drawn faint behind")
    p.add_argument("--scene", help="scene file whose control-point targets are drawn")
    p.add_argument("--title", default="")
    p.add_argument("--out", required=True)
    a = p.parse_args(argv)
    targets = []
    if a.scene:
        with open(a.scene) as f:
            targets = [c["target"] for c in json.load(f).get("control_points", [])]
    poses = [(physik_plot.read_bones_csv(path), label) for path, label in a.pose]
    if a.rig:
        from physik_addon import rig_format
        rig = rig_format.load_rig(a.rig)
        poses.insert(0, ([{"bone": b["name"], "parent": b["parent"] or "", "head": b["head"],
                        "tail": b["tail"]} for b in rig["bones"]], "rest"))
    fig = plt.figure(figsize=(13, 4.6))
    for i, view in enumerate(("front", "side")):
        ax = fig.add_subplot(1, 3, i + 1)
        for k, (bones, label) in enumerate(poses):
            physik_plot.draw_pose(ax, bones, view, color=color_of(k, label), label=label,
                                  targets=targets if k == len(poses) - 1 else None)
        ax.set_title(view + " view")
        ax.legend(fontsize=7, loc="lower left")
    ax = fig.add_subplot(1, 3, 3, projection="3d")
    for k, (bones, label) in enumerate(poses):
        draw_3d(ax, bones, color_of(k, label), label, targets if k == len(poses) - 1 else [])
    cx, cy, cz = CAMERA
    ax.view_init(elev=math.degrees(math.atan2(cz, math.hypot(cx, cy))),
                 azim=math.degrees(math.atan2(cy, cx)))
    ax.set_box_aspect((1, 1, 1))
    for setter in (ax.set_xlim, ax.set_ylim):
        setter(-2.5, 2.5)
    ax.set_zlim(-2.6, 2.4)
    ax.set_title("paper camera")
    fig.suptitle(a.title)
    physik_plot.save(fig, a.out)
    print("wrote", a.out)


if __name__ == "__main__":
    main()
