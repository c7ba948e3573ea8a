#!/usr/bin/env python3
"""Two builds' runs of every shipped scene, compared (a change to the step's order of operations may
move trajectories by round-off, never more).

For each models/scenes/*.json and each scheme, `physik simulate SCENE --set scheme=S` runs with the
old binary and the new one; the report gives, per run, whether final_state_hash is the same and
the largest absolute difference between the two trajectory.csv files (every numeric column, every
row). Exit 1 if any difference exceeds --tolerance or the runs differ in shape.

    /usr/bin/python3 scripts/compare_scene_runs.py --old OLD/physik --new build/physik
        [--schemes exact,implicit,gauss-seidel] [--tolerance 1e-12] [--reuse-old] [--out DIR]
"""
import argparse
import csv
import glob
import json
import os
import subprocess
import sys

SOURCE_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def run(binary, scene, scheme, out):
    cmd = [binary, "simulate", scene, "--set", f"scheme={scheme}", "--out", out, "--quiet"]
    p = subprocess.run(cmd, capture_output=True, text=True, check=False)
    error = f"exit {p.returncode}: {p.stderr.strip()[-300:]}" if p.returncode != 0 else ""
    os.makedirs(out, exist_ok=True)
    with open(os.path.join(out, "exit.txt"), "w") as f:
        f.write(error)
    if error:
        return None, error
    return read_summary(out), None


def reused(out):
    """(summary, error) of a run already in out"""
    with open(os.path.join(out, "exit.txt")) as f:
        error = f.read()
    return (None, error) if error else (read_summary(out), None)


def read_summary(out):
    with open(os.path.join(out, "summary.json")) as f:
        return json.load(f)


def read_rows(path):
    with open(path) as f:
        rows = list(csv.reader(f))
    return rows[0], rows[1:]


def max_difference(a, b):
    """largest |a - b| over numeric cells; None when the files differ in shape or text"""
    head_a, rows_a = read_rows(a)
    head_b, rows_b = read_rows(b)
    if head_a != head_b or len(rows_a) != len(rows_b):
        return None
    worst = 0.0
    for ra, rb in zip(rows_a, rows_b):
        if len(ra) != len(rb):
            return None
        for x, y in zip(ra, rb):
            if x == y:
                continue
            try:
                worst = max(worst, abs(float(x) - float(y)))
            except ValueError:
                return None
    return worst


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--old", required=True)
    p.add_argument("--new", default=os.path.join(SOURCE_DIR, "build", "physik"))
    p.add_argument("--schemes", default="exact,implicit,gauss-seidel")
    p.add_argument("--tolerance", type=float, default=1e-12)
    p.add_argument("--reuse-old", action="store_true",
                   help="keep the old binary's runs already in OUT/old (same binary)")
    p.add_argument("--out", default=os.path.join(SOURCE_DIR, "build", "compare_scene_runs"))
    a = p.parse_args()
    failed = False
    print("| scene | scheme | hash same | max abs trajectory difference |")
    print("|---|---|---|---|")
    for scene in sorted(glob.glob(os.path.join(SOURCE_DIR, "models", "scenes", "*.json"))):
        name = os.path.splitext(os.path.basename(scene))[0]
        for scheme in a.schemes.split(","):
            outs = [os.path.join(a.out, which, name, scheme) for which in ("old", "new")]
            reuse = a.reuse_old and os.path.exists(os.path.join(outs[0], "exit.txt"))
            s_old, e_old = reused(outs[0]) if reuse else run(a.old, scene, scheme, outs[0])
            s_new, e_new = run(a.new, scene, scheme, outs[1])
            if e_old or e_new:
                same_error = e_old == e_new
                print(f"| {name} | {scheme} | both fail: {same_error} | {e_old or e_new} |")
                failed |= not same_error
                continue
            same = s_old.get("final_state_hash") == s_new.get("final_state_hash")
            diff = max_difference(*(os.path.join(o, "trajectory.csv") for o in outs))
            bad = diff is None or diff > a.tolerance
            failed |= bad
            shown = "shape differs" if diff is None else f"{diff:.3g}"
            print(f"| {name} | {scheme} | {'yes' if same else 'NO'} | {shown} |", flush=True)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
