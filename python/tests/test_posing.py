"""physik.PosingSession against the C++ it binds: its solve is `physik solve`'s (same steps,
residual, summary and state hash, bit for bit), its advance and set_target are the engine's
steps and schedule, its pose is numpy views of its state, its bad input is InputError, and its
per-frame calls allocate nothing in C++ (counted by a preloaded operator new)."""
import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import physik
from conftest import cli, read_json, scene_path, without

# the keys `physik solve` adds to the session's summary (physik/posing/scene_solve.cpp)
SOLVE_KEYS = ("solver", "iterations", "time_s", "residual", "residual_tol", "stalled",
              "out_of_steps", "finish", "finish_iterations", "dt_growth", "max_dt", "wall_time_s",
              "not_converged_reason", "method", "residual_tol_angle", "stationary",
              "refused_iterations", "final_step", "goals", "short_goals")


def solve_like_the_cli(scene, solver, finish, finish_options):
    """A session driven as physik/posing/scene_solve.cpp drives it for --solver physik,
    physik-steps or physik-explicit."""
    mode = solver in ("physik", "physik-steps")
    session = physik.PosingSession(scene, solve_mode=mode)
    if solver == "physik":  # the equilibrium solve: --max-iterations (1000; the CLI's flag is
        # also the finish's max_iterations), --tol-angle 1e-4
        rule = physik.solve_mode_rule()
        rule.update(max_steps=(finish_options or {}).get("max_iterations", 1000),
                    tolerance_angle=1e-4)
    else:
        rule = physik.steps_mode_rule() if mode else {"method": "steps"}
        rule.update(max_steps=scene.steps, tolerance_angle=1e-4)
    rule.update(finish=finish, finish_options=finish_options)
    return session, session.solve(**rule)


# (scene, solver, finish, finish_options, the CLI's flags for those options); hand_tight's
# physics stalls, so its finish runs
CASES = [("pinhead_two_hands", "physik", "none", None, []),
         ("pinhead_two_hands", "physik-steps", "none", None, []),
         ("fig9_outstretched", "physik-explicit", "none", None, []),
         ("fig11_sit", "physik", "none", None, []),
         ("fig11_sit", "physik-steps", "none", None, []),
         ("hand_tight", "physik", "dls", None, []),
         ("hand_tight", "physik", "ccd", {"max_iterations": 7, "respect_limits": False},
          ["--max-iterations", "7", "--no-limits"]),
         ("hand_tight", "physik", "dls", {"lambda": 0.05, "jacobian": "fd"},
          ["--lambda", "0.05", "--jacobian", "fd"])]


@pytest.mark.parametrize("name,solver,finish,options,flags", CASES,
                         ids=["%s-%s-%s%s" % (c[0], c[1], c[2], "-options" if c[3] else "")
                              for c in CASES])
def test_solve_equals_physik_solve(name, solver, finish, options, flags, tmp):
    path = scene_path(name)
    status, _, err = cli("solve", path, "--solver", solver, "--finish", finish, "--out", tmp,
                         "--quiet", *flags)
    expected = read_json(os.path.join(tmp, "summary.json"))
    assert status == (0 if expected["converged"] else 4), err  # 4: short of its tolerance
    session, r = solve_like_the_cli(physik.Scene.load(path), solver, finish, options)
    assert (r.steps, r.residual, r.tolerance) == (expected["iterations"], expected["residual"],
                                                  expected["residual_tol"])
    assert (r.converged, r.stalled, r.out_of_steps, r.diverged) == (
        expected["converged"], expected["stalled"], expected["out_of_steps"], expected["diverged"])
    assert r.finish_iterations == expected["finish_iterations"]
    summary = session.summary()
    assert summary["final_state_hash"] == expected["final_state_hash"]
    assert without(summary, *SOLVE_KEYS) == without(expected, *SOLVE_KEYS)
    # the pose, bit for bit, as physik.solve (the CLI's C++ path) returns it
    if options:
        assert 0 < r.finish_iterations <= options.get("max_iterations", 1000)
        return
    pose = physik.solve(physik.Scene.load(path), solver, finish=finish).pose
    for field in ("heads", "tails", "orientations", "local_rotations", "root_head",
                  "joint_angles", "limit_excess"):
        assert np.array_equal(getattr(session.pose, field), getattr(pose, field)), field


def test_rule_defaults_and_the_solve_mode_rules():
    rule = physik.solve_mode_rule()
    assert rule["method"] == "equilibrium"
    steps = physik.steps_mode_rule()
    assert steps["method"] == "steps"
    assert steps["dt_growth"] == physik._core._SOLVE_DT_GROWTH > 1
    assert steps["max_dt"] == physik._core._SOLVE_MAX_DT
    # the solve mode's rule is SolveRule's defaults, which solve() takes when not given
    scene = physik.Scene.load(scene_path("pinhead_two_hands"))
    a = physik.PosingSession(scene, solve_mode=True)
    b = physik.PosingSession(scene, solve_mode=True)
    assert a.solve() == b.solve(**rule)
    assert a.solve().method == "equilibrium"
    assert np.array_equal(a.pose.heads, b.pose.heads)
    # the time-stepping rule's growth is its own (the keywords are used)
    c = physik.PosingSession(scene, solve_mode=True)
    growth = {k: steps[k] for k in ("method", "dt_growth", "max_dt")}
    d = physik.PosingSession(scene, solve_mode=True)
    assert c.solve(**growth) == d.solve(**steps)
    e = physik.PosingSession(scene, solve_mode=True)
    assert e.solve(method="steps").steps != c.solve(**steps).steps


