#!/usr/bin/env python3
"""Draw the IK comparison from results/ik_comparison/summary.json: success rate, time
per solve and continuity per rig and solver, and write the table as ik_comparison_table.md."""
import argparse
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import physik_plot  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402

COLUMNS = [("success_rate", "success", lambda v: "%.1f%%" % (100 * v)),
           ("median_residual_over_reach", "median residual/reach", lambda v: "%.2g" % v),
           ("median_iterations", "median iters", lambda v: "%.0f" % v),
           ("mean_time_ms", "ms/solve", lambda v: "%.3g" % v),
           ("max_limit_violation_deg", "max viol (deg)", lambda v: "%.2g" % v),
           ("mean_total_rotation_rad", "total rot (rad)", lambda v: "%.3g" % v),
           ("mean_offpath_motion", "off-path motion", lambda v: "%.3g" % v),
           ("mean_offpath_rotation_rad", "off-path rot (rad)", lambda v: "%.3g" % v),
           ("unreachable_not_converged", "unreach: not conv", lambda v: "%.0f%%" % (100 * v)),
           ("unreachable_excess_over_reach", "unreach: excess/reach", lambda v: "%.2g" % v),
           ("continuity_median_ratio", "jump median", lambda v: "%.3g" % v),
           ("continuity_p95_ratio", "jump p95", lambda v: "%.3g" % v)]


def table_markdown(rows):
    head = ["rig", "solver", "n"] + [c[1] for c in COLUMNS]
    out = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for r in rows:
        cells = [r["rig"], r["solver"], "%d+%d" % (r["reachable"], r["unreachable"])]
        for key, _, f in COLUMNS:
            v = r.get(key)
            cells.append("n/a" if v is None or v != v else f(v))
        out.append("| " + " | ".join(cells) + " |")
    return "\n".join(out) + "\n"


def grouped_bars(rows, key, ylabel, path, log=False):
    """One group of bars per rig, one bar per solver."""
    if not rows:
        raise ValueError("no rows to plot")
    rigs = list(dict.fromkeys(r["rig"] for r in rows))
    solvers = list(dict.fromkeys(r["solver"] for r in rows))
    fig, ax = plt.subplots(figsize=(12, 4))
    width = 0.8 / len(solvers)
    for k, s in enumerate(solvers):
        xs, ys = [], []
        for i, rig in enumerate(rigs):
            for r in rows:
                if r["rig"] == rig and r["solver"] == s and r.get(key) is not None:
                    xs.append(i + (k - (len(solvers) - 1) / 2) * width)
                    ys.append(max(r[key], 1e-6) if log else r[key])
        ax.bar(xs, ys, width, label=s, color=plt.cm.tab20(k % 20))
    ax.set_xticks(range(len(rigs)))
    ax.set_xticklabels(rigs)
    ax.set_ylabel(ylabel)
    if log:
        ax.set_yscale("log")
    ax.legend(fontsize=8, ncol=4)
    ax.grid(True, axis="y", lw=0.3)
    physik_plot.save(fig, path)
    plt.close(fig)
    return path


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("folder", help="results/ik_comparison (holds summary.json)")
    args = ap.parse_args(argv)
    summary = json.load(open(os.path.join(args.folder, "summary.json")))
    rows = summary["table"]
    out = []
    out.append(grouped_bars(rows, "success_rate", "success rate (residual < 1e-3 reach)",
                            os.path.join(args.folder, "ik_success.png")))
    out.append(grouped_bars(rows, "mean_time_ms", "mean time per solve (ms)",
                            os.path.join(args.folder, "ik_time.png"), log=True))
    out.append(grouped_bars(rows, "continuity_p95_ratio",
                            "p95 pose jump / target move", os.path.join(args.folder, "ik_continuity.png"),
                            log=True))
    with open(os.path.join(args.folder, "ik_comparison_table.md"), "w") as f:
        f.write(table_markdown(rows))
    for p in out:
        print("  wrote", p)


if __name__ == "__main__":
    main()
