"""physik.sweep on Dask: a real dask-scheduler and two dask-workers on 127.0.0.1 (ports chosen by
the OS, one thread each, no nanny, all stopped even when a test fails) run a 12-run grid, which
must equal the serial run row for row (final_state_hash included); one worker SIGKILLed while it
runs a task loses nothing (its runs are done again by the other, all 12 rows, hashes equal);
the default LocalCluster gives the same rows."""
import csv
import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time

import pytest

import physik
from physik import sweep
from conftest import SCENES

# 2 scenes x 3 dampings x 2 time steps = 12 runs of a few tenths of a second each
GRID12 = {
    "name": "grid12",
    "scenes": [os.path.join(SCENES, "pinhead_two_hands.json"), os.path.join(SCENES, "fig9_outstretched.json")],
    "grid": {"damping": [0.5, 1, 3], "dt": [0.05, 0.025]},
    "steps": 4000,
    "stop_when_converged": False,
}
OUTCOME_COLUMNS = [c for c in sweep.OUTCOMES if c != "wall_time_s"]


@pytest.fixture(scope="module")
def workdir():
    d = tempfile.mkdtemp(prefix="physik_sweep_test_")
    yield d
    shutil.rmtree(d, ignore_errors=True)


@pytest.fixture(scope="module")
def spec_path(workdir):
    path = os.path.join(workdir, "grid12.json")
    with open(path, "w") as f:
        json.dump(GRID12, f)
    return path


@pytest.fixture(scope="module")
def serial(spec_path, workdir):
    """The grid run serially through the command line: its CSV rows."""
    out = os.path.join(workdir, "serial")
    run_cli(spec_path, "--serial", "--out", out)
    return read_rows(out)


