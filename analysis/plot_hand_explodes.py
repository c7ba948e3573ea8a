#!/usr/bin/env python3
"""Paper Sec. 5: the tightly limited hand (results/hand_explodes).

hand_timeline.png  kinetic energy and largest joint-limit violation per step, the shipped scene
                   and every torsion_k x damping sweep run (a line ends where a run diverged)
hand_sweep.png     peak kinetic energy and max limit violation per sweep run, as bars
                   (hatched: the run explodes)
hand_poses.png     frames of the shipped run, front and side views
"""
import argparse
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import physik_plot  # noqa: E402
from physik_plot import plt  # noqa: E402


def _series(table, name):
    """(steps, values) of a column, skipping the empty cells after a run stopped."""
    steps, vals = [], []
    for s, v in zip(table["step"], table[name]):
        if isinstance(v, float):
            steps.append(s)
            vals.append(v)
    return steps, vals


def plot_timeline(csv_path, out_png):
    t = physik_plot.read_table(csv_path)
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(13, 4.5))
    s, v = _series(t, "kinetic_energy")
    a1.semilogy(s, [max(x, 1e-12) for x in v], color="k", lw=2, label="shipped scene")
    s, v = _series(t, "max_limit_violation_deg")
    a2.semilogy(s, [max(x, 1e-6) for x in v], color="k", lw=2, label="shipped scene")
    for col in t:
        if col.startswith("ke_"):
            tag = col[len("ke_"):]
            s, v = _series(t, col)
            a1.semilogy(s, [max(x, 1e-12) for x in v], lw=1, label=tag)
            s, v = _series(t, "limit_" + tag)
            a2.semilogy(s, [max(x, 1e-6) for x in v], lw=1, label=tag)
    a1.set_title("kinetic energy", fontsize=10)
    a1.set_ylabel("J")
    a2.set_title("largest joint-limit violation", fontsize=10)
    a2.set_ylabel("deg")
    for ax in (a1, a2):
        ax.set_xlabel("step")
        ax.grid(True, lw=0.3)
    a2.legend(fontsize=8, title="k = torsion_k, c = damping", title_fontsize=8)
    return physik_plot.save(fig, out_png)


def plot_sweep(csv_path, out_png):
    t = physik_plot.read_table(csv_path)
    labels = ["k=%g\nc=%g" % (k, c) for k, c in zip(t["torsion_k"], t["damping"])]
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(12, 4))
    for ax, key, title, unit in ((a1, "peak_kinetic_energy", "peak kinetic energy", "J"),
                                 (a2, "max_limit_violation_deg", "max joint-limit violation", "deg")):
        vals = [max(v, 1e-12) for v in t[key]]
        bars = ax.bar(range(len(vals)), vals, color=["tab:red" if e else "tab:blue"
                                                     for e in t["explodes"]])
        for b, e in zip(bars, t["explodes"]):
            if e:
                b.set_hatch("//")
        ax.set_yscale("log")
        ax.set_xticks(range(len(vals)))
        ax.set_xticklabels(labels, fontsize=8)
        ax.set_title(title + " (red: explodes)", fontsize=10)
        ax.set_ylabel(unit)
        ax.grid(True, axis="y", lw=0.3)
    return physik_plot.save(fig, out_png)


def plot_poses(folder, frames, steps, out_png):
    fig, axes = plt.subplots(2, len(frames), figsize=(2.8 * len(frames), 6), squeeze=False)
    for col, (f, s) in enumerate(zip(frames, steps)):
        bones = physik_plot.read_bones_csv(os.path.join(folder, f))
        for row, view in enumerate(("front", "side")):
            ax = axes[row][col]
            physik_plot.draw_pose(ax, bones, view, color="tab:purple")
            ax.set_title("step %d, %s" % (s, view), fontsize=9)
    fig.suptitle("tight hand, shipped scene", fontsize=10)
    return physik_plot.save(fig, out_png)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("folder", help="results/hand_explodes")
    args = ap.parse_args(argv)
    summary = json.load(open(os.path.join(args.folder, "summary.json")))
    print("  wrote", plot_timeline(os.path.join(args.folder, "timeline.csv"),
                                   os.path.join(args.folder, "hand_timeline.png")))
    print("  wrote", plot_sweep(os.path.join(args.folder, "sweep.csv"),
                                os.path.join(args.folder, "hand_sweep.png")))
    print("  wrote", plot_poses(args.folder, summary["frames"], summary["frame_steps"],
                                os.path.join(args.folder, "hand_poses.png")))


if __name__ == "__main__":
    main()
