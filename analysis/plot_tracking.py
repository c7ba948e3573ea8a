#!/usr/bin/env python3
"""Tracking: lag and jump ratio per frame of a dragged control point, per solver."""
import argparse
import collections
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import physik_plot as pp  # noqa: E402


def plot(folder):
    cols = pp.read_table(os.path.join(folder, "frames.csv"))
    series = collections.OrderedDict()
    for k, name in enumerate(cols["solver"]):
        s = series.setdefault(name, ([], [], []))
        s[0].append(cols["frame"][k])
        s[1].append(max(cols["lag"][k], 1e-12))
        s[2].append(cols["jump_ratio"][k])
    fig, (a, b) = pp.plt.subplots(1, 2, figsize=(11, 3.8))
    for name, (frame, lag, jump) in series.items():
        a.semilogy(frame, lag, label=name, lw=1)
        b.plot(frame, jump, label=name, lw=1)
    a.set_xlabel("frame")
    a.set_ylabel("lag: largest residual after the frame (rig units)")
    b.set_xlabel("frame")
    b.set_ylabel("jump ratio: tail motion / target motion")
    a.legend(fontsize=8)
    fig.suptitle("A control point dragged in a circle, 0.05 rig units per frame")
    return pp.save(fig, os.path.join(folder, "tracking.png"))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("folder")
    print("  wrote", plot(ap.parse_args(argv).folder))


if __name__ == "__main__":
    main()
