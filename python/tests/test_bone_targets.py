"""PosingSession's bone targets (orientation targets, aims, pins): set between steps, they are the
scene file's targets (the same steps, bit for bit), they turn and hold the bones they name, and
their bad input is the scene file's InputError; the scene-level solve and Simulation take scenes
that carry them."""
import json

import numpy as np
import pytest

import physik
from conftest import scene_path


def quat_angle(a_xyzw, b_wxyz):
    """The angle (rad) between a session orientation (x, y, z, w) and a target (w, x, y, z)."""
    a = np.array([a_xyzw[3], a_xyzw[0], a_xyzw[1], a_xyzw[2]])
    return 2.0 * np.arccos(min(1.0, abs(float(np.dot(a, b_wxyz)))))


def turned(q_xyzw, axis, angle):
    """(w, x, y, z) of the rotation by `angle` about world `axis`, applied after q."""
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    r = np.concatenate([[np.cos(angle / 2)], np.sin(angle / 2) * axis])
    q = np.array([q_xyzw[3], q_xyzw[0], q_xyzw[1], q_xyzw[2]])
    w1, v1, w2, v2 = r[0], r[1:], q[0], q[1:]
    return np.concatenate([[w1 * w2 - v1 @ v2], w1 * v2 + w2 * v1 + np.cross(v1, v2)])


def pinhead(preset="robust"):
    """pinhead_two_hands under `preset` (robust: the implicit step with damping auto settles in
    its 400 steps; the paper's scheme at its dt still swings a turned head at step 400)."""
    scene = physik.Scene.load(scene_path("pinhead_two_hands"))
    if preset:
        scene.update(params={"preset": preset})
    return scene


def test_an_orientation_target_turns_its_bone_as_the_scene_files_does():
    scene = pinhead()
    session, free = physik.PosingSession(scene), physik.PosingSession(scene)
    # the head (no control point on it) turned 0.6 rad about world z from where it starts
    b = scene.rig.find_bone("head")
    target = turned(session.pose.orientations[b], [0, 0, 1], 0.6)
    session.set_orientation_target("head", target, k=5.0)
    assert session.bone_targets["orientation_targets"][0]["bone"] == "head"
    start = quat_angle(session.pose.orientations[b], target)
    assert abs(start - 0.6) < 1e-9
    session.advance(400)
    free.advance(400)
    # at rest the head is on its target frame; without the target it stays about 0.6 rad off
    ended = quat_angle(session.pose.orientations[b], target)
    without = quat_angle(free.pose.orientations[b], target)
    assert ended < 0.02 * start and without > 0.5 * start, (start, ended, without)
    # the same target in the scene file: the same steps, bit for bit
    doc = scene.to_dict()
    doc["orientation_targets"] = [{"bone": "head", "quaternion": list(target), "k": 5.0}]
    sim = physik.Simulation(physik.Scene.from_dict(doc))
    sim.step(400)
    assert np.array_equal(sim.pose.heads, session.pose.heads)
    assert np.array_equal(sim.pose.orientations, session.pose.orientations)


def test_a_pin_holds_under_a_pull():
    # hand.L's head pinned where it starts while its tip is pulled to a target out of reach from
    # there: the pin carries the pull, and (pins.h: 100 control_k) gives way by at most 1/100 of
    # the control spring's stretch
    scene = pinhead()
    pinned, free = physik.PosingSession(scene), physik.PosingSession(scene)
    b = scene.rig.find_bone("hand.L")
    start = pinned.pose.heads[b].copy()
    pinned.set_pin("hand.L")
    assert pinned.bone_targets["pins"] == [{"bone": "hand.L", "alpha": 0.0, "point": list(start)}]
    pinned.advance(400)
    free.advance(400)
    stretch = pinned.residual()  # the hand's tip short of its target, loading the pin
    moved_pinned = np.linalg.norm(pinned.pose.heads[b] - start)
    moved_free = np.linalg.norm(free.pose.heads[b] - start)
    assert stretch > 0.1 * scene.rig.height and moved_free > 0.1 * scene.rig.height
    assert 0.0 < moved_pinned <= 1.001 * stretch / 100.0, (moved_pinned, stretch, moved_free)
    # cleared, and the elbow (forearm.L's head) pinned 0.1 above where it is: it goes there
    assert pinned.clear_pin("hand.L") and not pinned.clear_pin("hand.L")
    e = scene.rig.find_bone("forearm.L")
    goal = pinned.pose.heads[e] + np.array([0.0, 0.0, 0.1])
    pinned.set_pin("forearm.L", goal)
    assert [p["bone"] for p in pinned.bone_targets["pins"]] == ["forearm.L"]
    pinned.advance(400)
    assert np.linalg.norm(pinned.pose.heads[e] - goal) < 1e-3 * scene.rig.height


