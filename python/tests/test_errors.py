"""Every bad input raises physik.InputError (a ValueError) with exactly the CLI's message: the same
file is given to build/physik (exit 2, "physik: error: <message>") and to the module."""
import json
import math
import os
import subprocess
import sys

import pytest

import physik
from conftest import RIGS, SOURCE_DIR, cli, cli_error, scene_path

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
    ("unknown_value", scene_text(params={"scheme": "rk4"})),
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


def keyword(message, flag, name):
    """The CLI's message for an option, as Python words it: the keyword for the flag."""
    assert message.startswith(flag + ":"), message
    return name + message[len(flag):]


def test_an_unknown_override_names_the_keyword_and_the_closest_key():
    # Python names its keyword, not the CLI's --set
    path = scene_path("pinhead_two_hands")
    expected = "overrides: unknown parameter 'dampng' (did you mean 'damping'?)"
    assert raises_input_error(physik.Scene.load, path, overrides={"dampng": 1}) == expected
    assert raises_input_error(physik.Scene.load, path, overrides=["dampng=1"]) == expected


def test_bad_overrides_have_the_clis_message_for_the_keyword(tmp):
    path = scene_path("pinhead_two_hands")
    expected = cli_error("simulate", path, "--out", tmp, "--set", "bogus=1")
    assert raises_input_error(physik.Scene.load, path, overrides={"bogus": 1}) == \
        keyword(expected, "--set", "overrides")
    expected = cli_error("simulate", path, "--out", tmp, "--set", "damping=-2")
    assert raises_input_error(physik.Scene.load, path, overrides={"damping": -2}) == \
        keyword(expected, "--set", "overrides")
    expected = cli_error("simulate", path, "--out", tmp, "--steps", "-1")
    assert raises_input_error(physik.Scene.load, path, steps=-1) == \
        keyword(expected, "--steps", "steps")


def test_update_checks_like_the_file():
    scene = physik.Scene.load(scene_path("pinhead_two_hands"))
    path = scene.file
    assert raises_input_error(scene.update, params={"dt": 0}) == \
        path + ": params: field 'dt': must be positive"
    assert "unknown parameter 'bogus'" in raises_input_error(scene.update, params={"bogus": 1})
    assert raises_input_error(scene.update, convergence={"settle_steps": 0}) == \
        path + ": convergence: field 'settle_steps': must be at least 1"
    assert raises_input_error(scene.update, steps=0) == path + ": field 'steps': must be at least 1"
    assert scene.params["dt"] == 0.05  # unchanged by the failed updates


def test_unknown_solver(tmp):
    path = scene_path("pinhead_two_hands")
    scene = physik.Scene.load(path)
    expected = cli_error("solve", path, "--solver", "newton", "--out", tmp)
    assert raises_input_error(physik.solve, scene, "newton") == \
        keyword(expected, "--solver", "solver")
    expected = cli_error("solve", path, "--solver", "dls", "--tol", "-1", "--out", tmp)
    assert raises_input_error(physik.solve, scene, "dls", tol=-1) == \
        keyword(expected, "--tol", "tol")
    expected = cli_error("solve", path, "--solver", "dls", "--jacobian", "exact", "--out", tmp)
    assert raises_input_error(physik.solve, scene, "dls", jacobian="exact") == \
        keyword(expected, "--jacobian", "jacobian")
    expected = cli_error("solve", path, "--solver", "physik", "--max-dt", "0", "--out", tmp)
    assert raises_input_error(physik.solve, scene, "physik", max_dt=0) == \
        keyword(expected, "--max-dt", "max_dt")


def test_solve_needs_control_points(tmp):
    path = write(tmp, "free.json", json.dumps({"rig": ELBOW}))
    expected = cli_error("solve", path, "--solver", "dls", "--out", tmp)
    assert raises_input_error(physik.solve, physik.Scene.load(path), "dls") == expected


