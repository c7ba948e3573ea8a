#!/usr/bin/env python3
"""Scaling: microseconds per step against bones, log-log, one panel per rig kind (chain, binary
tree), a line per solve with its fitted exponent; the 0.5 us per bone target dashed."""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import physik_plot as pp  # noqa: E402

LABELS = {"gauss_seidel_paper": "Gauss-Seidel, eps 1e-3 (paper)",
          "gauss_seidel_tight": "Gauss-Seidel, eps 1e-9",
          "exact": "exact (articulated body)", "mj_step": "mj_step (MuJoCo)"}


def series(table, kind, method):
    """(bones, us per step) of the rows that ran."""
    pts = [(n, us) for k, n, m, s, us in zip(table["kind"], table["nbone"], table["method"],
                                             table["status"], table["us_per_step"])
           if k == kind and m == method and s == "ok" and us != ""]
    return [p[0] for p in pts], [p[1] for p in pts]


def plot(folder):
    table = pp.read_table(os.path.join(folder, "scaling.csv"))
    if not table["kind"]:
        raise ValueError("%s/scaling.csv has no rows" % folder)
    fits = {(f["kind"], f["method"]): f["exponent"] for f in pp.load_summary(folder)["exponents"]}
    kinds = [k for k in ("chain", "tree2") if k in table["kind"]]
    fig, axes = pp.plt.subplots(1, len(kinds), figsize=(5.5 * len(kinds), 4.2), squeeze=False)
    for ax, kind in zip(axes[0], kinds):
        for method, label in LABELS.items():
            n, us = series(table, kind, method)
            if not n:
                continue
            p = fits.get((kind, method))
            ax.loglog(n, us, marker="o", label=label + ("" if p is None else ", p = %.2f" % p))
        n_all = sorted(set(v for k, v in zip(table["kind"], table["nbone"]) if k == kind))
        ax.loglog(n_all, [0.5 * v for v in n_all], "k--", lw=1, label="0.5 us per bone")
        ax.set_xlabel("bones")
        ax.set_ylabel("microseconds per step (CPU)")
        ax.set_title("chain" if kind == "chain" else "balanced binary tree")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    return pp.save(fig, os.path.join(folder, "scaling.png"))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("folder")
    print("  wrote", plot(ap.parse_args(argv).folder))


if __name__ == "__main__":
    main()
