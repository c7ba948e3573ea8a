"""Every bad input raises physik.InputError (a ValueError) with exactly the CLI's message: the same
file is given to build/physik (exit 2, "physik: error: <message>") and to the module."""
import json
import math
import os
import subprocess
import sys

import pytest

import physik
from conftest import RIGS, SOURCE_DIR, cli_error, scene_path

ELBOW = os.path.join(RIGS, "elbow.json")


def write(tmp, name, text):
    path = os.path.join(tmp, name)
    with open(path, "w") as f:
        f.write(text)
    return path


def raises_input_error(fn, *args, **kwargs):
    with pytest.raises(physik.InputError) as e:
        fn(*args, **kwargs)
    assert isinstance(e.value, ValueError)
    return str(e.value)


def scene_text(**fields):
    doc = {"rig": ELBOW, "control_points": [{"bone": "forearm", "target": [0, 1, 2]}]}
    doc.update(fields)
    return json.dumps(doc)


# (name, scene file text); each is loaded by `physik simulate` and by Scene.load
BAD_SCENES = [
    ("malformed", '{"rig": "%s", "control_points": [' % ELBOW),
    ("unknown_bone", scene_text(control_points=[{"bone": "wrist", "target": [0, 0, 1]}])),
    ("nan_target", '{"rig": "%s", "control_points": [{"bone": "forearm", "target": [NaN, 0, 1]}]}' % ELBOW),
    ("huge_target", '{"rig": "%s", "control_points": [{"bone": "forearm", "target": [1e999, 0, 1]}]}' % ELBOW),
    ("string_target", scene_text(control_points=[{"bone": "forearm", "target": [0, "x", 1]}])),
    ("negative_dt", scene_text(params={"dt": -1})),
    ("unknown_param", scene_text(params={"dampin": 3})),
    ("unknown_value", scene_text(params={"integration": "rk4"})),
    ("missing_rig", json.dumps({"rig": "nowhere.json"})),
    ("alpha", scene_text(control_points=[{"bone": "forearm", "alpha": 2, "target": [0, 0, 1]}])),
    ("schedule_step", scene_text(steps=10, schedule=[{"step": 10, "control_point": 0, "target": [0, 0, 1]}])),
]


@pytest.mark.parametrize("name,text", BAD_SCENES, ids=[n for n, _ in BAD_SCENES])
def test_bad_scene(name, text, tmp):
    path = write(tmp, name + ".json", text)
    expected = cli_error("simulate", path, "--out", os.path.join(tmp, "out"), "--quiet")
    assert raises_input_error(physik.Scene.load, path) == expected
    assert expected.startswith(path)


def test_missing_scene_file(tmp):
    path = os.path.join(tmp, "none.json")
    expected = cli_error("simulate", path, "--out", tmp)
    assert raises_input_error(physik.Scene.load, path) == expected


def rig_text(bones):
    return json.dumps({"bones": bones})


# (name, rig file text); each is loaded by `physik rig info` and by Rig.load
BAD_RIGS = [
    ("cycle", rig_text([{"name": "root", "parent": None, "head": [0, 0, 0], "tail": [0, 0, 1]},
                        {"name": "a", "parent": "b", "head": [0, 0, 1], "tail": [0, 0, 2]},
                        {"name": "b", "parent": "a", "head": [0, 0, 2], "tail": [0, 0, 3]}])),
    ("zero_length", rig_text([{"name": "a", "parent": None, "head": [0, 0, 0], "tail": [0, 0, 0]}])),
    ("inverted_limits", rig_text([{"name": "a", "parent": None, "head": [0, 0, 0], "tail": [0, 0, 1]},
                                  {"name": "b", "parent": "a", "head": [0, 0, 1], "tail": [0, 0, 2],
                                   "limits_deg": {"x": [30, -30]}}])),
    ("two_roots", rig_text([{"name": "a", "parent": None, "head": [0, 0, 0], "tail": [0, 0, 1]},
                            {"name": "b", "parent": None, "head": [0, 0, 1], "tail": [0, 0, 2]}])),
    ("unknown_parent", rig_text([{"name": "a", "parent": None, "head": [0, 0, 0], "tail": [0, 0, 1]},
                                 {"name": "b", "parent": "c", "head": [0, 0, 1], "tail": [0, 0, 2]}])),
    ("negative_mass", rig_text([{"name": "a", "parent": None, "head": [0, 0, 0], "tail": [0, 0, 1],
                                 "mass": -1}])),
]


