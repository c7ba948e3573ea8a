#!/usr/bin/env python3
"""Clip following: the toes' heights and the followed points' distance to the clip, per run."""
import argparse
import collections
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import physik_plot as pp  # noqa: E402


def plot(folder):
    cols = pp.read_table(os.path.join(folder, "frames.csv"))
    with open(os.path.join(folder, "summary.json")) as f:
        floor = 100.0 * json.load(f)["report"]["settings"]["floor_height"]
    series = collections.OrderedDict()
    for k, name in enumerate(cols["run"]):
        s = series.setdefault(name, ([], [], [], [], []))
        s[0].append(cols["time"][k])
        s[1].append(cols["left_toe_z"][k])
        s[2].append(cols["right_toe_z"][k])
        s[3].append(cols["distance"][k])
        s[4].append(cols["left_planted"][k])
    fig, (a, b) = pp.plt.subplots(1, 2, figsize=(11, 3.8))
    for name, (t, lz, rz, dist, planted) in series.items():
        style = "k-" if name == "clip" else "-"
        a.plot(t, lz, style, label=name + " left toe", lw=1)
        if name != "clip":
            b.plot(t, dist, label=name, lw=1)
    clip_t, _, _, _, planted = series["clip"]
    for t, p in zip(clip_t, planted):
        if p:
            a.axvspan(t - 1 / 60, t + 1 / 60, color="0.9", lw=0)
    a.axhline(floor, color="brown", lw=1, label="floor")
    a.set_xlabel("time (s); grey: the clip's left foot planted")
    a.set_ylabel("toe height (cm)")
    a.legend(fontsize=8)
    b.set_xlabel("time (s)")
    b.set_ylabel("followed points' mean distance to the clip (cm)")
    b.legend(fontsize=8)
    fig.suptitle("A walk clip followed by PhysIK under gravity, with and without a floor")
    return pp.save(fig, os.path.join(folder, "clip_following.png"))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("folder")
    print("  wrote", plot(ap.parse_args(argv).folder))


if __name__ == "__main__":
    main()