def test_an_aim_turns_the_axis_toward_its_point_and_clear_removes():
    scene = pinhead()
    s = physik.PosingSession(scene)
    b = scene.rig.find_bone("head")
    point = s.pose.heads[b] + np.array([1.0, 0.0, 0.0])  # along +x from the head's head

    def misalignment():
        axis = s.pose.tails[b] - s.pose.heads[b]
        to = point - s.pose.heads[b]
        return np.arccos(np.dot(axis, to) / np.linalg.norm(axis) / np.linalg.norm(to))

    before = misalignment()
    s.set_aim_target("head", point, k=5.0)
    s.advance(400)
    assert misalignment() < 0.5 * before, (before, misalignment())
    assert s.clear_aim_target("head") is True
    assert s.clear_aim_target("head") is False
    assert s.bone_targets == {"orientation_targets": [], "aim_targets": [], "pins": []}


def raises_input_error(fn, *args, **kwargs):
    with pytest.raises(physik.InputError) as e:
        fn(*args, **kwargs)
    return str(e.value)


def test_bad_bone_targets_are_input_errors():
    s = physik.PosingSession(pinhead())
    assert isinstance(physik.InputError("x"), ValueError)
    assert raises_input_error(s.set_orientation_target, "hand.L", [0, 0, 0, 0]) == \
        "set_orientation_target: field 'quaternion': zero quaternion: give a unit [w, x, y, z]"
    assert "not a unit quaternion (norm 2, more than 1e-3 from 1)" in raises_input_error(
        s.set_orientation_target, "hand.L", [2, 0, 0, 0])
    assert raises_input_error(s.set_orientation_target, "hand.X", [1, 0, 0, 0]).startswith(
        "set_orientation_target: field 'bone': unknown bone 'hand.X' (did you mean 'hand.L'?)")
    assert "'spring': unknown spring law 'stiff'" in raises_input_error(
        s.set_orientation_target, "hand.L", [1, 0, 0, 0], spring="stiff")
    assert "field 'k'" in raises_input_error(s.set_orientation_target, "hand.L", [1, 0, 0, 0], k=-1)
    head = s.pose.heads[s.scene.rig.find_bone("hand.L")]
    assert "rig units from the head of bone 'hand.L'" in raises_input_error(
        s.set_aim_target, "hand.L", head)
    near = [head[0] + 1e-5, head[1], head[2]]  # 1e-5 off the head: no direction to speak of
    assert "lies 1e-05 rig units from the head of bone 'hand.L': an aim's point must be at least " \
        "0.1 of its bone's length" in raises_input_error(s.set_aim_target, "hand.L", near)
    assert "field 'axis'" in raises_input_error(s.set_aim_target, "hand.L", [0, 0, 9],
                                                axis=[0, 0, 0])
    assert "field 'alpha'" in raises_input_error(s.set_pin, "hand.L", alpha=2)
    assert "above 0" in raises_input_error(s.set_pin, "hand.L", k=0)
    with pytest.raises(TypeError, match=r"quaternion must be 4 numbers \(w, x, y, z\)"):
        s.set_orientation_target("hand.L", [1, 0, 0])
    assert s.bone_targets == {"orientation_targets": [], "aim_targets": [], "pins": []}
    # a welded bone: pin its weld
    rig = {"name": "welded", "bones": [
        {"name": "pelvis", "parent": None, "head": [0, 0, 1], "tail": [0, 0, 1.2]},
        {"name": "spine", "parent": "pelvis", "head": [0, 0, 1.2], "tail": [0, 0, 1.6]},
        {"name": "chest", "parent": "spine", "head": [0, 0, 1.6], "tail": [0, 0, 1.8],
         "weld": "spine"}]}
    w = physik.PosingSession(physik.Scene.from_dict({"rig": rig, "control_points": []}))
    assert raises_input_error(w.set_pin, "chest") == \
        "set_pin: field 'bone': 'chest' is welded to 'spine': pin the bone it is welded to"
    w.set_pin("spine")


def test_a_pin_holds_under_the_full_linearisation():
    # the pose-terms step reads the bone targets through the force list (forces.h pose_forces):
    # the pin of test_a_pin_holds_under_a_pull, with implicit_linearisation full, holds as well
    doc = pinhead().to_dict()
    doc["params"] = {"scheme": "implicit", "implicit_linearisation": "full"}
    full = physik.PosingSession(physik.Scene.from_dict(doc))
    b = full.scene.rig.find_bone("hand.L")
    start = full.pose.heads[b].copy()
    full.set_pin("hand.L")
    full.advance(400)
    stretch = full.residual()
    moved = np.linalg.norm(full.pose.heads[b] - start)
    assert stretch > 0.1 * full.scene.rig.height
    assert 0.0 < moved <= 1.001 * stretch / 100.0, (moved, stretch)


def test_the_scene_level_solve_takes_bone_targets():
    doc = pinhead().to_dict()
    doc["pins"] = [{"bone": "forearm.L"}]
    scene = physik.Scene.from_dict(doc)
    start = physik.Simulation(scene).pose.heads[scene.rig.find_bone("forearm.L")].copy()
    result = physik.solve(scene, "physik")
    # the solve holds the elbow where it was while the hand reaches
    moved = np.linalg.norm(result.pose.heads[scene.rig.find_bone("forearm.L")] - start)
    free = physik.solve(pinhead(), "physik")
    moved_free = np.linalg.norm(free.pose.heads[scene.rig.find_bone("forearm.L")] - start)
    assert moved < 0.05 * moved_free, (moved, moved_free)


