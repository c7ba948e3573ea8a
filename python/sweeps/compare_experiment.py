#!/usr/bin/env python3
"""Check a physik.sweep results.csv against the C++ experiment's sweep.csv, row by row.

    build/physik experiment run damping_sweep tuning_study --out /tmp/exp
    PYTHONPATH=build/python python3 -m physik.sweep python/sweeps/damping_sweep.json --out /tmp/ds
    python3 python/sweeps/compare_experiment.py damping_sweep /tmp/exp/damping_sweep/sweep.csv /tmp/ds/results.csv

The experiment writes numbers with C++'s default stream format (6 significant digits, %g) and
booleans as 0/1; the sweep's values are formatted the same way and compared as text, so every
printed digit must agree. The columns compared are the experiment's, as its summary.json
records them ("tables": name and format per column), that the sweep's results.csv also has;
tuning_study's steps_to_converge is the sweep's steps_to_settle (the tuning study's measure).
The columns the sweep lacks are listed, not compared.
Exit 0 when every row agrees, 1 otherwise (each difference printed), 2 on bad arguments or an
experiment folder without the table's schema.
"""
import csv
import json
import os
import sys

# an experiment's column the sweep writes under another name
SWEEP_NAME = {"tuning_study": {"steps_to_converge": "steps_to_settle"}}


def g(value, digits=6):
    """A number as C++'s `out << std::setprecision(digits) << double` writes it."""
    return "%.*g" % (digits, float(value))


def flag(value):
    return "1" if value in ("1", "True", "true") else "0"


def as_written(column, value):
    """A sweep's cell as the experiment's column writes it (its schema's format)."""
    fmt = column["format"].split("|")[0]
    if fmt == "flag":
        return flag(value)
    if fmt.startswith("g"):
        return g(value, int(fmt[1:]))
    if column["name"] == "scene":  # the sweep names the scene file, the experiment its name
        return os.path.splitext(os.path.basename(value))[0]
    return value


def experiment_schema(csv_path):
    """The schema of the table the experiment wrote to csv_path, from summary.json beside it."""
    summary = os.path.join(os.path.dirname(csv_path), "summary.json")
    try:
        with open(summary) as f:
            tables = json.load(f).get("tables", {})
    except (OSError, ValueError) as e:
        raise ValueError("%s: cannot read the experiment's summary (%s)" % (summary, e))
    for schema in tables.values():
        if schema.get("file") == os.path.basename(csv_path):
            return schema
    raise ValueError("%s: no schema for %s under \"tables\""
                     % (summary, os.path.basename(csv_path)))


def compared_columns(kind, schema, sweep_header):
    """[(experiment column, sweep column name)] both have, and the experiment's others."""
    rename = SWEEP_NAME.get(kind, {})
    pairs, skipped = [], []
    for c in schema["columns"]:
        if not c.get("csv", True):
            continue
        name = rename.get(c["name"], c["name"])
        (pairs.append((c, name)) if name in sweep_header else skipped.append(c["name"]))
    return pairs, skipped


def compare(pairs, want, got):
    bad = 0
    if len(want) != len(got):
        print("row count: experiment %d, sweep %d" % (len(want), len(got)))
        bad += 1
    for i, (w, s) in enumerate(zip(want, got)):
        w = [w[c["name"]] for c, _ in pairs]
        s = [as_written(c, s[name]) for c, name in pairs]
        if w != s:
            bad += 1
            print("row %d differs:\n  experiment %s\n  sweep      %s" % (i + 1, w, s))
    return bad


def main(argv):
    if len(argv) != 4 or argv[1] not in ("damping_sweep", "tuning_study"):
        sys.stderr.write(__doc__)
        return 2
    kind = argv[1]
    try:
        schema = experiment_schema(argv[2])
    except ValueError as e:
        sys.stderr.write("%s\n" % e)
        return 2
    with open(argv[2]) as f:
        want = list(csv.DictReader(f))
    with open(argv[3]) as f:
        reader = csv.DictReader(f)
        got = list(reader)
    pairs, skipped = compared_columns(kind, schema, reader.fieldnames or [])
    bad = compare(pairs, want, got)
    print("%s: %d rows compared on %s (not in the sweep: %s), %d differ"
          % (kind, min(len(want), len(got)), ", ".join(c["name"] for c, _ in pairs),
             ", ".join(skipped) or "none", bad))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
