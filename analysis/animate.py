#!/usr/bin/env python3
"""Animated GIFs of run folders for REPORT.md (matplotlib, written by Pillow): what the HTML
viewer (viewer/viewer.js) plays, as a flat picture a markdown page can hold.

A run folder (physik/io/run_folder.h) gives scene.json (the rig: bone names, parents, radii),
trajectory.csv (every bone's head and tail per recorded step) and targets_and_limits.csv (the
control points' targets, each bone's joint-limit excess, rad). Each frame of the GIF:
  - every run's bones as thick segments, RADIUS_DRAWN of the bone's radius (at the full radius
    the rigs' 0.5-unit inertia radii merge into one blob in a small flat picture; the viewer
    draws them full), in the viewer's colours, bones past a joint limit by more than 0.1 deg
    in its highlight colour;
  - the control points' targets as crosses;
  - drawn far to near along the view direction (a painter's order, no lighting).
The runs share one timeline, the union of their recorded times; at time t each run shows its
last frame at or before t (as the viewer). `frames` instants are spread evenly over it.
Views: front (looking along +Y: x right, z up), side (looking along -X: y right, z up; pinhead
faces -Y, so it faces left), oblique (from front-right-above, the viewer's starting camera).

Run: python3 analysis/animate.py OUT.gif RUN_DIR [RUN_DIR ...] [--view V] [--frames N]
     [--title T] [--labels a,b]
     python3 analysis/animate.py --experiment results/fig7_cannon [--view V]
     (scripts/reproduce.sh: Figs 7, 10 and 11 -> <experiment>/animation.gif)
"""
import argparse
import csv
import json
import math
import os

import matplotlib

matplotlib.use(os.environ.get("MPLBACKEND", "Agg"))
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.animation import FuncAnimation, PillowWriter  # noqa: E402

PALETTE = ["#1f77b4", "#ff7f0e", "#2ca02c", "#9467bd", "#8c564b", "#17becf", "#7f7f7f",
           "#bcbd22"]  # viewer.js
PALETTE_NAMES = ["blue", "orange", "green", "purple", "brown", "cyan", "grey", "olive"]
HIGHLIGHT = "#e6194b"
LIMIT_SHOWN_RAD = math.radians(0.1)
RADIUS_DRAWN = 0.3
ALPHA = 0.85  # bones a little transparent, so an overlaid run shows through
# (screen right, screen up, toward the viewer) in world coordinates, each a right-handed frame
# (right x up = toward the viewer)
VIEWS = {"front": ((1, 0, 0), (0, 0, 1), (0, -1, 0)),
         "side": ((0, 1, 0), (0, 0, 1), (1, 0, 0))}


def _normalise(v):
    n = math.sqrt(sum(c * c for c in v))
    return tuple(c / n for c in v)


def _oblique():
    back = _normalise((0.35, -1.0, 0.3))  # from the target toward the camera, as viewer.js
    right = _normalise((-back[1], back[0], 0.0))  # horizontal, perpendicular to the view
    up = (back[1] * right[2] - back[2] * right[1], back[2] * right[0] - back[0] * right[2],
          back[0] * right[1] - back[1] * right[0])  # back x right
    return right, up, back


VIEWS["oblique"] = _oblique()


def _rows(path):
    with open(path, newline="") as f:
        reader = csv.reader(f)
        header = next(reader)
        return header, [[float(x) for x in row] for row in reader if row]


