#!/usr/bin/env python3
"""PhysIK vs MuJoCo: the endpoint gap over time, a panel per scene (small multiples on one y
scale), a colour per reference mode, solid for the Gauss-Seidel scheme and dashed for the exact
one; and the final poses drawn side by side (PhysIK black, MuJoCo blue)."""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import physik_plot as pp  # noqa: E402


MODE_COLORS = {"same-forces": "tab:blue", "exact-constraints": "tab:orange"}


def gap_series(t):
    """{scene: [(mode, scheme, steps, gaps)]}: the Gauss-Seidel gap of every (scene, mode), and the
    exact scheme's where the CSV has it; gaps floored at 1e-16 for the log scale."""
    out = {}
    for scene, mode in sorted(set(zip(t["scene"], t["mode"]))):
        idx = [i for i in range(len(t["step"])) if t["scene"][i] == scene and t["mode"][i] == mode]
        lines = out.setdefault(scene, [])
        lines.append((mode, "gauss-seidel", [t["step"][i] for i in idx],
                      [max(t["gap"][i], 1e-16) for i in idx]))
        ex = [i for i in idx if t.get("exact_gap") and t["exact_gap"][i] != ""]
        if ex:  # the exact scheme against the same MuJoCo run
            lines.append((mode, "exact", [t["step"][i] for i in ex],
                          [max(t["exact_gap"][i], 1e-16) for i in ex]))
    return out


def plot_gaps(folder):
    series = gap_series(pp.read_table(os.path.join(folder, "gap_over_time.csv")))
    ncol = min(len(series), 4)
    nrow = (len(series) + ncol - 1) // ncol
    fig, axes = pp.plt.subplots(nrow, ncol, figsize=(3.6 * ncol, 3.4 * nrow + 0.9), sharey=True,
                                squeeze=False)
    for ax, (scene, lines) in zip(axes.flat, series.items()):
        for mode, scheme, x, y in lines:
            ax.plot(x, y, "--" if scheme == "exact" else "-", color=MODE_COLORS.get(mode, "k"),
                    lw=1.4, label="%s, %s" % (mode, scheme))
        ax.set_yscale("log")
        ax.set_title(scene, fontsize=9)
        ax.set_xlabel("step")
        ax.grid(True, lw=0.3)
    for ax in list(axes.flat)[len(series):]:
        ax.axis("off")
    axes[0][0].set_ylabel("largest endpoint gap (rig units)")
    handles, labels = axes[0][0].get_legend_handles_labels()
    fig.legend(handles, labels, fontsize=8, loc="lower center", ncol=4, frameon=False)
    fig.suptitle("PhysIK vs MuJoCo: colour = reference mode; solid = Gauss-Seidel, dashed = exact")
    fig.tight_layout(rect=(0, 0.11, 1, 1))
    return pp.save(fig, os.path.join(folder, "mujoco_gap.png"))


def plot(folder):
    gap = plot_gaps(folder)
    s = pp.load_summary(folder)
    panels = []
    for row in s["rows"]:
        panels.append({"bones": pp.read_bones_csv(os.path.join(folder, row["physik_csv"])),
                       "label": "PhysIK", "title": "%s\n%s" % (row["scene"], row["mode"]),
                       "overlay": [{"bones": pp.read_bones_csv(os.path.join(folder, row["mujoco_csv"])),
                                    "color": "tab:blue", "label": "MuJoCo"}]})
    poses = pp.pose_panels(panels, os.path.join(folder, "mujoco_poses.png"), views=("front", "side"),
                           size=2.8, suptitle="final poses: PhysIK (black) and MuJoCo (blue)")
    return gap, poses


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("folder")
    for p in plot(ap.parse_args(argv).folder):
        print("  wrote", p)


if __name__ == "__main__":
    main()