def test_unknown_tune_parameter_and_bad_options():
    path = scene_path("pinhead_two_hands")
    scene = physik.Scene.load(path)
    expected = keyword(cli_error("tune", path, "--params", "damping,bogus", "--quiet"), "--params",
                       "params")
    assert raises_input_error(physik.tune, scene, "damping,bogus") == expected
    assert raises_input_error(physik.tune, scene, ["damping", "bogus"]) == expected
    expected = cli_error("tune", path, "--objective", "fast", "--quiet")
    assert raises_input_error(physik.tune, scene, "damping", "fast") == \
        keyword(expected, "--objective", "objective")
    expected = keyword(cli_error("tune", path, "--bounds", "damping=5:1", "--quiet"), "--bounds",
                       "bounds")
    assert raises_input_error(physik.tune, scene, "damping", bounds={"damping": (5, 1)}) == expected
    assert raises_input_error(physik.tune, scene, {"damping": (5, 1)}) == expected
    expected = cli_error("tune", path, "--scan-points", "1", "--quiet")
    assert raises_input_error(physik.tune, scene, scan_points=1) == \
        keyword(expected, "--scan-points", "scan_points")


def test_equilibrium_and_mujoco_options():
    path = scene_path("pinhead_two_hands")
    scene = physik.Scene.load(path)
    expected = cli_error("equilibrium", path, "--start", "middle")
    assert raises_input_error(physik.equilibrium, scene, start="middle") == \
        keyword(expected, "--start", "start")
    expected = cli_error("simulate", path, "--reference", "bullet", "--out", "/nonexistent/x")
    assert raises_input_error(physik.compare_mujoco, scene, "bullet") == \
        keyword(expected, "--reference", "mode")
    expected = cli_error("export-mjcf", os.path.join(RIGS, "pinhead.json"), "--dt", "0")
    assert raises_input_error(physik.export_mjcf, scene.rig, dt=0) == \
        keyword(expected, "--dt", "dt")


# a rig started into the ground warns as `physik simulate` warns, and one started through it is the
# CLI's bad input, in every call that runs the engine from the scene's start
def test_start_contacts_are_checked_as_the_cli_checks_them(tmp):
    def start_scene(name, fields):
        doc = {"rig": ELBOW, "gravity": [0, 0, -9.81], "params": {"dt": 0.01},
               "control_points": [{"bone": "forearm", "alpha": 1, "target": [0, 1, 3]}]}
        doc.update(fields)
        return write(tmp, name, json.dumps(doc))

    sunk = start_scene("sunk.json", {"ground": {"height": -0.06}})
    status, _, err = cli("simulate", sunk, "--out", os.path.join(tmp, "sunk"), "--steps", "1", "--quiet")
    assert status == 0, err
    (cli_warning,) = [l[len("physik: warning: "):] for l in err.splitlines()
                      if l.startswith("physik: warning: ")]
    scene = physik.Scene.load(sunk, steps=2)
    calls = [lambda: physik.Simulation(scene), lambda: physik._core.run_scene(scene),
             lambda: physik.PosingSession(scene), lambda: physik.solve(scene, "physik"),
             lambda: physik.tune(scene, scan_points=0, max_iterations=1)]
    for call in calls:
        with pytest.warns(physik.StartContactWarning) as record:
            call()
        assert [str(w.message) for w in record] == [cli_warning]
    below = start_scene("below.json", {"ground": {"height": 0},
                                       "initial_pose": {"root_head": [0, 0, -100]}})
    expected = cli_error("simulate", below, "--out", os.path.join(tmp, "below"), "--quiet")
    scene = physik.Scene.load(below)
    for call in [lambda: physik.Simulation(scene), lambda: physik._core.run_scene(scene),
                 lambda: physik.PosingSession(scene), lambda: physik.solve(scene, "physik"),
                 lambda: physik.tune(scene, scan_points=0, max_iterations=1)]:
        assert raises_input_error(call) == expected


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
    ("unknown_param", {"scenes": ["s.json"], "grid": {"dampin": [1]}}, "overrides: unknown parameter 'dampin' (did you mean 'damping'?)"),
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


SESSION_RULE = ("method, tolerance, tolerance_fraction, tolerance_angle, max_steps, stall_steps, "
                "stall_fraction, initial_step, armature, dt_growth, max_dt, finish, finish_options")
