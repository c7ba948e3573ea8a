#!/usr/bin/env python3
"""Fig 7: frames at the paper's steps for linear and capped springs, in a 3D view as the paper
shows them: one axis range for every panel (so the 12-unit travel shows), the target, a dashed line
from the control point to it, and the path the control point has taken; and the kinetic energy
over time. Reads results/fig7_cannon/{summary.json, <law>.csv, <law>_frame_*.csv}."""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import physik_plot as pp  # noqa: E402

COLORS = {"linear": "k", "capped": "tab:blue"}


def attachment(head, tail, alpha):
    return tuple(h + alpha * (t - h) for h, t in zip(head, tail))


def control_path(table, bone, alpha, last_step):
    """The control point's positions over the recorded steps up to last_step (inclusive)."""
    cols = ["%s.%s_%s" % (bone, end, a) for end in ("head", "tail") for a in "xyz"]
    path = []
    for k, step in enumerate(table["step"]):
        if step > last_step:
            break
        v = [table[c][k] for c in cols]
        path.append(attachment(v[:3], v[3:], alpha))
    return path


def bounds(points, margin=0.4):
    """One box around every point, (lo, hi) per axis, for every panel: the same range and scale."""
    lo = [min(p[i] for p in points) - margin for i in range(3)]
    hi = [max(p[i] for p in points) + margin for i in range(3)]
    return lo, hi


def draw3d(ax, bones, color, target, point, path, box):
    for b in bones:
        ax.plot(*[[b["head"][i], b["tail"][i]] for i in range(3)], "-", color=color, lw=1.6)
    if path:
        ax.plot(*[[p[i] for p in path] for i in range(3)], "-", color="tab:green", lw=0.8)
    ax.plot(*[[point[i], target[i]] for i in range(3)], "--", color="tab:red", lw=0.9)
    ax.plot(*[[target[i]] for i in range(3)], "x", color="tab:red", ms=7, mew=2)
    lo, hi = box
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_zlim(lo[2], hi[2])
    ax.set_box_aspect([h - l for l, h in zip(lo, hi)])  # equal scale on the three axes
    ax.view_init(elev=20, azim=-55)
    ax.set_xticks([round(lo[0] + 0.5), round(hi[0] - 0.5)])
    ax.tick_params(labelsize=7)
    ax.set_xlabel("x", fontsize=8, labelpad=-6)
    ax.set_ylabel("y", fontsize=8, labelpad=-6)
    ax.set_zlabel("z", fontsize=8, labelpad=-6)


def plot_frames(folder, s):
    laws = [law for law in ("linear", "capped") if law in s["laws"]]
    first = s["laws"][laws[0]]
    ncol = len(first["frames"])
    fig = pp.plt.figure(figsize=(3.8 * ncol, 3.2 * len(laws)))
    poses = {law: [pp.read_bones_csv(os.path.join(folder, f)) for f in s["laws"][law]["frames"]]
             for law in laws}
    pts = [b[e] for law in laws for bones in poses[law] for b in bones for e in ("head", "tail")]
    pts += [tuple(s["laws"][law]["target_world"]) for law in laws]
    box = bounds(pts)
    for r, law in enumerate(laws):
        m = s["laws"][law]
        table = pp.read_table(os.path.join(folder, m["csv"]))
        for c, (bones, step) in enumerate(zip(poses[law], m["frame_steps"])):
            ax = fig.add_subplot(len(laws), ncol, r * ncol + c + 1, projection="3d")
            b = next(x for x in bones if x["bone"] == m["control_bone"])
            point = attachment(b["head"], b["tail"], m["control_alpha"])
            path = control_path(table, m["control_bone"], m["control_alpha"], step)
            draw3d(ax, bones, COLORS[law], m["target_world"], point, path, box)
            ax.set_title("%s, step %d" % (law, step), fontsize=9)
    fig.suptitle("Fig 7: the torso's target moved 12 units at once (red x; dashed: the pull, "
                 "green: the path so far)", fontsize=10)
    return pp.save(fig, os.path.join(folder, "fig7_cannon_frames.png"))


def plot(folder):
    s = pp.load_summary(folder)
    frames = plot_frames(folder, s)
    series = []
    for law in ("linear", "capped"):
        t = pp.read_table(os.path.join(folder, s["laws"][law]["csv"]))
        series.append((t["step"], [max(e, 1e-12) for e in t["kinetic_energy"]], law))
    energy = pp.curves(series, os.path.join(folder, "fig7_cannon_energy.png"), "step",
                       "kinetic energy (J)", "Fig 7: kinetic energy", logy=True)
    return frames, energy


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("folder")
    for p in plot(ap.parse_args(argv).folder):
        print("  wrote", p)


if __name__ == "__main__":
    main()
