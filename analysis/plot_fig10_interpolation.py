#!/usr/bin/env python3
"""Paper Fig 10: polar-about-COM vs linear target interpolation (results/fig10_interpolation).

fig10_frames.png            the frames of each scheme (rows: polar-com, linear; columns: steps
                            0, 12, 25, 37, 50, last) in the front view, with the moved hand's tip
                            path and effective-target path up to that step
fig10_secondary_motion.png  off-arm and off-chain rotation per step for both schemes, the
                            interpolation window shaded
"""
import argparse
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import physik_plot  # noqa: E402
from physik_plot import plt  # noqa: E402


SCHEMES = [("polar_com", "polar", "polar about the COM", "tab:blue"),
           ("linear", "linear", "linear", "tab:red")]


def plot_frames(folder, summary, out_png, view="front"):
    """Rows = schemes, columns = the saved frames of each."""
    ncol = max(len(summary[key]["frames"]) for key, _, _, _ in SCHEMES)
    table = physik_plot.read_table(os.path.join(folder, "secondary_motion.csv"))
    i, j = {"front": (0, 2), "side": (1, 2)}[view]
    axis_names = "xyz"
    fig, axes = plt.subplots(2, ncol, figsize=(2.6 * ncol, 6.2), squeeze=False)
    drawn, used = [], []
    for row, (key, prefix, label, color) in enumerate(SCHEMES):
        frames = summary[key]["frames"]
        steps = summary[key]["frame_steps"]
        for col in range(ncol):
            ax = axes[row][col]
            if col >= len(frames):
                ax.axis("off")
                continue
            bones = physik_plot.read_bones_csv(os.path.join(folder, frames[col]))
            physik_plot.draw_pose(ax, bones, view, color=color)
            drawn.append(bones)
            used.append(ax)
            upto = [k for k, s in enumerate(table["step"]) if s <= steps[col]]
            if upto:
                ax.plot([table["%s_target_%s" % (prefix, axis_names[i])][k] for k in upto],
                        [table["%s_target_%s" % (prefix, axis_names[j])][k] for k in upto],
                        ":", color="tab:red", lw=1.2)
                ax.plot([table["%s_tip_%s" % (prefix, axis_names[i])][k] for k in upto],
                        [table["%s_tip_%s" % (prefix, axis_names[j])][k] for k in upto],
                        "-", color="0.4", lw=0.8)
            ax.set_title("%s, step %d" % (prefix, steps[col]), fontsize=9)
    physik_plot.same_limits(used, drawn, view)
    fig.suptitle("Fig 10: raised hand, %s view (dotted red: effective target path, grey: hand tip "
                 "path)" % view, fontsize=10)
    return physik_plot.save(fig, out_png)


def plot_secondary_motion(csv_path, out_png, interpolation_steps=50):
    """Secondary motion against the initial pose, per step, both schemes."""
    t = physik_plot.read_table(csv_path)
    fig, axes = plt.subplots(1, 3, figsize=(14, 4))
    for _, prefix, label, color in SCHEMES:
        axes[0].plot(t["step"], t[prefix + "_off_arm_rad"], color=color, label=label)
        axes[1].plot(t["step"], t[prefix + "_off_chain_rad"], color=color, label=label)
        axes[2].semilogy(t["step"], [max(v, 1e-12) for v in t[prefix + "_kinetic_energy"]],
                         color=color, label=label)
    titles = ["rotation off the raised arm's chain", "rotation off all controlled chains",
              "kinetic energy"]
    for ax, title, unit in zip(axes, titles, ["rad", "rad", "J"]):
        ax.axvspan(0, interpolation_steps, color="0.9", zorder=0)
        ax.set_title(title, fontsize=10)
        ax.set_xlabel("step")
        ax.set_ylabel(unit)
        ax.grid(True, lw=0.3)
    axes[0].legend(fontsize=8)
    fig.suptitle("Fig 10: secondary motion (shaded: target interpolation, %d steps)"
                 % interpolation_steps, fontsize=10)
    return physik_plot.save(fig, out_png)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("folder", help="results/fig10_interpolation")
    args = ap.parse_args(argv)
    summary = json.load(open(os.path.join(args.folder, "summary.json")))
    print("  wrote", plot_frames(args.folder, summary, os.path.join(args.folder, "fig10_frames.png")))
    print("  wrote", plot_secondary_motion(os.path.join(args.folder, "secondary_motion.csv"),
                                           os.path.join(args.folder, "fig10_secondary_motion.png"),
                                           summary.get("interpolation_steps", 50)))


if __name__ == "__main__":
    main()