def read_run(folder):
    """A run folder as {label, bones, parents, radii, times, steps, heads, tails, targets,
    excess}: per frame lists of (x, y, z); excess per frame per bone (largest |axis|, rad) or
    None without targets_and_limits.csv."""
    with open(os.path.join(folder, "scene.json")) as f:
        scene = json.load(f)
    bones = scene["rig"]["bones"]
    default_r = scene["rig"].get("defaults", {}).get("radius", 0.5)
    run = {"label": os.path.basename(os.path.normpath(folder)), "bones": [b["name"] for b in bones],
           "radii": [b.get("radius", default_r) for b in bones]}
    header, rows = _rows(os.path.join(folder, "trajectory.csv"))
    if not rows:
        raise ValueError("%s: an empty trajectory" % folder)
    col = {name: k for k, name in enumerate(header)}

    def point(row, bone, end):
        return tuple(row[col["%s.%s_%s" % (bone, end, a)]] for a in "xyz")

    run["steps"] = [int(r[col["step"]]) for r in rows]
    run["times"] = [r[col["time"]] for r in rows]
    run["heads"] = [[point(r, b, "head") for b in run["bones"]] for r in rows]
    run["tails"] = [[point(r, b, "tail") for b in run["bones"]] for r in rows]
    _read_targets_limits(folder, run)
    return run


def _read_targets_limits(folder, run):
    path = os.path.join(folder, "targets_and_limits.csv")
    run["targets"], run["excess"] = [[] for _ in run["steps"]], None
    if not os.path.isfile(path):
        return
    header, rows = _rows(path)
    by_step = {int(r[0]): r for r in rows}
    ntarget = sum(1 for h in header if h.endswith(".target_x"))
    nbone = len(run["bones"])
    run["excess"] = []
    for k, step in enumerate(run["steps"]):
        r = by_step.get(step)
        if r is None:
            run["excess"].append([0.0] * nbone)
            continue
        run["targets"][k] = [tuple(r[1 + 3 * c:4 + 3 * c]) for c in range(ntarget)]
        base = 1 + 3 * ntarget
        run["excess"].append([max(abs(v) for v in r[base + 3 * b:base + 3 * b + 3])
                              for b in range(nbone)])


def timeline(runs, frames):
    """`frames` instants over the union of the runs' times, and each run's frame at each."""
    t0 = min(r["times"][0] for r in runs)
    t1 = max(r["times"][-1] for r in runs)
    n = max(1, frames)
    instants = [t0 + (t1 - t0) * k / max(1, n - 1) for k in range(n)]
    picks = []
    for r in runs:
        j, pick = 0, []
        for t in instants:
            while j + 1 < len(r["times"]) and r["times"][j + 1] <= t + 1e-9 * max(1, abs(t)):
                j += 1
            pick.append(j)
        picks.append(pick)
    return instants, picks


def _project(p, view):
    right, up, back = VIEWS[view]
    return (sum(a * b for a, b in zip(p, right)), sum(a * b for a, b in zip(p, up)),
            sum(a * b for a, b in zip(p, back)))


def _bounds(runs, view):
    xs, ys = [], []
    for r in runs:
        for f in range(len(r["steps"])):
            for k, p in enumerate(r["heads"][f] + r["tails"][f] + r["targets"][f]):
                x, y, _ = _project(p, view)
                pad = r["radii"][k % len(r["bones"])] if k < 2 * len(r["bones"]) else 0.0
                xs += [x - pad, x + pad]
                ys += [y - pad, y + pad]
    cx, cy = 0.5 * (min(xs) + max(xs)), 0.5 * (min(ys) + max(ys))
    half = 0.55 * max(max(xs) - min(xs), max(ys) - min(ys), 1e-9)
    return (cx - half, cx + half), (cy - half, cy + half)


def _segments(runs, picks, k, view):
    """Every bone of every run at instant k as (depth, (x0, x1), (y0, y1), radius, colour)."""
    out = []
    for i, r in enumerate(runs):
        f = picks[i][k]
        for b in range(len(r["bones"])):
            h, t = _project(r["heads"][f][b], view), _project(r["tails"][f][b], view)
            hot = r["excess"] is not None and r["excess"][f][b] > LIMIT_SHOWN_RAD
            colour = HIGHLIGHT if hot else PALETTE[i % len(PALETTE)]
            out.append((0.5 * (h[2] + t[2]), (h[0], t[0]), (h[1], t[1]), r["radii"][b], colour))
    out.sort(key=lambda s: s[0])  # far (most negative toward-viewer depth) first
    return out


