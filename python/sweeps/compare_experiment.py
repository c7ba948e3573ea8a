#!/usr/bin/env python3
"""Check a physik.sweep results.csv against the C++ experiment's sweep.csv, row by row.

    build/physik experiment run damping_sweep tuning_study --out /tmp/exp
    PYTHONPATH=build/python python3 -m physik.sweep python/sweeps/damping_sweep.json --out /tmp/ds
    python3 python/sweeps/compare_experiment.py damping_sweep /tmp/exp/damping_sweep/sweep.csv /tmp/ds/results.csv

The experiment writes numbers with C++'s default stream format (6 significant digits, %g) and
booleans as 0/1; the sweep's values are formatted the same way and compared as text, so every
printed digit must agree. Columns compared:
  damping_sweep: scene, damping, converged, steps_to_converge, diverged, steps_run,
                 peak_kinetic_energy, max_final_residual
  tuning_study:  scale, density, damping, steps_to_converge (the sweep's steps_to_settle), diverged
Exit 0 when every row agrees, 1 otherwise (each difference printed).
"""
import csv
import os
import sys


def g(value):
    """A number as C++'s `out << double` writes it by default."""
    return "%g" % float(value)


def flag(value):
    return "1" if value in ("1", "True", "true") else "0"


def sweep_rows(kind, rows):
    out = []
    for r in rows:
        if kind == "damping_sweep":
            out.append([os.path.splitext(os.path.basename(r["scene"]))[0], g(r["damping"]),
                        flag(r["converged"]), r["steps_to_converge"], flag(r["diverged"]),
                        r["steps_run"], g(r["peak_kinetic_energy"]), g(r["max_final_residual"])])
        else:
            out.append([g(r["scale"]), g(r["density"]), g(r["damping"]), r["steps_to_settle"],
                        flag(r["diverged"])])
    return out


def experiment_rows(kind, rows):
    out = []
    for r in rows:
        if kind == "damping_sweep":
            out.append([r["scene"], g(r["damping"]), r["converged"], r["steps_to_converge"],
                        r["diverged"], r["steps_run"], g(r["peak_kinetic_energy"]),
                        g(r["max_final_residual"])])
        else:
            out.append([g(r["scale"]), g(r["density"]), g(r["damping"]), r["steps_to_converge"],
                        r["diverged"]])
    return out


def main(argv):
    if len(argv) != 4 or argv[1] not in ("damping_sweep", "tuning_study"):
        sys.stderr.write(__doc__)
        return 2
    kind = argv[1]
    with open(argv[2]) as f:
        want = experiment_rows(kind, list(csv.DictReader(f)))
    with open(argv[3]) as f:
        got = sweep_rows(kind, list(csv.DictReader(f)))
    bad = 0
    if len(want) != len(got):
        print("row count: experiment %d, sweep %d" % (len(want), len(got)))
        bad += 1
    for i, (w, s) in enumerate(zip(want, got)):
        if w != s:
            bad += 1
            print("row %d differs:\n  experiment %s\n  sweep      %s" % (i + 1, w, s))
    print("%s: %d rows compared, %d differ" % (kind, min(len(want), len(got)), bad))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
