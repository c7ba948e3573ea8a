"""The physik module against the CLI: the same scenes give the same summary.json (every key and
value, wall time aside: final_state_hash equal means bit-identical final states), and every
command the module mirrors (solve, export-mjcf, simulate --reference, tune, equilibrium,
rig chain) gives the CLI's output."""
import csv
import glob
import json
import os
import re
import subprocess
import sys

import numpy as np
import pytest

import physik
from conftest import (BINARY, RIGS, SCENES, SOURCE_DIR, cli, json_like, read_json, scene_path,
                      without)

ALL_SCENES = sorted(glob.glob(os.path.join(SCENES, "*.json")))


def test_every_scene_is_covered():
    assert len(ALL_SCENES) >= 12, ALL_SCENES


@pytest.mark.parametrize("path", ALL_SCENES, ids=[os.path.basename(p)[:-5] for p in ALL_SCENES])
def test_run_equals_simulate(path, tmp):
    status, _, err = cli("simulate", path, "--out", tmp, "--quiet")
    assert status in (0, 3), err
    expected = read_json(os.path.join(tmp, "summary.json"))
    got = json_like(physik.Simulation(physik.Scene.load(path)).run())
    assert sorted(got) == sorted(expected)
    assert got["final_state_hash"] == expected["final_state_hash"]
    assert without(got, "wall_time_s") == without(expected, "wall_time_s")
    assert (status == 3) == got["diverged"]


def test_overrides_and_steps_are_set_and_steps(tmp):
    path = scene_path("pinhead_two_hands")
    status, _, _ = cli("simulate", path, "--out", tmp, "--quiet", "--set", "damping=1",
                       "--set", "control_spring=linear", "--steps", "120")
    assert status == 0
    expected = read_json(os.path.join(tmp, "summary.json"))
    for overrides in ({"damping": 1, "control_spring": "linear"},
                      ["damping=1", "control_spring=linear"]):
        scene = physik.Scene.load(path, overrides=overrides, steps=120)
        got = physik.Simulation(scene).run()
        assert without(got, "wall_time_s") == without(expected, "wall_time_s")
    assert expected["steps_run"] == 120


def test_divergence_is_a_flag_or_an_exception(tmp):
    path = scene_path("pinhead_two_hands")
    status, _, _ = cli("simulate", path, "--out", tmp, "--quiet", "--set", "damping=20")
    assert status == 3
    expected = read_json(os.path.join(tmp, "summary.json"))
    scene = physik.Scene.load(path, overrides={"damping": 20})
    got = json_like(physik.Simulation(scene).run())
    assert got["diverged"] and without(got, "wall_time_s") == without(expected, "wall_time_s")
    sim = physik.Simulation(scene)
    with pytest.raises(physik.DivergedError) as e:
        sim.run(raise_on_divergence=True)
    assert str(e.value) == expected["divergence_reason"]
    assert isinstance(e.value, RuntimeError)
    assert sim.summary["diverged"] and sim.stopped
    assert sim.step(5) == 0  # a diverged run takes no more steps
    with pytest.raises(physik.DivergedError):
        sim.step(1, raise_on_divergence=True)


def test_steps_then_run_is_one_run():
    scene = physik.Scene.load(scene_path("fig10_raise_polar-com"))
    whole = physik.Simulation(scene).run()
    sim = physik.Simulation(scene)
    assert sim.step(7) == 7 and sim.step(50) == 50 and sim.step_count == 57
    assert abs(sim.time - 57 * scene.params["dt"]) < 1e-12
    parts = sim.run()
    assert without(parts, "wall_time_s") == without(whole, "wall_time_s")


def test_step_goes_past_the_scene_steps_and_run_stops_at_them():
    scene = physik.Scene.load(scene_path("fig6_elbow_linear"), steps=30)
    sim = physik.Simulation(scene)
    assert sim.step(40) == 40 and sim.summary["steps_run"] == 40
    assert physik.Simulation(scene).run()["steps_run"] == 30


def test_stop_when_converged_stops_step_too():
    scene = physik.Scene.load(scene_path("pinhead_two_hands"))
    scene.update(convergence={"stop_when_converged": True}, steps=1000)
    sim = physik.Simulation(scene)
    taken = sim.step(1000)
    s = sim.summary
    assert s["converged"] and sim.stopped and taken == s["steps_run"] < 1000
    assert sim.step(10) == 0