def animate(folders, out, view="oblique", frames=60, title=None, labels=None, fps=12):
    """Writes the GIF; returns its path."""
    runs = [read_run(f) for f in folders]
    for r, label in zip(runs, labels or []):
        r["label"] = label
    instants, picks = timeline(runs, frames)
    fig, ax = plt.subplots(figsize=(5.0, 4.4), dpi=80)
    xlim, ylim = _bounds(runs, view)
    points_per_unit = 5.0 * 72 * 0.8 / (xlim[1] - xlim[0])  # the axes span ~80% of the width
    fig.subplots_adjust(left=0.1, right=0.9, bottom=0.04, top=0.84)

    def draw(k):
        ax.clear()
        ax.set_xlim(*xlim)
        ax.set_ylim(*ylim)
        ax.set_aspect("equal")
        ax.set_xticks([])
        ax.set_yticks([])
        for _, xs, ys, radius, colour in _segments(runs, picks, k, view):
            width = 2 * RADIUS_DRAWN * radius * points_per_unit
            ax.plot(xs, ys, color=colour, lw=max(1.0, width),
                    solid_capstyle="round", alpha=ALPHA)
        for i, r in enumerate(runs):
            for p in r["targets"][picks[i][k]]:
                x, y, _ = _project(p, view)
                ax.plot([x], [y], marker="x", ms=8, mew=2, color=PALETTE[i % len(PALETTE)])
        names = ", ".join("%s (%s)" % (r["label"], PALETTE_NAMES[i % len(PALETTE)])
                          for i, r in enumerate(runs))
        ax.set_title("%s\nt = %.2f s   %s\nred: past a joint limit; x: targets; bones at %d%% "
                     "of their radii" % (title or "", instants[k], names, 100 * RADIUS_DRAWN),
                     fontsize=8)

    anim = FuncAnimation(fig, draw, frames=len(instants))
    anim.save(out, writer=PillowWriter(fps=fps))
    plt.close(fig)
    return out


def animate_experiment(folder, view="oblique", frames=60):
    """<folder>/animation.gif of the runs an experiment left (<folder>/runs/order.txt, in its
    order), titled with its report's title."""
    with open(os.path.join(folder, "runs", "order.txt")) as f:
        runs = [os.path.join(folder, "runs", n.strip()) for n in f if n.strip()]
    title = os.path.basename(os.path.normpath(folder))
    summary = os.path.join(folder, "summary.json")
    if os.path.isfile(summary):
        with open(summary) as f:
            title = json.load(f).get("report", {}).get("title", title)
    return animate(runs, os.path.join(folder, "animation.gif"), view, frames, title)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("paths", nargs="+", metavar="OUT.gif RUN_DIR",
                    help="the GIF to write, then the run folders; with --experiment, its folder")
    ap.add_argument("--experiment", action="store_true",
                    help="one experiment's folder: its runs (runs/order.txt) into animation.gif")
    ap.add_argument("--view", choices=sorted(VIEWS), default="oblique")
    ap.add_argument("--frames", type=int, default=60)
    ap.add_argument("--title", default="")
    ap.add_argument("--labels", default="", help="comma-separated legend names")
    a = ap.parse_args(argv)
    if a.experiment:
        if len(a.paths) != 1:
            ap.error("--experiment takes one folder")
        print("wrote", animate_experiment(a.paths[0], a.view, a.frames))
        return
    if len(a.paths) < 2:
        ap.error("give the GIF to write and at least one run folder")
    labels = a.labels.split(",") if a.labels else None
    print("wrote", animate(a.paths[1:], a.paths[0], a.view, a.frames, a.title, labels))


if __name__ == "__main__":
    main()