def test_advance_and_set_target_are_the_engines_steps_and_schedule():
    # fig11_sit moves its targets by a schedule; a session without the schedule, its targets
    # moved by set_target(interpolate=True) before the step the schedule names, runs the same
    scene = physik.Scene.load(scene_path("fig11_sit"))
    doc = scene.to_dict()
    schedule = doc.pop("schedule")
    assert schedule
    session = physik.PosingSession(physik.Scene.from_dict(doc))
    taken = 0
    for change in sorted(schedule, key=lambda c: c["step"]):
        session.advance(change["step"] - taken)  # the engine applies it once `step` steps are taken
        taken = change["step"]
        session.set_target(change["control_point"], np.array(change["target"]), interpolate=True)
    session.advance(scene.steps - taken)
    sim = physik.Simulation(scene)
    sim.step(scene.steps)
    assert session.step_count == sim.step_count == scene.steps
    for field in ("heads", "tails", "orientations", "local_rotations"):
        assert np.array_equal(getattr(session.pose, field), getattr(sim.pose, field)), field
    assert session.residual() == max(sim.residuals)
    final = [c["target"] for c in sorted(schedule, key=lambda c: c["step"])][-1]
    assert list(session.targets[schedule[-1]["control_point"]]) == final


def test_a_jump_moves_the_pull_at_once():
    scene = physik.Scene.load(scene_path("pinhead_two_hands"))
    jump, glide = physik.PosingSession(scene), physik.PosingSession(scene)
    target = jump.targets[0] + np.array([0.0, 0.0, 0.5])
    jump.set_target(0, target)
    glide.set_target(0, target, interpolate=True)
    assert np.array_equal(jump.targets[0], target) and np.array_equal(glide.targets[0], target)
    jump.advance(1)
    glide.advance(1)
    assert not np.array_equal(jump.pose.heads, glide.pose.heads)


def test_set_pose_restarts_the_solve_from_that_pose():
    # a session that has moved, given its scene's initial pose back, solves as a fresh one does
    scene = physik.Scene.load(scene_path("pinhead_two_hands"))
    fresh = physik.PosingSession(scene, solve_mode=True)
    initial = physik.Pose(*(np.array(a) for a in fresh._views()), scene.rig.bone_names)
    moved = physik.PosingSession(scene, solve_mode=True)
    moved.advance(10)
    assert not np.array_equal(moved.pose.heads, initial.heads)
    moved.set_pose(initial)
    assert np.array_equal(moved.pose.local_rotations, initial.local_rotations)
    assert np.allclose(moved.pose.heads, initial.heads, atol=1e-12)
    rule = physik.solve_mode_rule()
    assert moved.solve(**rule) == fresh.solve(**rule)
    assert np.array_equal(moved.pose.heads, fresh.pose.heads)
    # the arrays form, and a pose from another session
    other = physik.PosingSession(scene)
    other.set_pose(np.array(fresh.pose.local_rotations), np.array(fresh.pose.root_head))
    assert np.array_equal(other.pose.local_rotations, fresh.pose.local_rotations)


def test_pose_is_views_of_the_session_state():
    session = physik.PosingSession(physik.Scene.load(scene_path("pinhead_two_hands")))
    pose = session.pose
    for a in (pose.heads, pose.tails, pose.orientations, pose.local_rotations, pose.root_head):
        assert not a.flags.owndata and not a.flags.writeable
    assert np.shares_memory(pose.heads, session.pose.heads)
    before = pose.heads.copy()
    angles = pose.joint_angles
    session.solve(max_steps=40)
    assert not np.array_equal(pose.heads, before)  # the same arrays show the new state
    assert not np.array_equal(pose.joint_angles, angles)  # recomputed when read
    with pytest.raises(ValueError):
        pose.heads[0, 0] = 1.0
    del session
    assert pose.heads.shape == (18, 3) and np.isfinite(pose.heads).all()  # kept alive


def raises_input_error(fn, *args, **kwargs):
    with pytest.raises(physik.InputError) as e:
        fn(*args, **kwargs)
    return str(e.value)