@pytest.mark.parametrize("name,text", BAD_RIGS, ids=[n for n, _ in BAD_RIGS])
def test_bad_rig(name, text, tmp):
    path = write(tmp, name + ".json", text)
    expected = cli_error("rig", "info", path)
    assert raises_input_error(physik.Rig.load, path) == expected
    # the same rig inside a scene: Scene.load reports it as `physik simulate` does
    scene = write(tmp, name + "_scene.json", json.dumps({"rig": path}))
    assert raises_input_error(physik.Scene.load, scene) == cli_error("simulate", scene, "--out", tmp)
    # and inline in a scene dict (the Blender add-on's way): the scene's source names it
    message = raises_input_error(physik.Scene.from_dict, {"rig": json.loads(text)}, source="arm")
    assert message.startswith("arm: rig: ")


def test_rig_chain_zero():
    expected = cli_error("rig", "chain", "0")
    assert raises_input_error(physik.Rig.chain, 0) == expected


def test_dict_errors_name_the_source():
    doc = {"rig": ELBOW, "control_points": [{"bone": "forearm", "target": [math.nan, 0, 1]}]}
    # a NaN cannot be written in a JSON file; from a dict it is caught by the same field check
    assert raises_input_error(physik.Scene.from_dict, doc, source="live") == \
        "live: control_points[0]: field 'target[0]': not a finite number"
    doc["control_points"][0] = {"bone": "wrist", "target": [0, 0, 1]}
    assert raises_input_error(physik.Scene.from_dict, doc) == \
        "<scene dict>: control_points[0]: field 'bone': unknown bone 'wrist' in rig " + ELBOW
    with pytest.raises(TypeError):
        physik.Scene.from_dict({"rig": ELBOW, "steps": object()})


def test_unknown_override(tmp):
    path = scene_path("pinhead_two_hands")
    expected = cli_error("simulate", path, "--out", tmp, "--set", "bogus=1")
    assert raises_input_error(physik.Scene.load, path, overrides={"bogus": 1}) == expected
    assert raises_input_error(physik.Scene.load, path, overrides=["bogus=1"]) == expected
    expected = cli_error("simulate", path, "--out", tmp, "--set", "damping=-2")
    assert raises_input_error(physik.Scene.load, path, overrides={"damping": -2}) == expected
    expected = cli_error("simulate", path, "--out", tmp, "--steps", "-1")
    assert raises_input_error(physik.Scene.load, path, steps=-1) == expected


def test_update_checks_like_the_file():
    scene = physik.Scene.load(scene_path("pinhead_two_hands"))
    path = scene.file
    assert raises_input_error(scene.update, params={"dt": 0}) == \
        path + ": params: field 'dt': must be positive"
    assert "unknown field" in raises_input_error(scene.update, params={"bogus": 1})
    assert raises_input_error(scene.update, convergence={"settle_steps": 0}) == \
        path + ": convergence: field 'settle_steps': must be at least 1"
    assert raises_input_error(scene.update, steps=0) == path + ": field 'steps': must be at least 1"
    assert scene.params["dt"] == 0.05  # unchanged by the failed updates


def test_unknown_solver(tmp):
    path = scene_path("pinhead_two_hands")
    expected = cli_error("solve", path, "--solver", "newton", "--out", tmp)
    assert raises_input_error(physik.solve, physik.Scene.load(path), "newton") == expected
    expected = cli_error("solve", path, "--solver", "dls", "--tol", "-1", "--out", tmp)
    assert raises_input_error(physik.solve, physik.Scene.load(path), "dls", tol=-1) == expected
    expected = cli_error("solve", path, "--solver", "dls", "--jacobian", "exact", "--out", tmp)
    assert raises_input_error(physik.solve, physik.Scene.load(path), "dls", jacobian="exact") == expected