def test_a_solve_waits_for_its_turning_targets():
    # The solve judges each goal by its own measure (measures.h): the control points' distances
    # against tol, the orientation targets' and aims' angles against tol_angle (rad). A scene
    # whose only goal is a head turned 0.5 rad about world z converges with the head turned onto
    # it; a scene whose control points are already met does not stop before its orientation
    # target is
    doc = pinhead().to_dict()
    session = physik.PosingSession(physik.Scene.from_dict(doc))
    b = session.scene.rig.find_bone("head")
    length = session.scene.rig.bone_lengths[b]
    target = turned(session.pose.orientations[b], [0, 0, 1], 0.5)
    only = dict(doc, control_points=[],
                orientation_targets=[{"bone": "head", "quaternion": list(target)}])
    result = physik.solve(physik.Scene.from_dict(only), "physik")
    tol = result.summary["residual_tol_angle"]
    assert result.summary["converged"] and tol == 1e-4
    [turn] = result.summary["orientation_residuals_rad"]
    assert turn < tol, (turn, length, tol)
    assert result.summary["short_goals"] == []
    # the hands' tips' targets where the tips start (met at step 0), the head's turn still to make
    rig = session.scene.rig
    tips = [session.pose.tails[rig.find_bone(cp["bone"])] for cp in doc["control_points"]]
    assert all(cp["alpha"] == 1.0 for cp in doc["control_points"])
    both = dict(only, control_points=[dict(cp, target=list(t))
                                      for cp, t in zip(doc["control_points"], tips)])
    with_turn = physik.solve(physik.Scene.from_dict(both), "physik")
    assert with_turn.summary["converged"] and with_turn.summary["iterations"] > 1
    [turn] = with_turn.summary["orientation_residuals_rad"]
    assert turn < with_turn.summary["residual_tol_angle"], turn
    assert max(with_turn.summary["final_residuals"]) < with_turn.summary["residual_tol"]


def test_an_aim_without_an_axis_turns_the_bones_forward_axis(tmp_path):
    """A rig whose bone has a forward axis (rig file `bones[].forward`, as `rig from-bvh` gives a
    human skeleton's face and palms): set_aim_target without an axis takes it, with one keeps the
    given axis; a bone without one aims along itself (+Y)."""
    rig = {"bones": [
        {"name": "neck", "parent": None, "head": [0, 0, 0], "tail": [0, 0, 0.1]},
        {"name": "head", "parent": "neck", "head": [0, 0, 0.1], "tail": [0, 0, 0.3],
         "forward": [0, 0, 2]}]}
    (tmp_path / "rig.json").write_text(json.dumps(rig))
    (tmp_path / "scene.json").write_text('{"rig": "rig.json", "steps": 10}')
    s = physik.PosingSession(physik.Scene.load(str(tmp_path / "scene.json")))
    s.set_aim_target("head", [1.0, 0.0, 0.2])
    s.set_aim_target("neck", [1.0, 0.0, 0.0])
    axes = {a["bone"]: a["axis"] for a in s.bone_targets["aim_targets"]}
    assert axes == {"head": [0.0, 0.0, 1.0], "neck": [0.0, 1.0, 0.0]}, axes
    s.set_aim_target("head", [1.0, 0.0, 0.2], axis=[1.0, 0.0, 0.0])
    axes = {a["bone"]: a["axis"] for a in s.bone_targets["aim_targets"]}
    assert axes["head"] == [1.0, 0.0, 0.0], axes


def test_typed_quaternion_is_normalised_with_one_warning():
    """(0.7071, 0.7071, 0, 0), norm 0.99999, as a person types it: normalised, and said once as
    an InputWarning naming the method and the norm; 1e-3 from unit and beyond: InputError."""
    s = physik.PosingSession(pinhead())
    with pytest.warns(physik.InputWarning) as record:
        s.set_orientation_target("hand.L", [0.7071, 0.7071, 0, 0])
    assert [str(w.message) for w in record] == [
        "set_orientation_target: field 'quaternion': norm 0.99999041 (within 1e-3 of 1): "
        "normalised to unit"]
    q = s.bone_targets["orientation_targets"][0]["quaternion"]
    assert abs(np.linalg.norm(q) - 1.0) < 1e-15 and abs(q[0] - q[1]) < 1e-15, q
    assert "norm 1.0011, more than 1e-3 from 1" in raises_input_error(
        s.set_orientation_target, "hand.L", [1.0011, 0, 0, 0])
    # the scene's reader says it as the CLI does, naming the dict and the element
    d = pinhead().to_dict()
    d["orientation_targets"] = [{"bone": "hand.R", "quaternion": [0.7071, 0, 0.7071, 0]}]
    with pytest.warns(physik.InputWarning, match=r"<scene dict>: orientation_targets\[0\]: "
                      r"field 'quaternion': norm 0.99999041"):
        physik.Scene.from_dict(d)
    assert "unknown bone 'hnad.R' (did you mean 'hand.R'?)" in raises_input_error(
        s.set_aim_target, "hnad.R", [0, -5, 1])