def test_bad_input_is_input_error():
    scene = physik.Scene.load(scene_path("pinhead_two_hands"))
    s = physik.PosingSession(scene)
    assert raises_input_error(s.set_target, 2, [0, 0, 1]) == \
        "set_target: field 'control point': no control point 2 (the scene has 2)"
    assert raises_input_error(s.set_target, -1, [0, 0, 1]).startswith(
        "set_target: field 'control point'")
    for bad in (float("nan"), float("inf"), -float("inf")):
        assert raises_input_error(s.set_target, 0, [0, bad, 1]) == \
            "set_target: field 'target': not finite"
    with pytest.raises(TypeError, match=r"target must be 3 numbers"):
        s.set_target(0, [0, 1])
    with pytest.raises(TypeError, match=r"target must be 3 numbers"):
        s.set_target(0, "abc")
    assert raises_input_error(s.advance, -1) == "advance: field 'steps': must not be negative"
    assert raises_input_error(s.solve, tolerance=-1) == \
        "SolveRule: field 'tolerance': must be finite and >= 0"
    assert raises_input_error(s.solve, stall_steps=-1) == \
        "SolveRule: field 'stall_steps': must not be negative (0: the method's)"
    assert raises_input_error(s.solve, tolerance_angle=float("nan")) == \
        "SolveRule: field 'tolerance_angle': must be finite and >= 0"
    assert raises_input_error(s.solve, method="newton") == \
        "solve: field 'method': unknown method 'newton' (expected equilibrium|steps)"
    assert "needs scheme implicit" in raises_input_error(s.solve, method="steps", dt_growth=2)
    assert raises_input_error(s.solve, finish="newton") == \
        "solve: field 'finish': unknown finish 'newton' (expected none|ccd|dls)"
    assert "unknown field" in raises_input_error(s.solve, finish="dls", finish_options={"lamda": 1})
    assert raises_input_error(s.solve, finish_options={"lambda": 1}) == \
        "solve: field 'finish_options': given without a finish (ccd or dls)"
    assert raises_input_error(s.solve, finish="ccd", finish_options={"max_iterations": -1}) == \
        "solve: finish_options: field 'max_iterations': must not be negative"
    assert raises_input_error(s.summary) == "summary: no solve yet"
    n = scene.rig.nbone
    assert raises_input_error(s.set_pose, np.zeros((3, 4)), np.zeros(3)).startswith(
        "set_pose: field 'local_rotations': shape (3, 4) for a rig of %d bones" % n)
    q = np.tile([0.0, 0.0, 0.0, 2.0], (n, 1))
    assert "not a finite unit quaternion" in raises_input_error(s.set_pose, q, np.zeros(3))
    q[:, 3] = 1.0
    assert raises_input_error(s.set_pose, q, [0, np.nan, 0]) == \
        "set_pose: field 'root_head': not finite"
    assert s.step_count == 0 and s.residual() > 0.1  # nothing changed by the refused calls
    free = physik.Scene.from_dict({"rig": scene.rig.to_dict()})
    assert "a solve needs a goal" in raises_input_error(physik.PosingSession(free).solve)


ALLOC_PROBE = textwrap.dedent("""
    import ctypes, os, sys
    import numpy as np
    import physik
    counter = ctypes.CDLL(os.environ["PHYSIK_ALLOC_COUNTER"])
    counter.physik_alloc_count.restype = ctypes.c_long

    def allocations(call, n=20):
        call()  # a first call may size what it keeps
        counter.physik_alloc_counting(1)
        for _ in range(n):
            call()
        counter.physik_alloc_counting(0)
        return counter.physik_alloc_count() / n

    scene = physik.Scene.load(sys.argv[1])
    s = physik.PosingSession(scene, solve_mode=True)
    rule = physik.solve_mode_rule()
    p = np.array([0.3, 0.2, 1.0])
    local, root = np.array(s.pose.local_rotations), np.array(s.pose.root_head)
    calls = {
        "residual": lambda: s.residual(),
        "set_target": lambda: s.set_target(1, p),
        "set_target_list": lambda: s.set_target(0, [0.3, -0.2, 1.0], interpolate=True),
        "advance": lambda: s.advance(),
        "advance_25": lambda: s.advance(25),
        "solve": lambda: s.solve(**rule),
        "set_pose": lambda: s.set_pose(local, root),
        "pose": lambda: s.pose,
        "scene": lambda: s.scene,
    }
    for name, call in calls.items():
        print(name, allocations(call))
""")


def test_per_frame_calls_allocate_nothing_in_cpp():
    library = os.environ.get("PHYSIK_ALLOC_COUNTER")
    if not library:
        pytest.skip("no allocation counter in this build (a sanitizer build owns operator new)")
    env = dict(os.environ, LD_PRELOAD=library)
    p = subprocess.run([sys.executable, "-c", ALLOC_PROBE, scene_path("pinhead_two_hands")],
                       capture_output=True, text=True, env=env)
    assert p.returncode == 0, p.stderr
    counts = {line.split()[0]: float(line.split()[1]) for line in p.stdout.splitlines()}
    # residual() is a const read: its count is pybind11's own per call (the argument vectors of
    # its dispatcher), which every bound call pays; the session's calls add nothing to it
    base = counts.pop("residual")
    assert base <= 4, base
    assert counts.pop("scene") > base + 10  # a copy of the scene: the counter does count
    assert counts == {name: base for name in counts}, counts
