#!/usr/bin/env python3
"""The equilibrium solve against simulate and Ceres, from results/equilibrium_solve: per shipped
scene, how far simulate's rest pose lies from the equilibrium solve's (over the rig's height, log
scale; a marker where simulate meets its goals and the equilibrium solve does not), and per case
with a unique minimum the distance of the solve's pose from Ceres' (the 1e-6 target dashed)."""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import physik_plot as pp  # noqa: E402

FLOOR = 1e-16  # log-scale floor for exact zeros


def plot(folder):
    scenes = pp.read_table(os.path.join(folder, "scenes.csv"))
    ceres = pp.read_table(os.path.join(folder, "ceres.csv"))
    fig, axes = pp.plt.subplots(1, 2, figsize=(12, 4.2))
    ax = axes[0]
    names = scenes["scene"]
    ax.bar(range(len(names)), [max(d, FLOOR) for d in scenes["distance"]], color="tab:blue")
    for i, (meets, code) in enumerate(zip(scenes["simulate_meets"], scenes["equilibrium_exit"])):
        if meets and code == 4:
            ax.plot([i], [max(scenes["distance"][i], FLOOR)], "rx", ms=10)
    ax.set_xticks(range(len(names)))
    ax.set_xticklabels(names, rotation=60, ha="right", fontsize=7)
    ax.set_yscale("log")
    ax.set_ylabel("simulate's rest pose from the equilibrium's / height")
    ax.set_title("shipped scenes (x: simulate meets its goals, the solve exits 4)", fontsize=9)
    ax.grid(True, axis="y", lw=0.3)
    ax = axes[1]
    cases = ceres["case"]
    ax.bar(range(len(cases)), [max(d, FLOOR) for d in ceres["distance"]], color="tab:red")
    ax.axhline(1e-6, ls="--", color="0.5", lw=0.8)
    ax.set_xticks(range(len(cases)))
    ax.set_xticklabels(cases, rotation=30, ha="right", fontsize=7)
    ax.set_yscale("log")
    ax.set_ylabel("the solve's pose from Ceres' / height")
    ax.set_title("unique minima: against Ceres (dashed: 1e-6)", fontsize=9)
    ax.grid(True, axis="y", lw=0.3)
    fig.tight_layout()
    return [pp.save(fig, os.path.join(folder, "equilibrium_solve.png"))]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("folder")
    for p in plot(ap.parse_args(argv).folder):
        print("  wrote", p)


if __name__ == "__main__":
    main()
