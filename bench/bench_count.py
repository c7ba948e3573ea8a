#!/usr/bin/env python3
"""Instructions per bone-step, counted by callgrind (`make bench-count`; a benchmark, never timed).

A time on a shared 2-core machine moves with whatever else runs; an instruction count of the same
run does not. For each case (rig, bones, scheme) this runs physik_count (bench/count_steps.cpp:
the scaling scenario of experiments/scaling.h set up, then its steps) under

    valgrind --tool=callgrind --toggle-collect='count_stepping_loop*'

which counts the instructions executed inside count_stepping_loop and nothing else: the program's
start, the rig, the scene and init_state (set-up) are not counted. Each case runs twice, N and
2 N steps, and reports
    ir_per_bone_step       I(N) / (N n): the first N steps from rest, as the issue's count
    ir_per_bone_step_next  (I(2N) - I(N)) / (N n): steps N+1 .. 2N
    next_over_first        their ratio: 1 where a step's cost does not depend on the state (exact),
                           and a check that nothing outside the loop was counted (a constant in I
                           would show here as a ratio below 1)
with I the instructions (callgrind's Ir) and n the bones. Why the toggle and not the difference
alone: the toggle removes set-up exactly (at 10,000 bones init_state costs more than a step), and
the difference then shows whether the first N steps are typical of the run.
With --cache-sim, callgrind also simulates the data caches (with this machine's first-level and
last-level sizes; no second level), and the table adds the first N steps' misses per bone-step:
a count of what a time sees as the state leaving the caches.

The table goes to stdout, the rows to OUT/bench_count.csv and OUT/bench_count.json
(default OUT: build/bench_count, never in git).

    /usr/bin/python3 bench/bench_count.py --binary build/physik_count [--sizes 100,1000,10000]
        [--schemes exact,implicit] [--steps N] [--cache-sim] [--out DIR]
"""
import argparse
import csv
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
import time

SOURCE_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TOGGLE = "count_stepping_loop*"
COLUMNS = ["rig", "bones", "scheme", "steps", "ir_first", "ir_double", "ir_per_bone_step",
           "ir_per_bone_step_next", "next_over_first", "iterations_first", "iterations_double",
           "final_state_hash", "valgrind_s", "d1_miss_per_bone_step", "ll_miss_per_bone_step"]
# gauss-seidel's joint passes per step grow with n (a long chain's plateau in docs/DESIGN.md), so
# its step costs about n^2: it is counted over fewer steps, and only up to 1,000 bones
GAUSS_SEIDEL_MAX_BONES = 1000


def steps_for(scheme):
    """N: 100 steps (exact and implicit: under callgrind most of a case's time is its set-up),
    10 for gauss-seidel"""
    return 10 if scheme == "gauss-seidel" else 100


def callgrind_totals(path):
    """{event: count} collected in a callgrind output file: its `events:` line named by its
    `totals:` line (`summary:` in older files), whose trailing zeros callgrind leaves out"""
    events, totals = ["Ir"], None
    with open(path) as f:
        for line in f:
            if line.startswith("events:"):
                events = line.split()[1:]
            elif line.startswith("totals:") or (totals is None and line.startswith("summary:")):
                totals = [int(x) for x in line.split()[1:]]
    if totals is None:
        raise ValueError(f"{path}: no 'totals:' or 'summary:' line (not a callgrind output file?)")
    return dict(zip(events, totals + [0] * (len(events) - len(totals))))


def callgrind_total(path):
    """Ir collected in a callgrind output file"""
    return callgrind_totals(path)["Ir"]


def count(binary, rig, bones, scheme, steps, scratch, cache_sim=False):
    """({event: count} inside count_stepping_loop, the driver's JSON line, s under valgrind) for
    one run"""
    out = os.path.join(scratch, f"callgrind.{rig}.{bones}.{scheme}.{steps}.out")
    cmd = ["valgrind", "--tool=callgrind", f"--toggle-collect={TOGGLE}",
           f"--cache-sim={'yes' if cache_sim else 'no'}",
           f"--callgrind-out-file={out}", binary, "--rig", rig, "--bones", str(bones),
           "--scheme", scheme, "--steps", str(steps)]
    t0 = time.monotonic()
    p = subprocess.run(cmd, capture_output=True, text=True, check=False)
    seconds = time.monotonic() - t0
    if p.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)}: exit {p.returncode}\n{p.stderr[-2000:]}")
    return callgrind_totals(out), json.loads(p.stdout.strip().splitlines()[-1]), seconds