# (a call with a misspelt keyword, its name, the misspelt key, the valid keywords)
UNKNOWN_KEYWORDS = [
    (lambda s: physik.solve(s, tole=1), "solve", "tole",
     "scene, solver, tol, tol_angle, max_iterations, lambda_, jacobian, gravity, rotation_damping, "
     "socket, cone, no_limits, armature, dt_growth, max_dt, finish, raise_on_divergence"),
    (lambda s: physik.Scene.load(s.file, overides={}), "Scene.load", "overides",
     "path, overrides, steps"),
    (lambda s: s.update(param={}), "Scene.update", "param", "params, convergence, steps"),
    (lambda s: physik.Simulation(s, steps=3), "Simulation", "steps", "scene"),
    (lambda s: physik.Simulation(s).step(m=2), "Simulation.step", "m", "n, raise_on_divergence"),
    (lambda s: physik.Simulation(s).run(every=2), "Simulation.run", "every",
     "raise_on_divergence, record_every"),
    (lambda s: physik.PosingSession(s, mode=True), "PosingSession", "mode", "scene, solve_mode"),
    (lambda s: physik.PosingSession(s).solve(tole=1), "PosingSession.solve", "tole", SESSION_RULE),
    (lambda s: physik.PosingSession(s).set_target(0, [0, 0, 1], smooth=True),
     "PosingSession.set_target", "smooth", "c, target, interpolate"),
    (lambda s: physik.export_mjcf(s.rig, joint="ball"), "export_mjcf", "joint", "rig, joints, dt"),
    (lambda s: physik.compare_mujoco(s, model="x"), "compare_mujoco", "model", "scene, mode"),
    (lambda s: physik.tune(s, param="damping"), "tune", "param",
     "scene, params, objective, bounds, measure, steps, scan_points, max_iterations, verbose"),
    (lambda s: physik.equilibrium(s, begin="x"), "equilibrium", "begin",
     "scene, start, compare, with_pose"),
    (lambda s: physik.Rig.chain(3, length=2), "Rig.chain", "length", "n, bone_length, radius"),
    (lambda s: physik.param_table(x=1), "param_table", "x", None),
    (lambda s: physik.sweep.sweep("x.json", outdir="y"), "sweep", "outdir",
     "spec_path, out, scheduler, serial, workers, progress"),
]


@pytest.mark.parametrize("call,name,key,valid", UNKNOWN_KEYWORDS,
                         ids=[c[1] for c in UNKNOWN_KEYWORDS])
def test_an_unknown_keyword_names_the_valid_ones(call, name, key, valid):
    import physik.sweep  # noqa: F401 -- the sweep module is a name of the package too
    scene = physik.Scene.load(scene_path("pinhead_two_hands"))
    with pytest.raises(TypeError) as e:
        call(scene)
    tail = "valid: " + valid if valid else "it takes no arguments"
    assert str(e.value) == "%s() got an unexpected keyword argument '%s'; %s" % (name, key, tail)


def test_other_bad_arguments_are_one_line():
    scene = physik.Scene.load(scene_path("pinhead_two_hands"))
    sim = physik.Simulation(scene)
    with pytest.raises(TypeError) as e:
        sim.step("ten")
    assert str(e.value) == "Simulation.step(): bad arguments (str); expected " \
                           "(n: int = 1, raise_on_divergence: bool = False)"
    with pytest.raises(TypeError) as e:
        physik.Scene.load(3.5)
    assert str(e.value).startswith("Scene.load(): bad arguments (float); expected (path: str, ")
    with pytest.raises(TypeError) as e:
        physik.solve()
    assert str(e.value).startswith("solve(): missing a required argument: 'scene'; "
                                   "valid: scene, solver, ")
    # a TypeError raised inside a call is the call's own, unchanged
    with pytest.raises(TypeError, match=r"^scene.steps: cannot be written as JSON"):
        physik.Scene.from_dict({"rig": ELBOW, "steps": object()})
    # and a call that matches runs as before
    assert sim.step(n=2) == 2 and sim.step_count == 2
