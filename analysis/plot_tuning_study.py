#!/usr/bin/env python3
"""Tuning study figure: steps to settle vs damping per rig variant (scale, density), the
divergence region shaded, the Ceres optimum, the closed-form rule and the paper's / original's
values marked. Reads results/tuning_study/{sweep.csv,summary.json}."""
import argparse
import json
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import physik_plot  # noqa: E402  (sets the Agg backend)
import matplotlib.pyplot as plt  # noqa: E402


def read_sweep(path):
    """{variant: [(damping, steps or None, diverged)]} in file order."""
    t = physik_plot.read_table(path)
    curves = {}
    for variant, c, steps, diverged in zip(t["variant"], t["damping"], t["steps_to_converge"],
                                          t["diverged"]):
        steps = int(steps)
        curves.setdefault(variant, []).append((c, steps if steps >= 0 else None, diverged == 1))
    if not curves:
        raise ValueError("%s: no rows" % path)
    return curves


def diverged_spans(pts):
    """The damping intervals to shade as diverged, from the data alone: one interval per run of
    consecutive diverged grid points (sorted by c), reaching halfway (in log c) to the grid
    neighbours that did not diverge, or to the grid's end. A settling point is never inside."""
    pts = sorted(pts)
    cs = [p[0] for p in pts]
    spans, k = [], 0
    while k < len(pts):
        if not pts[k][2]:
            k += 1
            continue
        j = k
        while j + 1 < len(pts) and pts[j + 1][2]:
            j += 1
        lo = cs[k] if k == 0 else math.sqrt(cs[k - 1] * cs[k])
        hi = cs[j] if j == len(pts) - 1 else math.sqrt(cs[j] * cs[j + 1])
        spans.append((lo, hi))
        k = j + 1
    return spans


def plot_tuning_study(sweep_csv, summary_json, out_png):
    curves = read_sweep(sweep_csv)
    rows = {r["variant"]: r for r in json.load(open(summary_json))["rows"]}
    n = len(curves)
    ncol = min(4, n)
    nrow = int(math.ceil(n / ncol))
    fig, axes = plt.subplots(nrow, ncol, figsize=(4.6 * ncol, 3.8 * nrow), squeeze=False)
    for ax, (name, pts) in zip(axes.flat, curves.items()):
        ok = [(c, s) for c, s, d in pts if s is not None and not d]
        top = max([s for _, s in ok] + [10]) * 1.5
        if ok:
            ax.plot([c for c, _ in ok], [s for _, s in ok], "o-", color="k", ms=3, label="steps to settle")
        for k, (lo, hi) in enumerate(diverged_spans(pts)):
            ax.axvspan(lo, hi, color="tab:red", alpha=0.12, label="diverges" if k == 0 else None)
        div = [c for c, _, d in pts if d]
        if div:
            ax.plot(div, [1.5] * len(div), "x", color="tab:red", ms=5)
        slow = [c for c, s, d in pts if s is None and not d]
        if slow:
            ax.plot(slow, [top] * len(slow), "v", color="tab:gray", ms=4, label="not settled")
        r = rows.get(name)
        if r:
            marks = [("c_tuned", "tab:blue", "-", "Ceres %.3g"), ("c_rule", "tab:green", "--", "rule %.3g")]
            for key, color, ls, fmt in marks:
                if r.get(key, -1) > 0:
                    ax.axvline(r[key], color=color, ls=ls, lw=1.2, label=fmt % r[key])
            if r.get("c_tuned", -1) > 0 and ok:
                # the optimum on the curve: the curve's value interpolated in log c
                c0 = r["c_tuned"]
                near = min(ok, key=lambda p: abs(math.log(p[0] / c0)))
                ax.plot([c0], [near[1]], "*", color="tab:blue", ms=12)
            for c, lab in ((20.0, "paper 20"), (3.0, "original 3")):
                ax.axvline(c, color="tab:orange" if c == 20 else "tab:purple", ls=":", lw=1, label=lab)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_ylim(1, top * 1.3)
        ax.set_title(name, fontsize=9)
        ax.set_xlabel("damping c (N s/m)")
        ax.set_ylabel("steps to settle")
        ax.grid(True, lw=0.3, which="both")
        ax.legend(fontsize=8, loc="upper left")
    for ax in list(axes.flat)[n:]:
        ax.axis("off")
    physik_plot.save(fig, out_png)
    plt.close(fig)
    return out_png


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("folder", help="results/tuning_study")
    args = ap.parse_args(argv)
    png = plot_tuning_study(os.path.join(args.folder, "sweep.csv"),
                            os.path.join(args.folder, "summary.json"),
                            os.path.join(args.folder, "tuning_study.png"))
    print("  wrote", png)


if __name__ == "__main__":
    main()
