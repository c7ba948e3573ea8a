#!/usr/bin/env python3
"""Beyond the paper: the (dt, c) stability map, explicit vs implicit; steps to converge against
damping (damping insensitivity); distance to the Ceres equilibrium per step at large dt."""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import physik_plot as pp  # noqa: E402

COLORS = {"settled": "tab:green", "neither": "tab:orange", "diverged": "tab:red"}


def stability_panel(ax, t, scheme):
    idx = [i for i, s in enumerate(t["scheme"]) if s == scheme]
    for outcome, color in COLORS.items():
        sel = [i for i in idx if t["outcome"][i] == outcome]
        ax.scatter([t["dt"][i] for i in sel], [t["damping"][i] for i in sel], c=color, s=60, marker="s",
                   label="%s (%d)" % (outcome, len(sel)))
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("dt (s)")
    ax.set_ylabel("damping c (N s/m)")
    ax.set_title("%s: pinhead_two_hands" % scheme, fontsize=9)
    ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.13), ncol=3, frameon=False)


def insensitivity_panel(ax, t):
    top = max(t["steps_run"] + [1])
    for scene in sorted(set(t["scene"])):
        for scheme, style in (("explicit", "--"), ("implicit", "-")):
            idx = [i for i, (s, m) in enumerate(zip(t["scene"], t["scheme"])) if s == scene and m == scheme]
            ok = [i for i in idx if t["converged"][i] == 1]
            bad = [i for i in idx if t["diverged"][i] == 1]
            line, = ax.plot([t["damping"][i] for i in ok], [t["steps_to_converge"][i] for i in ok], "o" + style,
                            ms=3, label="%s %s" % (scene, scheme))
            ax.plot([t["damping"][i] for i in bad], [top * 1.5] * len(bad), "x", color=line.get_color(), ms=7)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("damping c (N s/m)")
    ax.set_ylabel("steps to converge (x = diverged)")
    ax.set_title("damping insensitivity, dt = 0.05", fontsize=9)
    ax.legend(fontsize=8)


def large_steps_panel(ax, t):
    # the preset's runs, one line per (torsion torque, dt): the paper's torque solid, the gradient dashed
    torques = t["torsion_torque"]
    for torque in sorted(set(torques)):
        for k, dt in enumerate(sorted(set(t["dt"]))):
            idx = [i for i, d in enumerate(t["dt"]) if d == dt and torques[i] == torque]
            if not idx:
                continue
            ax.plot([t["step"][i] for i in idx], [max(t["distance_to_equilibrium"][i], 1e-16) for i in idx],
                    color="C%d" % k, ls="--" if torque == "gradient" else "-",
                    label="dt = %g, %s torque" % (dt, torque))
    ax.axhline(1e-8, color="k", lw=0.8, ls=":")
    ax.set_yscale("log")
    ax.set_xscale("log")
    ax.set_xlabel("step")
    ax.set_ylabel("distance to the Ceres equilibrium")
    ax.set_title("large steps are the static solve (elbow)", fontsize=9)
    ax.legend(fontsize=8, ncol=2)


def plot(folder):
    fig, axes = pp.plt.subplots(2, 2, figsize=(12, 9.5))
    smap = pp.read_table(os.path.join(folder, "stability_map.csv"))
    stability_panel(axes[0][0], smap, "explicit")
    stability_panel(axes[0][1], smap, "implicit")
    insensitivity_panel(axes[1][0], pp.read_table(os.path.join(folder, "insensitivity.csv")))
    large_steps_panel(axes[1][1], pp.read_table(os.path.join(folder, "large_steps.csv")))
    for ax in axes.flat:
        ax.grid(True, lw=0.3)
    fig.tight_layout()
    return pp.save(fig, os.path.join(folder, "beyond_the_paper.png"))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("folder")
    print("  wrote", plot(ap.parse_args(argv).folder))


if __name__ == "__main__":
    main()