def case(binary, rig, bones, scheme, steps, scratch, cache_sim=False):
    """one row: N and 2 N steps counted; with cache_sim also the first N steps' data-cache
    misses (reads and writes) per bone-step in callgrind's first level (D1) and last level (LL)
    caches, simulated with this machine's sizes"""
    e1, run1, s1 = count(binary, rig, bones, scheme, steps, scratch, cache_sim)
    e2, run2, s2 = count(binary, rig, bones, scheme, 2 * steps, scratch, cache_sim)
    i1, i2 = e1["Ir"], e2["Ir"]
    first = i1 / (steps * bones)
    nxt = (i2 - i1) / (steps * bones)
    misses = {}
    for level in ("D1", "DL"):
        if cache_sim:
            misses[level] = (e1[level + "mr"] + e1[level + "mw"]) / (steps * bones)
    return {"rig": rig, "bones": bones, "scheme": scheme, "steps": steps, "ir_first": i1,
            "ir_double": i2, "ir_per_bone_step": first, "ir_per_bone_step_next": nxt,
            "next_over_first": nxt / first if first > 0 else math.nan,
            "iterations_first": run1["iterations"], "iterations_double": run2["iterations"],
            "final_state_hash": run2["final_state_hash"], "valgrind_s": s1 + s2,
            "d1_miss_per_bone_step": misses.get("D1", ""),
            "ll_miss_per_bone_step": misses.get("DL", "")}


def print_table(rows, file=sys.stdout):
    cache = any(r["d1_miss_per_bone_step"] != "" for r in rows)
    head = ["rig", "bones", "scheme", "N", "Ir/bone-step", "next N", "next/first", "iter 2N"]
    head += ["D1 miss/bone-step", "LL miss/bone-step"] if cache else []
    print("| " + " | ".join(head) + " |", file=file)
    print("|" + "---|" * len(head), file=file)
    for r in rows:
        line = (f"| {r['rig']} | {r['bones']:,} | {r['scheme']} | {r['steps']} | "
                f"{r['ir_per_bone_step']:,.0f} | {r['ir_per_bone_step_next']:,.0f} | "
                f"{r['next_over_first']:.4f} | {r['iterations_double']} |")
        if cache:
            line += f" {r['d1_miss_per_bone_step']:.2f} | {r['ll_miss_per_bone_step']:.3f} |"
        print(line, file=file)


def write(rows, out):
    os.makedirs(out, exist_ok=True)
    with open(os.path.join(out, "bench_count.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=COLUMNS)
        w.writeheader()
        w.writerows(rows)
    with open(os.path.join(out, "bench_count.json"), "w") as f:
        json.dump({"toggle_collect": TOGGLE, "columns": COLUMNS, "rows": rows}, f, indent=1)


def parse_args(argv):
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--binary", default=os.path.join(SOURCE_DIR, "build", "physik_count"))
    p.add_argument("--rig", default="chain", choices=["chain", "tree2"])
    p.add_argument("--sizes", default="100,1000,10000", help="bones, comma-separated")
    p.add_argument("--schemes", default="exact,implicit,gauss-seidel",
                   help="comma-separated; gauss-seidel only up to "
                        f"{GAUSS_SEIDEL_MAX_BONES} bones")
    p.add_argument("--steps", type=int, default=0, help="N (default: steps_for the scheme)")
    p.add_argument("--out", default=os.path.join(SOURCE_DIR, "build", "bench_count"))
    p.add_argument("--cache-sim", action="store_true",
                   help="also simulate the data caches (D1 and LL misses per bone-step; slower)")
    a = p.parse_args(argv)
    try:
        a.sizes = [int(x) for x in a.sizes.split(",")]
    except ValueError:
        p.error(f"--sizes: '{a.sizes}' is not a comma-separated list of integers")
    a.schemes = a.schemes.split(",")
    for s in a.schemes:
        if s not in ("exact", "implicit", "gauss-seidel"):
            p.error(f"--schemes: '{s}' is not exact, implicit or gauss-seidel")
    if any(n < 1 for n in a.sizes):
        p.error(f"--sizes: every size must be at least 1 bone, not {a.sizes}")
    if a.steps < 0:
        p.error(f"--steps: must be positive (0: steps_for the scheme), not {a.steps}")
    if not os.access(a.binary, os.X_OK):
        p.error(f"--binary: {a.binary} is not an executable (build the physik_count target)")
    if shutil.which("valgrind") is None:
        p.error("valgrind not found (apt-get install valgrind; scripts/install-deps.sh has it)")
    return a


def main(argv=None):
    a = parse_args(argv)
    rows = []
    with tempfile.TemporaryDirectory() as scratch:
        for bones in a.sizes:
            for scheme in a.schemes:
                if scheme == "gauss-seidel" and bones > GAUSS_SEIDEL_MAX_BONES:
                    continue
                steps = a.steps or steps_for(scheme)
                rows.append(case(a.binary, a.rig, bones, scheme, steps, scratch, a.cache_sim))
                print(f"counted {a.rig} {bones} {scheme}: {rows[-1]['valgrind_s']:.0f} s",
                      file=sys.stderr)
    print_table(rows)
    write(rows, a.out)
    print(f"rows: {os.path.join(a.out, 'bench_count.csv')} and bench_count.json")
    return 0


if __name__ == "__main__":
    sys.exit(main())
