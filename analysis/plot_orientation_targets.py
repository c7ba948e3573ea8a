#!/usr/bin/env python3
"""Orientation targets: per rig, each solver's orientation error (rad, log scale) against its
position error (fraction of the reach), a marker per target, the success box (1e-3 of the reach,
1e-3 rad) dashed; and the secondary motion (mean off-chain tail displacement / reach) per solver."""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import physik_plot as pp  # noqa: E402

COLORS = {"physik": "tab:red", "physik-steps": "tab:purple", "physik-explicit": "tab:orange",
          "dls": "tab:blue", "kdl": "tab:green", "kdl-nr": "tab:olive"}
FLOOR = 1e-12  # log-scale floor for exact zeros


def plot(folder):
    t = pp.read_table(os.path.join(folder, "solves.csv"))
    rigs = list(dict.fromkeys(t["rig"]))
    solvers = list(dict.fromkeys(t["solver"]))
    fig, axes = pp.plt.subplots(2, len(rigs), figsize=(4.6 * len(rigs), 7.2), squeeze=False)
    for c, rig in enumerate(rigs):
        ax = axes[0][c]
        for s in solvers:
            idx = [i for i in range(len(t["rig"])) if t["rig"][i] == rig and t["solver"][i] == s]
            ax.scatter([max(t["position_error_reach"][i], FLOOR) for i in idx],
                       [max(t["orientation_error"][i], FLOOR) for i in idx],
                       s=18, color=COLORS.get(s, "k"), label=s)
        ax.axvline(1e-3, ls="--", color="0.5", lw=0.8)
        ax.axhline(1e-3, ls="--", color="0.5", lw=0.8)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("position error / reach")
        ax.set_ylabel("orientation error (rad)")
        ax.set_title("%s: final errors (dashed: success)" % rig, fontsize=9)
        ax.grid(True, lw=0.3)
        ax = axes[1][c]
        for k, s in enumerate(solvers):
            idx = [i for i in range(len(t["rig"])) if t["rig"][i] == rig and t["solver"][i] == s]
            ys = [t["secondary_motion"][i] / t["reach"][i] for i in idx]
            ax.scatter([k] * len(ys), ys, s=18, color=COLORS.get(s, "k"))
        ax.set_xticks(range(len(solvers)))
        ax.set_xticklabels(solvers, fontsize=8)
        ax.set_ylabel("secondary motion / reach")
        ax.set_title("%s: bones off the hand's chain" % rig, fontsize=9)
        ax.grid(True, lw=0.3)
    axes[0][0].legend(fontsize=8)
    fig.tight_layout()
    return [pp.save(fig, os.path.join(folder, "orientation_targets.png"))]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("folder")
    for p in plot(ap.parse_args(argv).folder):
        print("  wrote", p)


if __name__ == "__main__":
    main()
