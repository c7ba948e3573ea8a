"""Grids of PhysIK runs, on Dask or serially: python3 -m physik.sweep SPEC.json

A sweep runs every scene of the spec at every point of its parameter grid (one engine run each,
`physik simulate` with the point's parameters), and writes one CSV row per run plus a summary.
The runs are independent, so they go to a Dask cluster: a LocalCluster on this machine by default
(one single-threaded worker process per core), or an existing cluster with --scheduler
tcp://HOST:PORT (its workers must be able to `import physik`: the build tree's python/ folder on
their PYTHONPATH, or the installed package). --serial runs the same grid in this process, without
Dask; the rows are the same, state hash for state hash (the engine is deterministic). A worker
that dies mid-sweep loses nothing: the scheduler runs its tasks again on the others.

The spec (JSON; relative paths against the spec's folder):

    {
      "name": "damping_sweep",                        optional (default: the file's stem)
      "scenes": ["../../models/scenes/fig5_running.json", ...],          required
      "grid": {"damping": [0.25, 0.5, 1], "dt": [0.05, 0.025]},           required
      "steps": 1500,                                  optional: replaces each scene's
      "stop_when_converged": true                     optional: replaces each scene's
    }

"grid" is one block or a list of blocks; a block is the Cartesian product of its lists (the last
key varies fastest) and a list of blocks is their union, in order. Scenes vary slowest. A key is
  - an engine parameter (any key of a scene's "params", models/README.md), applied as
    `physik simulate --set key=value` (before the scene is read: control points that take their
    k, spring or cap from the params follow), or
  - a scene transform of the tuning study (experiments/tuning_study.cpp): "scale" (every rig
    position, radius, target, cap and the root position times s), "density" (every bone's mass =
    density x length, kg per rig unit), "scale_torsion" (true: torsion k times density x s^3).

Outputs in --out (default sweep_<name>): results.csv, one row per run in grid order:
  scene, <grid keys>, converged, diverged, steps_to_converge (-1: never), steps_to_settle (the
  tuning study's measure, -1: not settled), steps_run, peak_kinetic_energy (J),
  max_final_residual (rig units), final_state_hash, wall_time_s
and summary.json: the spec, where it ran, counts, and the fastest-converging point per scene.

Exit status: 0 done, 2 a bad spec or scene (the message names the file and the field),
1 anything else (e.g. a cluster that cannot be reached).
"""
import argparse
import csv
import itertools
import json
import math
import os
import socket
import sys
import time
import uuid

import physik
from physik import _arguments

TRANSFORMS = ("scale", "density", "scale_torsion")
OUTCOMES = ("converged", "diverged", "steps_to_converge", "steps_to_settle", "steps_run",
            "peak_kinetic_energy", "max_final_residual", "final_state_hash", "wall_time_s")


class SpecError(physik.InputError):
    """A bad sweep spec; str() names the spec file and the field."""


# --- the spec ----------------------------------------------------------------------------------

def _fail(path, field, reason):
    raise SpecError("%s: field '%s': %s" % (path, field, reason) if field else "%s: %s" % (path, reason))


