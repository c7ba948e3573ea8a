"""Simulation.run(record_every=N): `physik simulate --every N`'s trajectory.csv as numpy arrays,
value for value (each written with the table's 9 significant digits), with a first row for the
state the run starts from, on scenes with a schedule, a divergence and an early stop."""
import csv
import json
import os

import numpy as np
import pytest

import physik
from conftest import cli, json_like, read_json, scene_path, without


def table_rows(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    return rows[0], rows[1:]


def g(value):
    return "%.9g" % value  # the table's precision (physik/io/recorder.cpp)


def as_rows(t):
    """The trajectory's rows as the table writes them: step, time, kinetic_energy, passes,
    joint_mismatch, joint_separation, a residual per control point, six values per bone."""
    rows = []
    for r in range(len(t.steps)):
        row = [str(t.steps[r]), g(t.times[r]), g(t.kinetic_energy[r]), str(t.passes[r]),
               g(t.joint_mismatch[r]), g(t.joint_separation[r])]
        row += [g(v) for v in t.residuals[r]]
        for head, tail in zip(t.heads[r], t.tails[r]):
            row += [g(v) for v in head] + [g(v) for v in tail]
        rows.append(row)
    return rows


def check_start_row(scene, t):
    """The first row is the initial state, read from a fresh Simulation."""
    fresh = physik.Simulation(scene)
    assert (t.steps[0], t.times[0], t.passes[0], t.joint_mismatch[0]) == (0, 0.0, 0, 0.0)
    assert t.kinetic_energy[0] == fresh.kinetic_energy
    assert np.array_equal(t.residuals[0], fresh.residuals)
    assert np.array_equal(t.heads[0], fresh.pose.heads)
    assert np.array_equal(t.tails[0], fresh.pose.tails)


def early_stop_scene(tmp):
    """fig6's elbow, stopping once converged (a run that ends before its step count)."""
    doc = physik.Scene.load(scene_path("fig6_elbow_linear")).to_dict()
    doc["convergence"] = dict(doc.get("convergence", {}), stop_when_converged=True)
    path = os.path.join(tmp, "early_stop.json")
    with open(path, "w") as f:
        json.dump(doc, f)
    return path


# (scene, --every, --set overrides): a schedule with a last step off the grid, a divergence by
# energy, one to a non-finite state at step 1 (a row the table leaves out), an early stop
CASES = [("fig11_sit", 7, {}), ("pinhead_two_hands", 1, {"damping": 20}),
         ("pinhead_two_hands", 1, {"control_k": 1e308}), ("fig9_outstretched", 25, {}),
         ("early_stop", 3, {})]


@pytest.mark.parametrize("name,every,overrides", CASES,
                         ids=["-".join([c[0]] + ["%s=%g" % kv for kv in c[2].items()])
                              for c in CASES])
def test_trajectory_equals_simulate_every(name, every, overrides, tmp):
    path = early_stop_scene(tmp) if name == "early_stop" else scene_path(name)
    out = os.path.join(tmp, "out")
    flags = [a for k, v in overrides.items() for a in ("--set", "%s=%s" % (k, v))]
    status, _, err = cli("simulate", path, "--out", out, "--quiet", "--every", every, *flags)
    assert status in (0, 3), err
    header, expected = table_rows(os.path.join(out, "trajectory.csv"))
    scene = physik.Scene.load(path, overrides=overrides)
    result = physik.Simulation(scene).run(record_every=every)
    summary, t = result
    assert isinstance(result, physik.RunResult) and isinstance(t, physik.Trajectory)
    nc, nb = len(scene.control_points), scene.rig.nbone
    assert len(header) == 6 + nc + 6 * nb
    assert t.residuals.shape == (len(t.steps), nc) and t.heads.shape == (len(t.steps), nb, 3)
    check_start_row(scene, t)
    got = as_rows(t)
    if not expected or expected[0][0] != "0":
        got = got[1:]  # a table without the initial state's row: compare the steps it has
    assert got == expected
    assert summary["diverged"] == (status == 3)
    expected_summary = read_json(os.path.join(out, "summary.json"))
    assert without(json_like(summary), "wall_time_s") == without(expected_summary, "wall_time_s")


def test_rows_follow_the_rule():
    scene = physik.Scene.load(scene_path("fig11_sit"))
    t = physik.Simulation(scene).run(record_every=7).trajectory
    steps = list(t.steps)
    assert steps == [0] + list(range(7, scene.steps, 7)) + [scene.steps]
    assert np.all(np.diff(t.times) > 0)
    # without record_every, the summary alone (as before)
    assert isinstance(physik.Simulation(scene).run(), dict)


def test_a_stepped_simulation_records_from_where_it_is():
    scene = physik.Scene.load(scene_path("fig9_outstretched"))
    sim = physik.Simulation(scene)
    sim.step(12)
    heads = np.array(sim.pose.heads)
    t = sim.run(record_every=10).trajectory
    assert list(t.steps[:3]) == [12, 20, 30] and np.array_equal(t.heads[0], heads)
    assert sim.step(1) == 1  # a live simulation steps on past the scene's count, unrecorded
    # nothing left to run: the row of where it is, alone
    assert sim.run(record_every=5).trajectory.steps.tolist() == [scene.steps + 1]


def test_bad_record_every():
    sim = physik.Simulation(physik.Scene.load(scene_path("fig9_outstretched")))
    with pytest.raises(physik.InputError, match="run: field 'record_every': must not be negative"):
        sim.run(record_every=-1)
    assert sim.step_count == 0