def test_update_params_is_the_experiments_assignment():
    path = scene_path("fig9_outstretched")
    a = physik.Simulation(physik.Scene.load(path, overrides={"damping": 1.5})).run()
    scene = physik.Scene.load(path)
    scene.update(params={"damping": 1.5})
    b = physik.Simulation(scene).run()
    assert a["final_state_hash"] == b["final_state_hash"]
    assert scene.params["damping"] == 1.5
    # control points that give no k follow params.control_k; one that gives its own keeps it
    doc = read_json(scene_path("fig6_elbow_linear"))
    doc["control_points"][0]["k"] = 12.0
    s1 = physik.Scene.from_dict(doc, base_dir=SCENES)
    s1.update(params={"control_k": 5})
    assert [c["k"] for c in s1.control_points] == [12.0, 5.0, 5.0]
    s2 = physik.Scene.from_dict(doc, base_dir=SCENES)
    s2.update(params={"control_k": 5})
    s3 = physik.Scene.load(scene_path("fig6_elbow_linear"), overrides={"control_k": 5})
    assert [c["k"] for c in s3.control_points] == [5.0] * 3
    assert physik.Simulation(s2).run()["final_state_hash"] != physik.Simulation(s3).run()["final_state_hash"]


def _another_value(row, current):
    """A valid value of the row other than `current` (by its kind and range)."""
    if row["kind"] == "boolean":
        return not current
    if row["kind"] == "choice":
        return next(c for c in row["choices"] if c != current)
    if row["kind"] == "integer":
        return current + 1
    hi = row.get("range", {}).get("hi")
    value = current * 0.5 if current > 0 else 0.25
    assert hi is None or value < hi, row
    return value


def test_param_table_is_the_cli_table():
    status, out, err = cli("params", "--json")
    assert status == 0, err
    assert physik.param_table() == json.loads(out)


def test_every_table_row_reaches_update_and_load():
    # driven by the table: a row added to physik/model/params.cpp is covered without an edit here
    path = scene_path("fig9_outstretched")
    rows = physik.param_table()["params"]
    base = physik.Scene.load(path).params
    # a row the scene writer leaves out at its default (free_rods) is absent until set
    assert {"preset"} <= set(base) <= {"preset"} | {r["name"] for r in rows}
    for row in rows:
        name = row["name"]
        value = _another_value(row, base.get(name, row["defaults"][base["preset"]]))
        scene = physik.Scene.load(path)
        try:
            scene.update(params={name: value})
        except physik.InputError as e:
            # a value this scene's scheme would not use is refused, by update and load alike
            assert "applies" in str(e) or "cannot run" in str(e), (name, str(e))
            with pytest.raises(physik.InputError):
                physik.Scene.load(path, overrides={name: value})
            continue
        # damping auto reads back as the scene format writes it: "damping": "auto"
        want = dict(base, damping="auto") if name == "damping_auto" and value else dict(base, **{name: value})
        assert scene.params == want, name
        assert physik.Scene.load(path, overrides={name: value}).params == scene.params, name


def test_update_preset_resets_to_the_preset():
    status, out, err = cli("params", "--preset", "paper", "--json")
    assert status == 0, err
    scene = physik.Scene.load(scene_path("fig9_outstretched"), overrides={"dt": 0.01})
    scene.update(params={"preset": "paper", "damping": 7})
    assert scene.params == dict(json.loads(out), damping=7.0)


def test_from_dict_equals_load_and_takes_an_inline_rig():
    path = scene_path("fig9_outstretched")
    doc = read_json(path)
    by_path = physik.Scene.from_dict(doc, base_dir=SCENES, source=path)
    expected = physik.Simulation(physik.Scene.load(path)).run()
    got = physik.Simulation(by_path).run()
    assert without(got, "wall_time_s") == without(expected, "wall_time_s")
    # the rig inline (the Blender add-on's case): the same rig, so the same run
    doc["rig"] = physik.Rig.load(os.path.join(RIGS, "pinhead.json")).to_dict()
    inline = physik.Scene.from_dict(doc, source="armature")
    assert inline.rig_file == "" and inline.file == "armature"
    run = physik.Simulation(inline).run()
    assert run["rig"] == "" and run["converged"] == expected["converged"]
    assert run["steps_to_converge"] == expected["steps_to_converge"]
    assert np.allclose(run["final_residuals"], expected["final_residuals"], atol=1e-9)
    # and back: to_dict() writes the inline rig
    again = physik.Scene.from_dict(inline.to_dict(), source="again")
    assert again.rig.bone_names == inline.rig.bone_names