def load_spec(path):
    """The spec file as a dict, checked: SpecError naming the file and the field otherwise."""
    try:
        with open(path) as f:
            spec = json.load(f)
    except OSError as e:
        _fail(path, "", "cannot open file (%s)" % e.strerror)
    except ValueError as e:
        _fail(path, "", "invalid JSON: %s" % e)
    if not isinstance(spec, dict):
        _fail(path, "", "expected a JSON object")
    known = ("name", "comment", "scenes", "grid", "steps", "stop_when_converged")
    for key in spec:
        if key not in known:
            _fail(path, key, "unknown field (known fields: %s)" % ", ".join(known))
    scenes = spec.get("scenes")
    if not isinstance(scenes, list) or not scenes or not all(isinstance(s, str) for s in scenes):
        _fail(path, "scenes", "expected a non-empty list of scene file paths")
    if "grid" not in spec:
        _fail(path, "grid", "missing required field")
    blocks = spec["grid"] if isinstance(spec["grid"], list) else [spec["grid"]]
    if not blocks:
        _fail(path, "grid", "expected an object or a non-empty list of objects")
    for b, block in enumerate(blocks):
        where = "grid" if not isinstance(spec["grid"], list) else "grid[%d]" % b
        if not isinstance(block, dict) or not block:
            _fail(path, where, "expected an object of {key: [values]}")
        for key, values in block.items():
            if not isinstance(values, list) or not values:
                _fail(path, "%s.%s" % (where, key), "expected a non-empty list of values")
            if key in ("scale", "density"):
                for v in values:
                    if isinstance(v, bool) or not isinstance(v, (int, float)) or not v > 0 or math.isinf(v):
                        _fail(path, "%s.%s" % (where, key), "expected positive numbers, got %r" % (v,))
            if key == "scale_torsion" and not all(isinstance(v, bool) for v in values):
                _fail(path, "%s.%s" % (where, key), "expected true or false")
    steps = spec.get("steps")
    if steps is not None and (isinstance(steps, bool) or not isinstance(steps, int) or steps < 1):
        _fail(path, "steps", "expected an integer of at least 1")
    stop = spec.get("stop_when_converged")
    if stop is not None and not isinstance(stop, bool):
        _fail(path, "stop_when_converged", "expected true or false")
    return spec


def expand(spec, spec_path):
    """The spec's runs as task dicts (plain data, cheap to send to a worker), in grid order."""
    base = os.path.dirname(os.path.abspath(spec_path))
    blocks = spec["grid"] if isinstance(spec["grid"], list) else [spec["grid"]]
    tasks = []
    for label in spec["scenes"]:
        path = label if os.path.isabs(label) else os.path.normpath(os.path.join(base, label))
        for block in blocks:
            keys = list(block)
            for values in itertools.product(*(block[k] for k in keys)):
                point = dict(zip(keys, values))
                tasks.append({
                    "index": len(tasks),
                    "scene": label,
                    "scene_path": path,
                    "params": {k: v for k, v in point.items() if k not in TRANSFORMS},
                    "transforms": {k: v for k, v in point.items() if k in TRANSFORMS},
                    "steps": spec.get("steps"),
                    "stop_when_converged": spec.get("stop_when_converged"),
                })
    return tasks


def grid_keys(spec):
    """Every grid key, in first-seen order (the CSV's parameter columns)."""
    keys = []
    blocks = spec["grid"] if isinstance(spec["grid"], list) else [spec["grid"]]
    for block in blocks:
        keys += [k for k in block if k not in keys]
    return keys


# --- one run -----------------------------------------------------------------------------------

def _scaled_scene(path, params, scale=1.0, density=None, scale_torsion=False):
    """The tuning study's scaled scene (physik.scaled_scene, as experiments/tuning_study.cpp)."""
    base = physik.Scene.load(path, overrides=params)
    return physik.scaled_scene(base, float(scale), None if density is None else float(density),
                               bool(scale_torsion))


def build_scene(task):
    """The task's scene: loaded with its parameters, transformed, with the spec's steps and
    stop rule."""
    if task["transforms"]:
        scene = _scaled_scene(task["scene_path"], task["params"], **task["transforms"])
    else:
        scene = physik.Scene.load(task["scene_path"], overrides=task["params"])
    if task["steps"] is not None:
        scene.update(steps=task["steps"])
    if task["stop_when_converged"] is not None:
        scene.update(convergence={"stop_when_converged": task["stop_when_converged"]})
    return scene


def run_one(task):
    """Run one task; its CSV row as a dict (plus "index" and "worker")."""
    scene = build_scene(task)
    t0 = time.perf_counter()
    sim = physik.Simulation(scene)
    summary = sim.run()
    wall = time.perf_counter() - t0
    residuals = summary["final_residuals"]
    row = {"index": task["index"], "scene": task["scene"]}
    row.update(task["params"])
    row.update(task["transforms"])
    row.update({
        "converged": summary["converged"],
        "diverged": summary["diverged"],
        "steps_to_converge": -1 if summary["steps_to_converge"] is None else summary["steps_to_converge"],
        "steps_to_settle": sim.steps_to_settle,
        "steps_run": summary["steps_run"],
        "peak_kinetic_energy": summary["peak_kinetic_energy"],
        "max_final_residual": max(residuals) if residuals else 0.0,
        "final_state_hash": summary["final_state_hash"],
        "wall_time_s": wall,
        "worker": "%s:%d" % (socket.gethostname(), os.getpid()),
    })
    return row