def run_cli(*args):
    p = subprocess.run([sys.executable, "-m", "physik.sweep", "--quiet"] + list(args),
                       capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr
    return p


def read_rows(out):
    with open(os.path.join(out, "results.csv")) as f:
        return list(csv.DictReader(f))


def same_outcomes(rows, expected):
    assert len(rows) == len(expected) == 12
    for got, want in zip(rows, expected):
        for col in ["scene", "damping", "dt"] + OUTCOME_COLUMNS:
            assert got[col] == want[col], (col, got, want)


class DaskCluster:
    """dask-scheduler and n dask-workers as child processes; stop() kills whatever is left."""

    def __init__(self, workdir, n_workers=2):
        self.procs = []
        self.workers = []
        self.dir = tempfile.mkdtemp(dir=workdir)
        try:
            self._start(n_workers)
        except BaseException:
            self.stop()  # whatever did start
            raise

    def _start(self, n_workers):
        file = os.path.join(self.dir, "scheduler.json")
        log = open(os.path.join(self.dir, "scheduler.log"), "w")
        self.procs.append(subprocess.Popen(
            ["dask-scheduler", "--host", "127.0.0.1", "--port", "0", "--no-dashboard",
             "--scheduler-file", file], stdout=log, stderr=subprocess.STDOUT))
        self.address = self._wait_for_address(file)
        for k in range(n_workers):
            wlog = open(os.path.join(self.dir, "worker%d.log" % k), "w")
            p = subprocess.Popen(
                ["dask-worker", self.address, "--nthreads", "1", "--no-nanny", "--no-dashboard",
                 "--host", "127.0.0.1", "--name", "w%d" % k, "--death-timeout", "60",
                 "--local-directory", self.dir], stdout=wlog, stderr=subprocess.STDOUT)
            self.procs.append(p)
            self.workers.append(p)
        from dask.distributed import Client
        with Client(self.address, timeout="30s") as client:
            client.wait_for_workers(n_workers, timeout=60)

    def _wait_for_address(self, file):
        deadline = time.time() + 60
        while time.time() < deadline:
            if self.procs[0].poll() is not None:
                raise RuntimeError("dask-scheduler exited: " + self.logs())
            try:
                with open(file) as f:
                    return json.load(f)["address"]
            except (OSError, ValueError, KeyError):
                time.sleep(0.1)
        raise RuntimeError("dask-scheduler wrote no address: " + self.logs())

    def logs(self):
        text = ""
        for name in sorted(os.listdir(self.dir)):
            if name.endswith(".log"):
                with open(os.path.join(self.dir, name)) as f:
                    text += "\n--- %s\n%s" % (name, f.read()[-3000:])
        return text

    def stop(self):
        for p in reversed(self.procs):
            if p.poll() is None:
                p.terminate()
        for p in self.procs:
            try:
                p.wait(timeout=10)
            except subprocess.TimeoutExpired:
                p.kill()
                p.wait()


@pytest.fixture
def cluster(workdir):
    c = None
    try:
        c = DaskCluster(workdir)
        yield c
    finally:
        if c is not None:
            c.stop()


def test_serial_rows_are_the_simulations(serial, spec_path):
    # the serial CSV is the engine's own runs: spot-check two rows against Simulation directly
    for row in (serial[0], serial[-1]):
        scene = physik.Scene.load(os.path.join(SCENES, os.path.basename(row["scene"])),
                                  overrides={"damping": float(row["damping"]), "dt": float(row["dt"])},
                                  steps=4000)
        s = physik.Simulation(scene).run()
        assert row["final_state_hash"] == s["final_state_hash"]
        assert int(row["steps_run"]) == s["steps_run"] == 4000
    assert len({r["final_state_hash"] for r in serial}) == 12  # 12 different runs


def test_scheduler_and_two_workers_equal_serial(cluster, spec_path, workdir, serial):
    out = os.path.join(workdir, "dask")
    try:
        run_cli(spec_path, "--scheduler", cluster.address, "--out", out)
    except AssertionError:
        print(cluster.logs())
        raise
    same_outcomes(read_rows(out), serial)
    with open(os.path.join(out, "summary.json")) as f:
        summary = json.load(f)
    assert summary["where"] == {"mode": "scheduler", "scheduler": cluster.address, "workers": 2}
    assert summary["runs"] == 12


def test_a_worker_killed_mid_sweep_loses_nothing(cluster, spec_path, serial):
    from dask.distributed import Client, as_completed
    tasks = sweep.expand(sweep.load_spec(spec_path), spec_path)
    with Client(cluster.address, timeout="30s") as client:
        client.wait_for_workers(2, timeout=60)
        pids = client.run(os.getpid)  # worker address -> pid
        futures = sweep.submit(client, tasks)
        done = as_completed(futures)
        next(done)  # one run finished: both workers are now busy with the next ones
        processing = client.processing()
        victim = next(a for a, keys in processing.items() if keys)
        victim_keys = set(processing[victim])
        proc = next(p for p in cluster.workers if p.pid == pids[victim])
        os.kill(proc.pid, signal.SIGKILL)
        proc.wait(timeout=10)
        rows = client.gather(futures)
        survivors = client.run(os.getpid)
    assert victim not in survivors and len(survivors) == 1
    survivor_pid = list(survivors.values())[0]
    # every run was finished; the ones the killed worker was running were run again elsewhere
    assert len(rows) == 12
    by_key = {f.key: r for f, r in zip(futures, rows)}
    assert victim_keys and all(by_key[k]["worker"].endswith(":%d" % survivor_pid) for k in victim_keys)
    for got, want in zip(sorted(rows, key=lambda r: r["index"]), serial):
        assert got["final_state_hash"] == want["final_state_hash"]
        assert str(got["steps_run"]) == want["steps_run"]


def test_local_cluster_equals_serial(spec_path, workdir, serial):
    out = os.path.join(workdir, "local")
    run_cli(spec_path, "--workers", "2", "--out", out)
    same_outcomes(read_rows(out), serial)
    with open(os.path.join(out, "summary.json")) as f:
        assert json.load(f)["where"]["mode"] == "local"