def test_scene_reads_back():
    scene = physik.Scene.load(scene_path("fig11_sit"))
    assert scene.params["preset"] in ("original", "paper")
    assert scene.steps > 0 and scene.rig.nbone == 18
    assert all(set(c) == {"name", "bone", "alpha", "target", "spring", "k", "cap"}
               for c in scene.control_points)
    assert scene.schedule and all(set(t) == {"step", "control_point", "target"} for t in scene.schedule)
    assert set(scene.convergence) == {"residual_tol", "speed_tol", "settle_steps",
                                      "stop_when_converged", "stop_at_residual_tol", "divergence_energy"}
    copy = scene.copy()
    copy.update(steps=3)
    assert scene.steps != 3 and copy.steps == 3


def test_rig_chain_equals_the_cli():
    status, out, _ = cli("rig", "chain", "4", "--bone-length", "0.5")
    assert status == 0
    import json
    assert physik.Rig.chain(4, bone_length=0.5).to_dict() == json.loads(out)
    rig = physik.Rig.load(os.path.join(RIGS, "pinhead.json"))
    assert rig.nbone == 18 and rig.bone_parents[0] == -1
    assert rig.rest_heads.shape == (18, 3) and rig.find_bone("hand.L") >= 0


def read_bones_csv(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    heads = np.array([[float(r["head_" + a]) for a in "xyz"] for r in rows])
    tails = np.array([[float(r["tail_" + a]) for a in "xyz"] for r in rows])
    return [r["bone"] for r in rows], heads, tails


@pytest.mark.parametrize("solver", ["fabrik", "ccd", "jt", "dls", "mass-spring", "rotation", "physik",
                                    "physik-steps", "physik-explicit"])
def test_solve_equals_the_cli(solver, tmp):
    path = scene_path("pinhead_two_hands")
    status, _, err = cli("solve", path, "--solver", solver, "--out", tmp, "--quiet")
    expected = read_json(os.path.join(tmp, "summary.json"))
    assert status == (0 if expected["converged"] else 4), err  # 4: short of its tolerance
    result = physik.solve(physik.Scene.load(path), solver)
    timing = ("time_s", "wall_time_s")
    assert without(result.summary, *timing) == without(expected, *timing)
    names, heads, tails = read_bones_csv(os.path.join(tmp, "final_pose.csv"))
    assert names == result.pose.bone_names
    # final_pose.csv holds 10 significant digits
    assert np.allclose(result.pose.heads, heads, rtol=1e-9, atol=1e-9)
    assert np.allclose(result.pose.tails, tails, rtol=1e-9, atol=1e-9)


def test_solve_with_engine_equals_simulation_with_its_settings():
    # solve(physik-explicit) is the scene's engine run with stop_at_residual_tol
    scene = physik.Scene.load(scene_path("fig9_outstretched"))
    result = physik.solve(scene, "physik-explicit", tol=1e-3)
    s = scene.copy()
    s.update(convergence={"stop_at_residual_tol": True, "residual_tol": 1e-3})
    run = physik.Simulation(s).run()
    assert result.summary["final_state_hash"] == run["final_state_hash"]
    assert result.summary["converged"] == run["converged"]


def test_export_mjcf_equals_the_cli():
    rig_path = os.path.join(RIGS, "pinhead.json")
    for joints in ("rig", "ball"):
        status, out, _ = cli("export-mjcf", rig_path, "--joints", joints, "--dt", "0.025")
        assert status == 0
        assert physik.export_mjcf(physik.Rig.load(rig_path), joints=joints, dt=0.025) == out


def test_compare_mujoco_equals_the_cli(tmp):
    path = scene_path("pinhead_two_hands")
    status, _, err = cli("simulate", path, "--steps", "20", "--quiet", "--reference",
                         "mujoco:exact-constraints", "--out", tmp)
    assert status == 0, err
    expected = read_json(os.path.join(tmp, "comparison.json"))
    got = json_like(physik.compare_mujoco(physik.Scene.load(path, steps=20), "exact-constraints"))
    assert strip_times(got) == strip_times(expected)


def strip_times(d):
    """A JSON tree without its wall-clock entries."""
    if isinstance(d, dict):
        return {k: strip_times(v) for k, v in d.items()
                if k not in ("wall_time_s", "time_s", "tune_wall_time_s")}
    if isinstance(d, list):
        return [strip_times(v) for v in d]
    return d


def test_tune_equals_the_cli(tmp):
    path = scene_path("pinhead_two_hands")
    report = os.path.join(tmp, "report.json")
    status, _, err = cli("tune", path, "--params", "damping", "--scan-points", "4",
                         "--max-iterations", "3", "--steps", "150", "--report", report, "--quiet")
    # pinhead's tuned damping lowers the objective and settles later than the scene's: the CLI
    # says so and exits 4 (converged later), its report written all the same
    assert status == 4, err
    assert "physik: converged later: tune: " in err and "its objective is lower" in err
    expected = read_json(report)
    got = physik.tune(physik.Scene.load(path), "damping", "settle", scan_points=4,
                      max_iterations=3, steps=150)
    tuned = got.pop("tuned_scene")
    assert "Termination" in got.pop("ceres_full")
    assert strip_times(json_like(got)) == strip_times(expected)
    assert tuned.params["damping"] == got["values"][0]


def test_equilibrium_equals_the_cli(tmp):
    path = scene_path("fig9_outstretched")
    out = os.path.join(tmp, "eq.json")
    status, _, err = cli("equilibrium", path, "--compare", "--start", "physik", "--out", out)
    assert status == 0, err
    expected = read_json(out)
    got, pose = physik.equilibrium(physik.Scene.load(path), start="physik", compare=True,
                                   with_pose=True)
    assert strip_times(json_like(got)) == strip_times(expected)
    assert pose.heads.shape == (18, 3)


def test_fig6_example_reproduces_the_experiment(tmp):
    status, _, err = cli("experiment", "run", "fig6_elbow", "--out", tmp, cwd=SOURCE_DIR)
    assert status == 0, err
    cases = {c["case"]: c for c in read_json(os.path.join(tmp, "fig6_elbow", "summary.json"))["cases"]}
    p = subprocess.run([sys.executable, os.path.join(SOURCE_DIR, "examples", "fig6_elbow.py")],
                       capture_output=True, text=True, cwd=SOURCE_DIR)
    assert p.returncode == 0, p.stderr
    lines = {l.split()[0]: l.split() for l in p.stdout.splitlines() if l.split() and l.split()[0] in ("linear", "capped")}
    for law in ("linear", "capped"):
        final, peak = float(lines[law][1]), float(lines[law][2])
        assert abs(final - cases["near_" + law]["final_overbend_deg"]) < 1e-9
        assert abs(peak - cases["near_" + law]["peak_overbend_deg"]) < 1e-9


def test_version_is_the_clis_from_one_definition():
    status, out, err = cli("--version")
    assert status == 0, err
    assert out == physik.__version__ + "\n"
    assert re.fullmatch(r"\d+\.\d+\.\d+", physik.__version__)
    # the one definition both read (physik/model/version.h)
    with open(os.path.join(SOURCE_DIR, "physik", "model", "version.h")) as f:
        defined = re.findall(r'kVersion\[\] = "([^"]*)"', f.read())
    assert defined == [physik.__version__]
    # before a command too, and listed in the help
    assert cli("--version", "params")[:2] == (0, out)
    assert "--version" in cli("--help")[1]


def test_an_explicit_damping_is_the_value_used_everywhere(tmp_path):
    # a scene that names no preset runs the robust preset: damping auto, its choice reported
    scene_file = tmp_path / "plain.json"
    scene_file.write_text(json.dumps({
        "rig": os.path.join(os.path.dirname(scene_path("fig9_outstretched")), "..", "rigs", "pinhead.json"),
        "control_points": [{"name": "reach", "bone": "hand.L", "target": [1.2, -0.6, 1.4]}],
        "steps": 60}))
    auto = physik.Scene.load(str(scene_file))
    assert auto.params["preset"] == "robust" and auto.params["damping"] == "auto"
    auto_run = physik.Simulation(auto).run()
    assert auto_run["damping"] == auto_run["damping_auto_value"] > 0
    # an override: the value given, auto off
    fixed = physik.Scene.load(str(scene_file), overrides={"damping": 1.5})
    assert fixed.params["damping"] == 1.5
    fixed_run = physik.Simulation(fixed).run()
    assert fixed_run["damping"] == 1.5 and "damping_auto_value" not in fixed_run
    assert fixed_run["final_state_hash"] != auto_run["final_state_hash"]
    # Scene.update likewise, and back to auto
    updated = physik.Scene.load(str(scene_file))
    updated.update(params={"damping": 1.5})
    assert updated.params == fixed.params
    updated.update(params={"damping": "auto"})
    assert updated.params == auto.params
    # a sweep grid's damping is an override
    task = {"scene_path": str(scene_file), "params": {"damping": 1.5}, "transforms": {},
            "steps": None, "stop_when_converged": None}
    assert physik.Simulation(sweep_build_scene(task)).run()["final_state_hash"] == \
        fixed_run["final_state_hash"]
    # tuning damping tunes a value: the tuned scene's damping is it, auto off
    report = physik.tune(auto, "damping", scan_points=3, max_iterations=1, steps=40)
    assert report["tuned_scene"].params["damping"] == report["values"][0]


def sweep_build_scene(task):
    from physik import sweep
    return sweep.build_scene(task)