def check_tasks(tasks, spec_path):
    """Build every task's scene once (cheap) so a bad value fails here, before any run, with
    the spec named: SpecError."""
    for task in tasks:
        try:
            build_scene(task)
        except physik.InputError as e:
            point = dict(task["params"], **task["transforms"])
            raise SpecError("%s: grid point %s of %s: %s" % (spec_path, json.dumps(point),
                                                             task["scene"], e)) from None


# --- where the runs go -------------------------------------------------------------------------

def run_serial(tasks, progress=True):
    """Every task in this process, in order."""
    rows = []
    for i, task in enumerate(tasks):
        rows.append(run_one(task))
        if progress:
            sys.stderr.write("\r  run %d/%d" % (i + 1, len(tasks)))
            sys.stderr.flush()
    if progress:
        sys.stderr.write("\n")
    return rows


def _worker_physik():
    return physik.__file__


def submit(client, tasks):
    """The tasks as Dask futures, one per run, keyed physik-run-<index>-<token>."""
    token = uuid.uuid4().hex[:12]
    return client.map(run_one, tasks, key=["physik-run-%d-%s" % (t["index"], token) for t in tasks],
                      pure=False)


def run_dask(tasks, scheduler=None, workers=None, progress=True):
    """Every task on Dask: a LocalCluster (workers processes of one thread), or the cluster at
    `scheduler`. Returns (rows in task order, a description of where they ran)."""
    from dask.distributed import Client, LocalCluster
    from dask.distributed import progress as dask_progress
    cluster = None
    if scheduler:
        client = Client(scheduler, timeout="20s")
        where = {"mode": "scheduler", "scheduler": scheduler}
    else:
        n = workers or os.cpu_count() or 1
        cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                               dashboard_address=None)
        client = Client(cluster)
        where = {"mode": "local", "scheduler": cluster.scheduler_address}
    try:
        where["workers"] = len(client.scheduler_info()["workers"])
        try:
            client.run(_worker_physik)
        except Exception as e:  # noqa: BLE001 -- any failure here means the same thing
            raise RuntimeError("the Dask workers cannot import physik (%s: %s); put the build "
                               "tree's python/ folder on their PYTHONPATH" % (type(e).__name__, e))
        futures = submit(client, tasks)
        if progress:
            dask_progress(futures)
            sys.stdout.write("\n")
        rows = client.gather(futures)
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
    return sorted(rows, key=lambda r: r["index"]), where


# --- outputs -----------------------------------------------------------------------------------

def csv_columns(spec):
    """results.csv's header: scene, the grid keys, the outcomes."""
    return ["scene"] + grid_keys(spec) + list(OUTCOMES)


def write_csv(rows, spec, path):
    """results.csv: one row per run; floats exact (repr), booleans 0/1, missing keys empty."""
    cols = csv_columns(spec)
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(cols)
        for r in rows:
            w.writerow([_cell(r.get(c, "")) for c in cols])


def _cell(v):
    if isinstance(v, bool):
        return int(v)
    if isinstance(v, float):
        return repr(v)  # round-trips exactly
    return v


def spec_name(spec, spec_path):
    """The spec's "name", or its file's stem."""
    return spec.get("name") or os.path.splitext(os.path.basename(spec_path))[0]


