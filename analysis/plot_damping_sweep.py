#!/usr/bin/env python3
"""Damping sensitivity: steps to converge against damping, one colour and marker per scene; above
it, a strip with a row per scene for the runs that did not converge: hollow where the run ended
without converging (it ran out of steps), a cross where it diverged. Reads
results/damping_sweep/sweep.csv."""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import physik_plot as pp  # noqa: E402

STYLES = [("tab:blue", "o"), ("tab:orange", "s"), ("tab:green", "^"), ("tab:red", "D"),
          ("tab:purple", "v"), ("tab:brown", "P")]


def outcomes(t):
    """{scene: {"converged": [(c, steps)], "not_converged": [c], "diverged": [c]}} from the CSV's
    columns: every run lands in exactly one list."""
    out = {}
    for i, scene in enumerate(t["scene"]):
        o = out.setdefault(scene, {"converged": [], "not_converged": [], "diverged": []})
        c = t["damping"][i]
        if t["diverged"][i] == 1:
            o["diverged"].append(c)
        elif t["converged"][i] == 1:
            o["converged"].append((c, t["steps_to_converge"][i]))
        else:
            o["not_converged"].append(c)
    return out


def plot(folder):
    t = pp.read_table(os.path.join(folder, "sweep.csv"))
    runs = outcomes(t)
    fig, (strip, ax) = pp.plt.subplots(2, 1, figsize=(7.0, 5.4), sharex=True,
                                       gridspec_kw={"height_ratios": [1, 3]})
    for k, scene in enumerate(sorted(runs)):
        color, marker = STYLES[k % len(STYLES)]
        o = runs[scene]
        ax.plot([c for c, _ in o["converged"]], [s for _, s in o["converged"]], "-", marker=marker,
                color=color, ms=6, label=scene)
        strip.plot(o["not_converged"], [k] * len(o["not_converged"]), marker, color=color, ms=7,
                   mfc="none", mew=1.5)
        strip.plot(o["diverged"], [k] * len(o["diverged"]), "x", color=color, ms=8, mew=2)
    strip.set_yticks(range(len(runs)))
    strip.set_yticklabels(sorted(runs), fontsize=8)
    strip.set_ylim(-0.6, len(runs) - 0.4)
    strip.set_title("runs that did not converge: hollow = out of steps, x = diverged", fontsize=9)
    for a in (strip, ax):
        a.axvline(20, color="k", ls="--", lw=1)
        a.grid(True, lw=0.3)
    ax.text(20, ax.get_ylim()[1], " paper c = 20", fontsize=8, va="top")
    ax.set_xscale("log")
    ax.set_xlabel("damping c (N s/m at each bone end)")
    ax.set_ylabel("steps to converge")
    ax.legend(fontsize=8)
    return pp.save(fig, os.path.join(folder, "damping_sweep.png"))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("folder")
    print("  wrote", plot(ap.parse_args(argv).folder))


if __name__ == "__main__":
    main()