def test_solve_needs_control_points(tmp):
    path = write(tmp, "free.json", json.dumps({"rig": ELBOW}))
    expected = cli_error("solve", path, "--solver", "dls", "--out", tmp)
    assert raises_input_error(physik.solve, physik.Scene.load(path), "dls") == expected


def test_unknown_tune_parameter_and_bad_options():
    path = scene_path("pinhead_two_hands")
    scene = physik.Scene.load(path)
    expected = cli_error("tune", path, "--params", "damping,bogus", "--quiet")
    assert raises_input_error(physik.tune, scene, "damping,bogus") == expected
    assert raises_input_error(physik.tune, scene, ["damping", "bogus"]) == expected
    expected = cli_error("tune", path, "--objective", "fast", "--quiet")
    assert raises_input_error(physik.tune, scene, "damping", "fast") == expected
    expected = cli_error("tune", path, "--bounds", "damping=5:1", "--quiet")
    assert raises_input_error(physik.tune, scene, "damping", bounds={"damping": (5, 1)}) == expected
    assert raises_input_error(physik.tune, scene, {"damping": (5, 1)}) == expected


def test_equilibrium_and_mujoco_options():
    path = scene_path("pinhead_two_hands")
    scene = physik.Scene.load(path)
    expected = cli_error("equilibrium", path, "--start", "middle")
    assert raises_input_error(physik.equilibrium, scene, start="middle") == expected
    expected = cli_error("simulate", path, "--reference", "bullet", "--out", "/nonexistent/x")
    assert raises_input_error(physik.compare_mujoco, scene, "bullet") == expected
    expected = cli_error("export-mjcf", os.path.join(RIGS, "pinhead.json"), "--dt", "0")
    assert raises_input_error(physik.export_mjcf, scene.rig, dt=0) == expected


def test_step_count_must_not_be_negative():
    sim = physik.Simulation(physik.Scene.load(scene_path("fig6_elbow_linear")))
    assert raises_input_error(sim.step, -1) == "step: field 'n': must not be negative"


SWEEP_CASES = [
    ("not_json", "{", "invalid JSON"),
    ("no_grid", {"scenes": ["x.json"]}, "field 'grid': missing required field"),
    ("no_scenes", {"grid": {"damping": [1]}}, "field 'scenes': expected a non-empty list"),
    ("empty_values", {"scenes": ["s.json"], "grid": {"damping": []}}, "field 'grid.damping': expected a non-empty list"),
    ("bad_scale", {"scenes": ["s.json"], "grid": [{"scale": [0]}]}, "field 'grid[0].scale': expected positive numbers"),
    ("bad_steps", {"scenes": ["s.json"], "grid": {"damping": [1]}, "steps": 0}, "field 'steps'"),
    ("unknown_field", {"scenes": ["s.json"], "grid": {"damping": [1]}, "repeat": 2}, "field 'repeat': unknown field"),
    ("unknown_param", {"scenes": ["s.json"], "grid": {"dampin": [1]}}, "field 'dampin': unknown parameter"),
    ("bad_value", {"scenes": ["s.json"], "grid": {"dt": [0.05, -1]}}, "grid point {\"dt\": -1}"),
    ("missing_scene", {"scenes": ["nowhere.json"], "grid": {"damping": [1]}}, "cannot open file"),
]


@pytest.mark.parametrize("name,spec,needle", SWEEP_CASES, ids=[c[0] for c in SWEEP_CASES])
def test_bad_sweep_spec_exits_2_naming_file_and_field(name, spec, needle, tmp):
    write(tmp, "s.json", json.dumps({"rig": ELBOW, "steps": 5}))
    path = write(tmp, name + ".json", spec if isinstance(spec, str) else json.dumps(spec))
    p = subprocess.run([sys.executable, "-m", "physik.sweep", path, "--serial", "--out",
                        os.path.join(tmp, "out")], capture_output=True, text=True)
    assert p.returncode == 2, p.stderr
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("physik.sweep: error: " + path), p.stderr
    assert needle in lines[0], lines[0]
    assert not os.path.exists(os.path.join(tmp, "out"))


def test_sweep_help():
    p = subprocess.run([sys.executable, "-m", "physik.sweep", "--help"], capture_output=True, text=True)
    assert p.returncode == 0 and "--scheduler" in p.stdout and "--serial" in p.stdout