def summarize(rows, spec, spec_path, where, wall):
    """summary.json: the spec, where and how long it ran, counts, the fastest point per scene."""
    per_scene = {}
    for r in rows:
        s = per_scene.setdefault(r["scene"], {"runs": 0, "converged": 0, "diverged": 0, "fastest": None})
        s["runs"] += 1
        s["converged"] += bool(r["converged"])
        s["diverged"] += bool(r["diverged"])
        if r["converged"] and (s["fastest"] is None or r["steps_to_converge"] < s["fastest"]["steps_to_converge"]):
            s["fastest"] = {"point": {k: r[k] for k in grid_keys(spec) if k in r},
                            "steps_to_converge": r["steps_to_converge"]}
    return {"spec": os.path.abspath(spec_path), "name": spec_name(spec, spec_path), "grid": spec["grid"],
            "steps": spec.get("steps"), "stop_when_converged": spec.get("stop_when_converged"),
            "runs": len(rows), "converged": sum(bool(r["converged"]) for r in rows),
            "diverged": sum(bool(r["diverged"]) for r in rows), "where": where,
            "wall_time_s": wall, "run_time_s": sum(r["wall_time_s"] for r in rows),
            "csv": "results.csv", "per_scene": per_scene}


def sweep(spec_path, out=None, scheduler=None, serial=False, workers=None, progress=True):
    """Run the spec's grid and write results.csv and summary.json in `out`; returns the rows."""
    spec = load_spec(spec_path)
    tasks = expand(spec, spec_path)
    check_tasks(tasks, spec_path)
    out = out or "sweep_%s" % spec_name(spec, spec_path)
    t0 = time.perf_counter()
    if serial:
        rows, where = run_serial(tasks, progress), {"mode": "serial", "workers": 1}
    else:
        rows, where = run_dask(tasks, scheduler, workers, progress)
    wall = time.perf_counter() - t0
    os.makedirs(out, exist_ok=True)
    write_csv(rows, spec, os.path.join(out, "results.csv"))
    with open(os.path.join(out, "summary.json"), "w") as f:
        json.dump(summarize(rows, spec, spec_path, where, wall), f, indent=2)
        f.write("\n")
    return rows


def main(argv=None):
    """The command line (python3 -m physik.sweep); returns the exit status."""
    p = argparse.ArgumentParser(
        prog="python3 -m physik.sweep",
        description="Run a grid of PhysIK runs (scenes x parameter values) on Dask or serially; "
                    "write results.csv (one row per run) and summary.json.",
        epilog="The spec format is in this module's docstring (pydoc physik.sweep). Exit status: "
               "0 done, 2 bad spec, 1 other failure.")
    p.add_argument("spec", metavar="SPEC.json", help="the sweep spec (JSON)")
    p.add_argument("--out", help="output folder (default: sweep_<name>)")
    where = p.add_mutually_exclusive_group()
    where.add_argument("--scheduler", metavar="tcp://HOST:PORT",
                       help="an existing Dask scheduler (default: a LocalCluster on this machine)")
    where.add_argument("--serial", action="store_true", help="run in this process, without Dask")
    p.add_argument("--workers", type=int, help="LocalCluster worker processes (default: one per core)")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    a = p.parse_args(argv)
    if a.workers is not None and a.workers < 1:
        p.error("--workers must be at least 1")
    try:
        rows = sweep(a.spec, a.out, a.scheduler, a.serial, a.workers, not a.quiet)
    except physik.InputError as e:
        sys.stderr.write("physik.sweep: error: %s\n" % e)
        return 2
    except Exception as e:  # noqa: BLE001 -- reported, exit 1
        sys.stderr.write("physik.sweep: failed: %s: %s\n" % (type(e).__name__, e))
        return 1
    if not a.quiet:
        n_conv = sum(bool(r["converged"]) for r in rows)
        n_div = sum(bool(r["diverged"]) for r in rows)
        sys.stderr.write("physik.sweep: %d runs, %d converged, %d diverged\n" % (len(rows), n_conv, n_div))
    return 0


# a bad argument to the entry points: one line naming the valid keywords (physik/_arguments.py)
for _name in ("load_spec", "run_serial", "run_dask", "sweep"):
    globals()[_name] = _arguments.python(globals()[_name], _name)

if __name__ == "__main__":
    sys.exit(main())
