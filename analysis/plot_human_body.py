#!/usr/bin/env python3
"""A human body inside a human skeleton: the four skeletons' masses and widths.

Reads human_body_masses.csv and human_body_shapes.csv (experiments/human_body.cpp) and draws
  human_body_masses.png  each de Leva row's share of the body's mass: the table's (de Leva 1996)
                         beside each skeleton's rig
  human_body_widths.png  the hip width, the shoulder girdle's base and the shoulder width: their
                         largest change through the solve (feet pinned, head look-at) and the
                         follow under gravity, per skeleton (log scale; a change of 0 is drawn at
                         1e-16 m)
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import physik_plot as pp  # noqa: E402

FLOOR = 1e-16  # m, where a change of exactly 0 is drawn on the log axis


def rows_in_order(t):
    """The de Leva rows in the order of their first appearance."""
    out = []
    for r in t["row"]:
        if r not in out:
            out.append(r)
    if not out:
        raise ValueError("human_body_masses.csv: no rows")
    return out


def plot_masses(t, png):
    rows = rows_in_order(t)
    shapes = []
    for s in t["shape"]:
        if s not in shapes:
            shapes.append(s)
    width = 0.8 / (len(shapes) + 1)
    fig, ax = pp.plt.subplots(figsize=(11, 4.5))
    table = {r: s for r, s in zip(t["row"], t["table_share"])}
    xs = range(len(rows))
    ax.bar([x for x in xs], [100 * table[r] for r in rows], width, label="de Leva 1996", color="0.3")
    for k, shape in enumerate(shapes):
        share = {r: s for sh, r, s in zip(t["shape"], t["row"], t["rig_share"]) if sh == shape}
        ax.bar([x + (k + 1) * width for x in xs], [100 * share.get(r, 0.0) for r in rows], width,
               label=shape)
    ax.set_xticks([x + 0.4 for x in xs])
    ax.set_xticklabels(rows, rotation=45, ha="right", fontsize=8)
    ax.set_ylabel("share of the body's mass (%)")
    ax.set_title("Masses: the table's shares and the rigs'")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(png, dpi=110)
    pp.plt.close(fig)
    return png


def plot_widths(t, png):
    measures = [("hip_change_solve", "hips, solve"), ("hip_change_follow", "hips, follow"),
                ("girdle_change_solve", "girdle base, solve"),
                ("girdle_change_follow", "girdle base, follow"),
                ("shoulder_change_solve", "shoulders, solve"),
                ("shoulder_change_follow", "shoulders, follow")]
    shapes = list(t["shape"])
    width = 0.8 / len(measures)
    fig, ax = pp.plt.subplots(figsize=(10, 4.5))
    for k, (column, label) in enumerate(measures):
        values = [max(FLOOR, abs(v)) if v == v else FLOOR for v in t[column]]
        ax.bar([i + k * width for i in range(len(shapes))], values, width, label=label)
    ax.axhline(1e-6, color="k", lw=0.8, ls="--", label="1e-6 m (the claim)")
    ax.set_yscale("log")
    ax.set_xticks([i + 0.4 for i in range(len(shapes))])
    ax.set_xticklabels(shapes)
    ax.set_ylabel("largest change of the width (m)")
    ax.set_title("Widths through a solve and a follow under gravity")
    ax.legend(fontsize=7, ncol=2)
    fig.tight_layout()
    fig.savefig(png, dpi=110)
    pp.plt.close(fig)
    return png


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("folder", help="results/human_body (holds summary.json and its CSV tables)")
    args = ap.parse_args(argv)
    masses = pp.read_table(os.path.join(args.folder, "human_body_masses.csv"))
    shapes = pp.read_table(os.path.join(args.folder, "human_body_shapes.csv"))
    print("  wrote", plot_masses(masses, os.path.join(args.folder, "human_body_masses.png")))
    print("  wrote", plot_widths(shapes, os.path.join(args.folder, "human_body_widths.png")))


if __name__ == "__main__":
    main()
