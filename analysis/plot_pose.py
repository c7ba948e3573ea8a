#!/usr/bin/env python3
"""Draw one pose: the front and side views of a final_pose.csv (written by `physik simulate` and
`physik solve`), with the scene's control-point targets as red crosses when --scene is given.

The views follow the rig, not the world's axes. The front view looks at the rig's face, its
left on the right of the picture; the side view looks at its left side, its face to the left.
It faces the horizontal direction f for which its left is z x f, its left being the direction
from its right bones to its left bones (names holding "left"/"right", or ".L"/".R", "_l"/"_r"):
pinhead faces -y, MuJoCo's humanoid +x. A rig without such names faces along its horizontal
axis of least extent (the depth of a body wider than it is deep), toward -y (+x where that axis
is x); --facing sets it (--facing=-y, ...). Each view is framed on the pose and the targets,
with a margin of a tenth of their extent.

Run: /usr/bin/python3 analysis/plot_pose.py OUT/final_pose.csv [--scene SCENE.json] [--out PNG]
     [--facing=auto|+x|-x|+y|-y]
The drawing helpers are analysis/physik_plot.py's (the same stick figures as the paper figures).
"""
import argparse
import json
import math
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import physik_plot  # noqa: E402

FACINGS = {"+x": (1.0, 0.0), "-x": (-1.0, 0.0), "+y": (0.0, 1.0), "-y": (0.0, -1.0)}
LEFT = re.compile(r"left|(^|[._\- ])l($|[._\- ])", re.I)
RIGHT = re.compile(r"right|(^|[._\- ])r($|[._\- ])", re.I)


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


def _mean(points):
    return tuple(sum(p[k] for p in points) / len(points) for k in range(2))


def rig_facing(bones):
    """The horizontal unit direction (x, y) the posed rig faces (see the module's text)."""
    ends = lambda bs: [b[k][:2] for b in bs for k in ("head", "tail")]  # noqa: E731
    left = [b for b in bones if LEFT.search(b["bone"]) and not RIGHT.search(b["bone"])]
    right = [b for b in bones if RIGHT.search(b["bone"]) and not LEFT.search(b["bone"])]
    everything = ends(bones)
    xs, ys = [p[0] for p in everything], [p[1] for p in everything]
    extent = max(max(xs) - min(xs), max(ys) - min(ys), 1e-300)
    if left and right:
        (lx, ly), (rx, ry) = _mean(ends(left)), _mean(ends(right))
        ax, ay = lx - rx, ly - ry  # right to left
        n = math.hypot(ax, ay)
        if n > 1e-6 * extent:
            return (ay / n, -ax / n)  # (left axis) x z: the face's side
    # no sides by name: the horizontal axis of least spread (the smaller principal axis)
    cx, cy = _mean(everything)
    sxx = sum((x - cx) ** 2 for x in xs)
    syy = sum((y - cy) ** 2 for y in ys)
    sxy = sum((x - cx) * (y - cy) for x, y in zip(xs, ys))
    angle = 0.5 * math.atan2(2 * sxy, sxx - syy)  # the major axis
    fx, fy = -math.sin(angle), math.cos(angle)  # the minor axis
    if fy > 1e-12 or (abs(fy) <= 1e-12 and fx < 0):
        fx, fy = -fx, -fy  # toward -y, or +x when the axis is x
    return (fx, fy)


def view_frame(facing):
    """The views' horizontal axes in world (x, y): the front view's screen right (the rig's
    left, looking at its face) and the side view's (its back: it faces left)."""
    fx, fy = facing
    return (-fy, fx), (-fx, -fy)


def direction_text(d):
    """A horizontal unit direction as the world axis it is, else its components."""
    for name, (x, y) in FACINGS.items():
        if abs(d[0] - x) < 1e-9 and abs(d[1] - y) < 1e-9:
            return name
    return "(%.2f, %.2f, 0)" % d


def in_view_frame(points_or_bones, facing):
    """Bones (or points) with x, y replaced by their coordinates along the views' axes, so that
    physik_plot's front view (x, z) and side view (y, z) are the rig's."""
    front, side = view_frame(facing)

    def turn(p):
        return (p[0] * front[0] + p[1] * front[1], p[0] * side[0] + p[1] * side[1], p[2])
    if points_or_bones and isinstance(points_or_bones[0], dict):
        return [dict(b, head=turn(b["head"]), tail=turn(b["tail"])) for b in points_or_bones]
    return [turn(p) for p in points_or_bones]


def frame_view(ax, bones, targets, view):
    """The view's window: every bone end and target, a tenth of their extent around them."""
    i = 0 if view == "front" else 1
    pts = [b[k] for b in bones for k in ("head", "tail")] + list(targets or [])
    us, vs = [p[i] for p in pts], [p[2] for p in pts]
    margin = 0.1 * max(max(us) - min(us), max(vs) - min(vs), 1e-9)
    ax.set_xlim(min(us) - margin, max(us) + margin)
    ax.set_ylim(min(vs) - margin, max(vs) + margin)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("pose", help="a final_pose.csv (bone, parent, head_x..z, tail_x..z)")
    ap.add_argument("--scene", help="the scene file, for its targets")
    ap.add_argument("--out", help="the PNG to write (default: beside the pose, pose.png)")
    ap.add_argument("--facing", default="auto", choices=["auto"] + sorted(FACINGS),
                    help="the horizontal direction the rig faces (default: from its bones)")
    args = ap.parse_args(argv)
    bones = physik_plot.read_bones_csv(args.pose)
    targets = scene_targets(args.scene) if args.scene else None
    facing = rig_facing(bones) if args.facing == "auto" else FACINGS[args.facing]
    front, side = view_frame(facing)
    turned = in_view_frame(bones, facing)
    turned_targets = in_view_frame(targets, facing) if targets else None
    out = args.out or os.path.join(os.path.dirname(os.path.abspath(args.pose)), "pose.png")
    fig, axes = physik_plot.plt.subplots(1, 2, figsize=(8, 4.5))
    for ax, view, across in zip(axes, ("front", "side"), (front, side)):
        physik_plot.draw_pose(ax, turned, view, targets=turned_targets)
        ax.set_aspect("equal", adjustable="box")
        frame_view(ax, turned, turned_targets, view)
        ax.set_xlabel("%s (world %s)" % ("the rig's left" if view == "front" else "its back",
                                         direction_text(across)))
        ax.set_title("%s view (facing %s)" % (view, direction_text(facing)), fontsize=9)
    fig.suptitle(args.pose, fontsize=9)
    physik_plot.save(fig, out)
    print("wrote", out)


if __name__ == "__main__":
    main()
