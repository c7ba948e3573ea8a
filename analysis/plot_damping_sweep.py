#!/usr/bin/env python3
"""Damping sensitivity: steps to converge against damping; diverged runs marked at the top."""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import physik_plot as pp  # noqa: E402


def plot(folder):
    t = pp.read_table(os.path.join(folder, "sweep.csv"))
    fig, ax = pp.plt.subplots(figsize=(6.4, 4.2))
    top = max([s for s in t["steps_run"]] + [1])
    for k, scene in enumerate(sorted(set(t["scene"]))):
        idx = [i for i, s in enumerate(t["scene"]) if s == scene]
        ok = [i for i in idx if t["converged"][i] == 1]
        bad = [i for i in idx if t["diverged"][i] == 1]
        line, = ax.plot([t["damping"][i] for i in ok], [t["steps_to_converge"][i] for i in ok], "o-",
                        label=scene)
        ax.plot([t["damping"][i] for i in bad], [top * 1.1] * len(bad), "x", color=line.get_color(), ms=8)
    ax.axvline(20, color="k", ls="--", lw=1)
    ax.text(20, top * 1.15, "paper c = 20", fontsize=8, ha="center")
    ax.set_xscale("log")
    ax.set_xlabel("damping c (N s/m at each bone end)")
    ax.set_ylabel("steps to converge (x = diverged)")
    ax.grid(True, lw=0.3)
    ax.legend(fontsize=8)
    return pp.save(fig, os.path.join(folder, "damping_sweep.png"))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("folder")
    print("  wrote", plot(ap.parse_args(argv).folder))


if __name__ == "__main__":
    main()
