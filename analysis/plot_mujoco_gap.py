#!/usr/bin/env python3
"""PhysIK vs MuJoCo: the endpoint gap over time per scene and mode (Gauss-Seidel, and the exact
joint solve marked '(exact)'), and the final poses drawn side by side (PhysIK black, MuJoCo blue)."""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import physik_plot as pp  # noqa: E402


def plot(folder):
    t = pp.read_table(os.path.join(folder, "gap_over_time.csv"))
    keys = sorted(set(zip(t["scene"], t["mode"])))
    series = []
    for scene, mode in keys:
        idx = [i for i in range(len(t["step"])) if t["scene"][i] == scene and t["mode"][i] == mode]
        series.append(([t["step"][i] for i in idx], [max(t["gap"][i], 1e-16) for i in idx],
                       "%s %s" % (scene, mode)))
        ex = [i for i in idx if t.get("exact_gap") and t["exact_gap"][i] != ""]
        if ex:  # PhysIK's exact solve against the same MuJoCo run
            series.append(([t["step"][i] for i in ex], [max(t["exact_gap"][i], 1e-16) for i in ex],
                           "%s %s (exact)" % (scene, mode)))
    # Gauss-Seidel solid, exact dashed; the legend beside the axes (up to 16 series)
    fig, ax = pp.plt.subplots(figsize=(9.6, 4.2))
    for x, y, label in series:
        ax.plot(x, y, "--" if label.endswith("(exact)") else "-", label=label, lw=1.3)
    ax.set_yscale("log")
    ax.set_xlabel("step")
    ax.set_ylabel("largest endpoint gap (rig units)")
    ax.set_title("PhysIK vs MuJoCo: Gauss-Seidel (solid), exact solve (dashed)")
    ax.grid(True, lw=0.3)
    ax.legend(fontsize=7, loc="center left", bbox_to_anchor=(1.01, 0.5))
    fig.tight_layout()
    gap = pp.save(fig, os.path.join(folder, "mujoco_gap.png"))
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
