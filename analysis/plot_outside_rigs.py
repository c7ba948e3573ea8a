#!/usr/bin/env python3
"""Outside rigs: the outcome of every run (MuJoCo's sample models, scenes that name no settings).

Reads runs.csv (experiments/outside_rigs.cpp: one row per rig x scene x configuration) and draws
  left   per configuration, how many runs converged, were still moving at the step cap, diverged
         or were refused
  right  one cell per run (rows: rig and its 1- or 2-point scene; columns: configuration),
         coloured by outcome, with the steps to converge written in the converged cells
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import physik_plot as pp  # noqa: E402

OUTCOMES = ["converged", "not_converged", "diverged", "refused"]
LABELS = {"converged": "converged", "not_converged": "still moving", "diverged": "diverged",
          "refused": "refused"}
COLOURS = {"converged": "tab:green", "not_converged": "tab:orange", "diverged": "tab:red",
           "refused": "0.6"}


def configurations(t):
    """The configurations in the order of their first row."""
    out = []
    for c in t["configuration"]:
        if c not in out:
            out.append(c)
    if not out:
        raise ValueError("runs.csv: no runs")
    return out


def outcome_counts(t):
    """{configuration: {outcome: runs}} for every configuration and outcome."""
    counts = {c: {o: 0 for o in OUTCOMES} for c in configurations(t)}
    for c, o in zip(t["configuration"], t["outcome"]):
        if o not in OUTCOMES:
            raise ValueError("runs.csv: unknown outcome %r" % o)
        counts[c][o] += 1
    return counts


def outcome_grid(t):
    """(scene labels, configurations, {(scene, configuration): (outcome, steps)})."""
    scenes, cells = [], {}
    for i, rig in enumerate(t["rig"]):
        scene = "%s, %d pt" % (rig, int(t["points"][i]))
        if scene not in scenes:
            scenes.append(scene)
        cells[(scene, t["configuration"][i])] = (t["outcome"][i], int(t["steps_to_converge"][i]))
    return scenes, configurations(t), cells


def draw_counts(ax, counts):
    names = list(counts)
    left = [0] * len(names)
    for o in OUTCOMES:
        n = [counts[c][o] for c in names]
        ax.barh(range(len(names)), n, left=left, color=COLOURS[o], label=LABELS[o])
        left = [a + b for a, b in zip(left, n)]
    ax.set_yticks(range(len(names)))
    ax.set_yticklabels(names, fontsize=8)
    ax.invert_yaxis()
    ax.set_xlabel("runs")
    ax.set_title("outcomes per configuration", fontsize=9)
    ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.1), ncol=2)
    ax.grid(True, axis="x", lw=0.3)


def draw_grid(ax, scenes, configs, cells):
    for r, scene in enumerate(scenes):
        for c, config in enumerate(configs):
            outcome, steps = cells.get((scene, config), ("refused", -1))
            ax.add_patch(pp.plt.Rectangle((c, r), 1, 1, color=COLOURS[outcome], ec="w"))
            if outcome == "converged":
                ax.text(c + 0.5, r + 0.5, str(steps), ha="center", va="center", fontsize=8)
    ax.set_xlim(0, len(configs))
    ax.set_ylim(len(scenes), 0)
    ax.set_xticks([c + 0.5 for c in range(len(configs))])
    ax.set_xticklabels(configs, fontsize=8, rotation=20, ha="right")
    ax.set_yticks([r + 0.5 for r in range(len(scenes))])
    ax.set_yticklabels(scenes, fontsize=8)
    ax.set_title("every run (numbers: steps to converge)", fontsize=9)


def plot(folder):
    t = pp.read_table(os.path.join(folder, "runs.csv"))
    scenes, configs, cells = outcome_grid(t)
    fig, (a, b) = pp.plt.subplots(1, 2, figsize=(11, 0.25 * len(scenes) + 2.5),
                                  gridspec_kw={"width_ratios": [1, 1.3]})
    draw_counts(a, outcome_counts(t))
    draw_grid(b, scenes, configs, cells)
    return pp.save(fig, os.path.join(folder, "outside_rigs.png"))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("folder")
    print("  wrote", plot(ap.parse_args(argv).folder))


if __name__ == "__main__":
    main()
