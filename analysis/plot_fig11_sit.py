#!/usr/bin/env python3
"""Paper Fig 11: the sitting animation (results/fig11_sit).

fig11_frames.png     the saved frames (the paper's sit-0..5) in the side view (y-z), the start
                     pose faint behind each, the feet's targets as red crosses
fig11_residuals.png  every control point's residual over time (log scale), schedule steps marked
"""
import argparse
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import physik_plot  # noqa: E402
from physik_plot import plt  # noqa: E402


def window(poses, view, margin=0.25):
    """One window around every pose in the view, ((x0, x1), (y0, y1)), fitted to the poses' own
    width and height (not a square: a standing rig is tall and narrow)."""
    i, j = {"front": (0, 2), "side": (1, 2)}[view]
    xs = [b[k][i] for bones in poses for b in bones for k in ("head", "tail")]
    ys = [b[k][j] for bones in poses for b in bones for k in ("head", "tail")]
    return ((min(xs) - margin, max(xs) + margin), (min(ys) - margin, max(ys) + margin))


def plot_frames(folder, frames, out_png, view="side", targets=None):
    """frames: [{"step": int, "file": bones csv}] in order; one panel each; targets: static
    control-point targets [(x, y, z)] drawn as crosses."""
    first = physik_plot.read_bones_csv(os.path.join(folder, frames[0]["file"]))
    poses = [physik_plot.read_bones_csv(os.path.join(folder, f["file"])) for f in frames]
    (x0, x1), (y0, y1) = window([first] + poses, view)
    height = 4.2
    width = max(1.6, height * (x1 - x0) / (y1 - y0) + 0.7)  # each panel as wide as the poses
    fig, axes = plt.subplots(1, len(frames), figsize=(width * len(frames), height + 0.5),
                             squeeze=False)
    drawn = [first]
    for k, f in enumerate(frames):
        ax = axes[0][k]
        physik_plot.draw_pose(ax, first, view, color="0.8")
        drawn.append(poses[k])
        physik_plot.draw_pose(ax, drawn[-1], view, color="tab:blue", targets=targets)
        ax.set_title("sit-%d (step %d)" % (k, f["step"]), fontsize=9)
        ax.set_aspect("equal", adjustable="box")
        ax.set_xlim(x0, x1)
        ax.set_ylim(y0, y1)
    fig.suptitle("Fig 11: sitting from one moving (pelvis) and four static control points, %s view"
                 % view, fontsize=10)
    return physik_plot.save(fig, out_png)


def plot_residuals(csv_path, out_png, schedule_steps=()):
    t = physik_plot.read_table(csv_path)
    names = [c for c in t if c.startswith("residual_")]
    fig, axes = plt.subplots(1, 2, figsize=(12, 4))
    for n in names:
        axes[0].semilogy(t["step"], [max(v, 1e-9) for v in t[n]], label=n[len("residual_"):])
    axes[1].semilogy(t["step"], [max(v, 1e-12) for v in t["kinetic_energy"]], color="k")
    for ax in axes:
        for s in schedule_steps:
            ax.axvline(s, color="0.6", lw=0.8, ls="--")
        ax.set_xlabel("step")
        ax.grid(True, lw=0.3)
    axes[0].set_ylabel("distance to target (rig units)")
    axes[0].set_title("control-point residuals (dashed: pelvis target moves)", fontsize=10)
    axes[0].legend(fontsize=8)
    axes[1].set_ylabel("J")
    axes[1].set_title("kinetic energy", fontsize=10)
    return physik_plot.save(fig, out_png)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("folder", help="results/fig11_sit")
    args = ap.parse_args(argv)
    summary = json.load(open(os.path.join(args.folder, "summary.json")))
    static = [c["target"] for c in summary.get("control_points", []) if not c.get("moving")]
    print("  wrote", plot_frames(args.folder, summary["frames"],
                                 os.path.join(args.folder, "fig11_frames.png"), targets=static))
    print("  wrote", plot_residuals(os.path.join(args.folder, "residuals.csv"),
                                    os.path.join(args.folder, "fig11_residuals.png"),
                                    summary.get("schedule_steps", [])))


if __name__ == "__main__":
    main()
