#!/usr/bin/env python3
"""Paper Fig 9: PhysIK vs Blender's iTaSC and damped least squares on the outstretched hand
(results/fig9_outstretched).

fig9_poses.png     the final poses present (PhysIK, DLS, Blender's iTaSC when the experiment found
                   Blender, MuJoCo with PhysIK's forces) in front and side views, the rest pose faint
                   behind, control-point targets as red crosses
fig9_measures.png  the secondary-motion measures of measures.csv as grouped bars, one per method
"""
import argparse
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import physik_plot  # noqa: E402
from physik_plot import plt  # noqa: E402

POSES = [("physik_final.csv", "PhysIK", "tab:blue"),
         ("dls_final.csv", "damped least squares", "tab:orange"),
         ("itasc_final.csv", "Blender iTaSC", "tab:purple"),
         ("mujoco_final.csv", "MuJoCo, same forces", "tab:green")]
COLORS = {"physik": "tab:blue", "dls": "tab:orange", "itasc": "tab:purple",
          "mujoco_same_forces": "tab:green"}

ANGLES = [("shoulder_turn_deg", "shoulder turn\n(+ = right sh. fwd)"),
          ("lean_forward_deg", "forward lean"),
          ("lean_side_deg", "sideways lean"),
          ("head_tilt_deg", "head tilt"),
          ("neck_bend_deg", "neck bend")]
ROTATIONS = [("off_reach_rotation_rad", "off reaching\narm's chain"),
             ("off_chain_rotation_rad", "off all\ncontrolled chains")]


def poses_present(folder):
    """The (file, label, colour) of POSES whose file the experiment wrote."""
    return [p for p in POSES if os.path.isfile(os.path.join(folder, p[0]))]


def plot_poses(folder, out_png, targets=None):
    """One column per method present (PhysIK, DLS, iTaSC, MuJoCo), front and side rows."""
    rest = physik_plot.read_bones_csv(os.path.join(folder, "rest.csv"))
    present = poses_present(folder)
    fig, axes = plt.subplots(2, len(present), figsize=(4 * len(present), 8), squeeze=False)
    for col, (name, label, color) in enumerate(present):
        bones = physik_plot.read_bones_csv(os.path.join(folder, name))
        for row, view in enumerate(("front", "side")):
            ax = axes[row][col]
            physik_plot.draw_pose(ax, rest, view, color="0.75", label="rest")
            physik_plot.draw_pose(ax, bones, view, color=color, label=label, targets=targets)
            ax.set_title("%s, %s view" % (label, view), fontsize=10)
            if row == 0 and col == 0:
                ax.legend(loc="lower left", fontsize=8)
    fig.suptitle("Fig 9: outstretched hand (3 control points)")
    return physik_plot.save(fig, out_png)


def plot_measures(measures_csv, out_png):
    """Angles (deg) and summed off-chain rotations (rad) per method, as grouped bars."""
    t = physik_plot.read_table(measures_csv)
    methods = t["method"]
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4.2), gridspec_kw={"width_ratios": [5, 2]})
    for ax, group, unit in ((a1, ANGLES, "deg"), (a2, ROTATIONS, "rad")):
        width = 0.8 / max(len(methods), 1)
        for m, method in enumerate(methods):
            xs = [g + (m - (len(methods) - 1) / 2) * width for g in range(len(group))]
            ax.bar(xs, [t[key][m] for key, _ in group], width, label=method,
                   color=COLORS.get(method, None))
        ax.set_xticks(range(len(group)))
        ax.set_xticklabels([lab for _, lab in group], fontsize=8)
        ax.set_ylabel(unit)
        ax.axhline(0, color="k", lw=0.5)
        ax.grid(True, axis="y", lw=0.3)
    a1.set_title("pose changes against rest")
    a2.set_title("summed bone rotation")
    a1.legend(fontsize=8)
    return physik_plot.save(fig, out_png)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("folder", help="results/fig9_outstretched")
    args = ap.parse_args(argv)
    targets = None
    summary_path = os.path.join(args.folder, "summary.json")
    if os.path.isfile(summary_path):
        targets = json.load(open(summary_path)).get("targets")
    print("  wrote", plot_poses(args.folder, os.path.join(args.folder, "fig9_poses.png"), targets))
    print("  wrote", plot_measures(os.path.join(args.folder, "measures.csv"),
                                   os.path.join(args.folder, "fig9_measures.png")))


if __name__ == "__main__":
    main()
