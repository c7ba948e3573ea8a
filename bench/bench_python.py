#!/usr/bin/env python3
"""What the Python module costs over C++ (a benchmark, never a test).

1. run(): Simulation(scene).run() from Python against the engine's own run_scene(scene) called
   once from C++ (physik._core.run_scene: the same scene, the same process, no Python in the
   loop), and against `physik simulate --quiet` (its summary's wall_time_s, which also includes
   writing trajectory.csv every step). Target: Python within 10% of C++.
2. step(): the cost of one step(1) call from Python, against one step inside step(N) (C++ loop):
   the difference is the per-call overhead of crossing into C++ (GIL release included).

Each figure is the best (minimum) of --repeat trials, wall clock and CPU time of the calling
thread (where the engine runs; on a busy machine the wall time also counts waiting for a core),
with the trials of the two sides interleaved so a busy machine slows both alike.

    PYTHONPATH=build/python /usr/bin/python3 bench/bench_python.py [--repeat 7] [--calls 10000]
"""
import argparse
import json
import os
import subprocess
import tempfile
import time

import physik
from physik import _core

SOURCE_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def scene(name, **kw):
    return physik.Scene.load(os.path.join(SOURCE_DIR, "models", "scenes", name + ".json"), **kw)


def timed(fn, *args):
    """(wall s, CPU s of this thread, result): the engine runs in the calling thread, so its CPU
    time is the cost without the waiting a busy machine adds to the wall time."""
    w0, c0 = time.perf_counter(), time.thread_time()
    result = fn(*args)
    return time.perf_counter() - w0, time.thread_time() - c0, result


def python_run(s):
    return physik.Simulation(s).run()


def cli_run(binary, path, steps):
    with tempfile.TemporaryDirectory() as out:
        subprocess.run([binary, "simulate", path, "--quiet", "--steps", str(steps), "--out", out],
                       check=False, capture_output=True)
        with open(os.path.join(out, "summary.json")) as f:
            return json.load(f)


def bench_run(name, steps, repeat, binary):
    s = scene(name, steps=steps)
    py, cpp, cli = [], [], []
    for _ in range(repeat):
        *t, a = timed(python_run, s)
        py.append(t)
        *t, b = timed(_core.run_scene, s)
        cpp.append(t)
        assert a["final_state_hash"] == b["final_state_hash"], "the two runs differ"
    if binary:
        cli = [cli_run(binary, s.file, steps)["wall_time_s"] for _ in range(3)]
    wall = min(t[0] for t in py) / min(t[0] for t in cpp)
    cpu = min(t[1] for t in py) / min(t[1] for t in cpp)
    print("run()   %-18s %4d steps, %2d bones: Python %7.2f ms (CPU %7.2f), C++ run_scene %7.2f ms "
          "(CPU %7.2f); Python/C++ wall %.3f, CPU %.3f%s"
          % (name, a["steps_run"], s.rig.nbone, min(t[0] for t in py) * 1e3, min(t[1] for t in py) * 1e3,
             min(t[0] for t in cpp) * 1e3, min(t[1] for t in cpp) * 1e3, wall, cpu,
             "; physik simulate (writes CSV) %.2f ms" % (min(cli) * 1e3) if cli else ""))
    return wall, cpu


def bench_step(name, calls, repeat):
    s = scene(name, steps=calls)
    s.update(convergence={"stop_when_converged": False, "stop_at_residual_tol": False})
    one, batch = [], []

    def one_by_one(sim):
        for _ in range(calls):
            sim.step(1)

    for _ in range(repeat):
        sim, sim2 = physik.Simulation(s), physik.Simulation(s)
        one.append(timed(one_by_one, sim)[:2])
        batch.append(timed(sim2.step, calls)[:2])
        assert sim.summary["final_state_hash"] == sim2.summary["final_state_hash"]
    for k, what in ((0, "wall"), (1, "CPU")):
        per_call = min(t[k] for t in one) / calls
        per_step = min(t[k] for t in batch) / calls
        print("step()  %-18s %2d bones (%4s): step(1) x %d: %6.2f us per call; inside step(%d): "
              "%6.2f us per step; overhead %.2f us per call"
              % (name, s.rig.nbone, what, calls, per_call * 1e6, calls, per_step * 1e6,
                 (per_call - per_step) * 1e6))


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--repeat", type=int, default=7)
    p.add_argument("--calls", type=int, default=10000)
    p.add_argument("--binary", default=os.path.join(SOURCE_DIR, "build", "physik"),
                   help="the CLI, for `physik simulate`'s engine time ('' to skip)")
    a = p.parse_args()
    binary = a.binary if a.binary and os.path.exists(a.binary) else None
    ratios = [bench_run(name, steps, a.repeat, binary)
              for name, steps in (("fig5_running", 400), ("pinhead_two_hands", 400),
                                  ("fig11_sit", 400), ("fig6_elbow_linear", 800))]
    print("run(): worst Python/C++ ratio: wall %.3f, CPU %.3f (target <= 1.10)"
          % (max(r[0] for r in ratios), max(r[1] for r in ratios)))
    for name in ("fig6_elbow_linear", "pinhead_two_hands"):
        bench_step(name, a.calls, a.repeat)


if __name__ == "__main__":
    main()
