#!/usr/bin/env python3
"""Fig 6: the limited elbow at rest for each spring law and target (side view y-z), drawn as the
paper draws it: the wrist's target with a dashed line from the wrist to it, and the elbow's limit
(the forearm bent exactly 90 deg from the upper arm) as a dotted ray, so the over-bend past the
limit can be checked by eye. Reads results/fig6_elbow/{summary.json, *_frame_*.csv}."""
import argparse
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import physik_plot as pp  # noqa: E402

LIMIT_DEG = 90.0  # the forearm's largest bend from the upper arm's line (interior angle 90 deg)


def limit_ray(bones):
    """The forearm at its limit, (head, tail) in the side view's (y, z): the upper arm's direction
    turned by LIMIT_DEG in the bend plane, toward the side the forearm bends to."""
    upper = next(b for b in bones if not b["parent"])
    fore = next(b for b in bones if b["parent"] == upper["bone"])
    uy, uz = upper["tail"][1] - upper["head"][1], upper["tail"][2] - upper["head"][2]
    fy, fz = fore["tail"][1] - fore["head"][1], fore["tail"][2] - fore["head"][2]
    n, length = math.hypot(uy, uz), math.hypot(fy, fz)
    a = math.radians(LIMIT_DEG) * (1 if uy * fz - uz * fy > 0 else -1)
    dy = (uy * math.cos(a) - uz * math.sin(a)) / n * length
    dz = (uy * math.sin(a) + uz * math.cos(a)) / n * length
    head = (fore["head"][1], fore["head"][2])
    return head, (head[0] + dy, head[1] + dz)


def draw_case(ax, bones, targets):
    pp.draw_pose(ax, bones, "side")
    (hy, hz), (ty, tz) = limit_ray(bones)
    ax.plot([hy, ty], [hz, tz], ":", color="tab:gray", lw=2, label="limit (90 deg)")
    if targets:
        wrist = next(b for b in bones if b["parent"])["tail"]
        t = targets[-1]  # the wrist's target: the scene's last control point
        ax.plot([wrist[1], t[1]], [wrist[2], t[2]], "--", color="tab:red", lw=1)
        ax.plot([t[1]], [t[2]], "x", color="tab:red", ms=9, mew=2, label="target")
        ax.legend(fontsize=8, loc="lower right")


def plot(folder):
    s = pp.load_summary(folder)
    cases = s["cases"]
    nrow = 2 if len(cases) > 3 and len(cases) % 2 == 0 else 1  # a row per target
    ncol = len(cases) // nrow
    fig, axes = pp.plt.subplots(nrow, ncol, figsize=(3.4 * ncol, 3.4 * nrow), squeeze=False)
    axes = list(axes.flat)
    poses = [pp.read_bones_csv(os.path.join(folder, c["final_frame"])) for c in cases]
    for ax, c, bones in zip(axes, cases, poses):
        draw_case(ax, bones, c.get("targets_world"))
        ax.set_title("%s\nover-bend %.1f deg (peak %.1f)" % (
            c["case"], c["final_overbend_deg"], c["peak_overbend_deg"]), fontsize=9)
    targets = [[t for t in c.get("targets_world", [])] for c in cases]
    extra = [[{"head": t, "tail": t} for t in ts] for ts in targets]
    pp.same_limits(axes, [p + e for p, e in zip(poses, extra)], "side", margin=0.3)
    fig.suptitle("Fig 6: elbow limited to 90..180 deg, at rest (side view)")
    return pp.save(fig, os.path.join(folder, "fig6_elbow.png"))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("folder")
    print("  wrote", plot(ap.parse_args(argv).folder))


if __name__ == "__main__":
    main()
