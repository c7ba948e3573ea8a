#!/usr/bin/env python3
"""Linearisation study: median steps and bare steps per solve, per rig and variant (log scale)."""
import argparse
import collections
import os
import statistics
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import physik_plot as pp  # noqa: E402


def medians(cols):
    """{rig: {variant: (median steps, median bare steps)}} in the table's order."""
    runs = collections.OrderedDict()
    for k, rig in enumerate(cols.get("rig", [])):
        cell = runs.setdefault(rig, collections.OrderedDict()).setdefault(cols["variant"][k], ([], []))
        cell[0].append(cols["steps"][k])
        cell[1].append(cols["substeps"][k])
    if not runs:
        raise ValueError("runs.csv: no runs")
    return collections.OrderedDict(
        (rig, collections.OrderedDict((v, (statistics.median(s), statistics.median(b)))
                                      for v, (s, b) in cells.items()))
        for rig, cells in runs.items())


def plot(folder):
    table = medians(pp.read_table(os.path.join(folder, "runs.csv")))
    variants = list(collections.OrderedDict.fromkeys(v for cells in table.values() for v in cells))
    fig, axes = pp.plt.subplots(1, 2, figsize=(11, 3.8), sharey=True)
    width = 0.8 / len(variants)
    for ax, index, title in ((axes[0], 0, "steps of the rule"),
                             (axes[1], 1, "bare steps taken (the guard's rejected ones included)")):
        for j, v in enumerate(variants):
            xs = [i + (j - (len(variants) - 1) / 2) * width for i in range(len(table))]
            ys = [table[rig].get(v, (float("nan"),) * 2)[index] for rig in table]
            ax.bar(xs, ys, width, label=v)
        ax.set_xticks(range(len(table)))
        ax.set_xticklabels(list(table))
        ax.set_yscale("log")
        ax.set_title(title, fontsize=10)
    axes[0].set_ylabel("median per solve")
    axes[0].legend(fontsize=8)
    fig.suptitle("The solve mode with the shipped implicit step and with dense Newton steps")
    return pp.save(fig, os.path.join(folder, "linearisation.png"))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("folder", help="the experiment's output folder (runs.csv)")
    print("  wrote", plot(ap.parse_args(argv).folder))


if __name__ == "__main__":
    main()
