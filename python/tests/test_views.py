"""Simulation.pose: numpy views of the engine's state, without copying, read-only, alive as long as
they are referenced, following every step bit for bit (checked with the engine's own state hash
recomputed from the views), with the documented quaternion order."""
import gc
import struct
import threading

import numpy as np
import pytest

import physik
from conftest import scene_path


def fnv1a_state_hash(heads, tails, orientations):
    """physik::state_hash (physik/engine/engine.cpp) over the views: FNV-1a over the bytes of
    head[k], tail[k] for k = x, y, z, then the quaternion's x, y, z, w, per bone."""
    h = 1469598103934665603
    for i in range(heads.shape[0]):
        values = []
        for k in range(3):
            values += [heads[i, k], tails[i, k]]
        values += list(orientations[i])
        for b in struct.pack("<%dd" % len(values), *values):
            h = ((h ^ b) * 1099511628211) & 0xFFFFFFFFFFFFFFFF
    return "%016x" % h


def quat_rotate(q, v):
    """Rotate v by the unit quaternion q = (x, y, z, w)."""
    u, w = np.asarray(q[:3]), q[3]
    return v + 2.0 * np.cross(u, np.cross(u, v) + w * v)


@pytest.fixture
def sim():
    return physik.Simulation(physik.Scene.load(scene_path("fig5_running")))


def test_views_have_the_rig_shapes_and_share_the_state(sim):
    pose = sim.pose
    n = sim.scene.rig.nbone
    assert pose.heads.shape == (n, 3) and pose.tails.shape == (n, 3)
    assert pose.orientations.shape == (n, 4) and pose.local_rotations.shape == (n, 4)
    assert pose.root_head.shape == (3,) and pose.bone_names == sim.scene.rig.bone_names
    for a in (pose.heads, pose.tails, pose.orientations, pose.local_rotations, pose.root_head):
        assert a.dtype == np.float64 and not a.flags.owndata
    # no copy: two reads of .pose see the same memory
    again = sim.pose
    assert np.shares_memory(pose.heads, again.heads)
    assert pose.heads.__array_interface__["data"][0] == again.heads.__array_interface__["data"][0]


def test_views_follow_every_step(sim):
    pose = sim.pose
    address = pose.heads.__array_interface__["data"][0]
    before = pose.heads.copy()
    for n in (1, 1, 5, 20):
        sim.step(n)
        # the same array objects now show the new state, bit for bit
        assert fnv1a_state_hash(pose.heads, pose.tails, pose.orientations) == sim.summary["final_state_hash"]
        assert np.array_equal(pose.root_head, pose.heads[0])
    assert pose.heads.__array_interface__["data"][0] == address
    assert not np.array_equal(before, pose.heads)
    sim.run()
    assert fnv1a_state_hash(pose.heads, pose.tails, pose.orientations) == sim.summary["final_state_hash"]


def test_views_refuse_writes(sim):
    pose = sim.pose
    for a in (pose.heads, pose.tails, pose.orientations, pose.local_rotations, pose.root_head):
        assert not a.flags.writeable
        with pytest.raises(ValueError):
            a[0] = 0.0
        with pytest.raises(ValueError):
            a.flags.writeable = True
        with pytest.raises(ValueError):
            np.asarray(a)[...] = 1.0
    with pytest.raises(ValueError):
        np.add(pose.heads, 1.0, out=pose.heads)
    sim.step(3)
    assert fnv1a_state_hash(pose.heads, pose.tails, pose.orientations) == sim.summary["final_state_hash"]


def test_views_keep_the_simulation_alive():
    sim = physik.Simulation(physik.Scene.load(scene_path("fig9_outstretched")))
    sim.step(10)
    expected = sim.summary["final_state_hash"]
    pose = sim.pose
    del sim
    gc.collect()
    assert fnv1a_state_hash(pose.heads, pose.tails, pose.orientations) == expected


def test_quaternion_order_is_xyzw_and_matches_the_bones(sim):
    sim.step(30)
    pose = sim.pose
    lengths = np.array(sim.scene.rig.bone_lengths)
    assert np.allclose(np.linalg.norm(pose.orientations, axis=1), 1.0, atol=1e-12)
    assert np.allclose(np.linalg.norm(pose.local_rotations, axis=1), 1.0, atol=1e-12)
    # a bone's local +Y, turned by its world orientation (x, y, z, w), runs from head to tail
    for i in range(len(lengths)):
        tail = pose.heads[i] + quat_rotate(pose.orientations[i], np.array([0.0, lengths[i], 0.0]))
        assert np.allclose(tail, pose.tails[i], atol=1e-9)
    # with the components read in any other order it would not (the check can fail)
    wxyz = np.roll(pose.orientations, 1, axis=1)
    bad = [i for i in range(len(lengths)) if not np.allclose(
        pose.heads[i] + quat_rotate(wxyz[i], np.array([0.0, lengths[i], 0.0])), pose.tails[i], atol=1e-6)]
    assert bad


def test_local_rotations_at_rest_and_as_blender():
    sim = physik.Simulation(physik.Scene.from_dict(
        {"rig": physik.Rig.chain(3).to_dict(), "control_points": [{"bone": "b2", "target": [1, 0, 2]}]}))
    pose = sim.pose
    assert np.array_equal(pose.local_rotations, np.tile([0.0, 0.0, 0.0, 1.0], (3, 1)))
    sim.step(40)
    root, rotations = pose.as_blender()
    assert root == list(pose.heads[0]) and list(rotations) == ["b0", "b1", "b2"]
    for i, name in enumerate(["b0", "b1", "b2"]):
        x, y, z, w = pose.local_rotations[i]
        assert rotations[name] == (w, x, y, z)
    assert any(abs(r[0]) < 1.0 - 1e-6 for r in rotations.values())  # it moved


def test_run_releases_the_gil():
    # while run() works in one thread, this thread reads the step count; it can see a count
    # strictly between the start and the end only if run() let go of the GIL
    scene = physik.Scene.load(scene_path("pinhead_two_hands"), steps=3000)
    sim = physik.Simulation(scene)
    t = threading.Thread(target=sim.run)
    seen = set()
    t.start()
    while t.is_alive():
        seen.add(sim.step_count)
    t.join()
    assert sim.step_count == 3000
    assert any(0 < k < 3000 for k in seen), sorted(seen)


def log_map(quaternions):
    """Rotation vectors of (n, 4) unit quaternions (x, y, z, w), angle in [0, pi]."""
    q = np.where(quaternions[:, 3:4] < 0.0, -quaternions, quaternions)
    s = np.linalg.norm(q[:, :3], axis=1)
    angle = 2.0 * np.arctan2(s, q[:, 3])
    scale = np.where(s > 1e-12, angle / np.where(s > 1e-12, s, 1.0), 2.0)
    return q[:, :3] * scale[:, None]


def limit_excess(rig, angles):
    """Each angle's signed excess past the rig's limit on its axis (rig.to_dict's limits_deg)."""
    out = np.zeros_like(angles)
    # the root's too: only a pinned root has limits (a free or fixed root has none)
    for i, bone in enumerate(rig.to_dict()["bones"]):
        for k, axis in enumerate("xyz"):
            if axis in bone.get("limits_deg", {}):
                lo, hi = np.radians(bone["limits_deg"][axis])
                a = angles[i, k]
                out[i, k] = a - hi if a > hi else a - lo if a < lo else 0.0
    return out


def test_joint_angles_are_the_log_map_and_their_excess_past_the_limits(sim):
    pose = sim.pose
    assert np.array_equal(pose.joint_angles, np.zeros((sim.scene.rig.nbone, 3)))  # at rest
    sim.step(60)
    angles, excess = pose.joint_angles, pose.limit_excess  # read now: the state after 60 steps
    assert angles.shape == excess.shape == (sim.scene.rig.nbone, 3)
    assert np.allclose(angles, log_map(np.array(pose.local_rotations)), atol=1e-12, rtol=0)
    assert np.abs(angles).max() > 0.1
    assert np.allclose(excess, limit_excess(sim.scene.rig, angles), atol=1e-12, rtol=0)
    assert np.degrees(np.abs(excess).max()) <= sim.summary["max_limit_violation_deg"] + 1e-9
    sim.step(5)
    assert not np.array_equal(pose.joint_angles, angles)  # computed from the state when read


def test_a_pose_past_its_limits_reports_the_excess():
    # CCD without limits bends the pinhead past them; the largest excess is the summary's
    scene = physik.Scene.load(scene_path("pinhead_two_hands"))
    result = physik.solve(scene, "ccd", no_limits=True)
    excess = result.pose.limit_excess
    assert result.summary["max_limit_violation_deg"] > 1.0
    assert abs(np.degrees(np.abs(excess).max()) - result.summary["max_limit_violation_deg"]) < 1e-9
    expected = limit_excess(scene.rig, result.pose.joint_angles)
    assert np.allclose(excess, expected, atol=1e-12, rtol=0)
    assert np.array_equal(excess[0], np.zeros(3))


def axis_quat(deg, axis):
    """The unit quaternion (x, y, z, w) of a turn by deg degrees about a unit axis."""
    half = np.radians(deg) / 2.0
    return np.append(np.sin(half) * np.asarray(axis, float), np.cos(half))


def quat_mul(a, b):
    """The Hamilton product a b of quaternions (x, y, z, w)."""
    va, wa, vb, wb = a[:3], a[3], b[:3], b[3]
    return np.append(wa * vb + wb * va + np.cross(va, vb), wa * wb - va.dot(vb))


@pytest.mark.parametrize("scheme", ["gauss-seidel", "exact", "implicit"])
def test_a_universal_joint_reads_in_the_joints_of_the_scheme(scheme):
    # the elbow with its y axis freed: a universal joint (x, then y; z locked at 0), bent -50 deg
    # about x and turned 40 deg about its y, which is on its set and within its limits. The
    # exact and implicit schemes read its own angles (-50, 40, 0) and no excess; the paper's
    # scheme, where the lock is a torsion spring on a ball, reads the rotation vector, whose z
    # component is several degrees past the lock (physik/model/joint_angles.h)
    rig = {"name": "wrist", "bones": [
        {"name": "upper_arm", "parent": None, "head": [0, 0, 0], "tail": [0, 0, 2]},
        {"name": "forearm", "parent": "upper_arm", "head": [0, 0, 2], "tail": [0, 0, 4],
         "limits_deg": {"x": [-90, 0], "y": [-60, 60], "z": [0, 0]}}]}
    q = quat_mul(axis_quat(-50, [1, 0, 0]), axis_quat(40, [0, 1, 0]))
    rotation_vector = log_map(q[None, :])[0]
    scene = physik.Scene.from_dict({
        "rig": rig, "control_points": [], "params": {"scheme": scheme},
        "initial_pose": {"rotation_deg": {"forearm": list(np.degrees(rotation_vector))}}})
    pose = physik.Simulation(scene).pose
    angles, excess = pose.joint_angles[1], pose.limit_excess[1]
    if scheme == "gauss-seidel":
        assert np.allclose(angles, rotation_vector, atol=1e-12, rtol=0)
        assert np.degrees(abs(excess[2])) > 5.0 and excess[2] == angles[2]
        assert np.array_equal(excess[:2], np.zeros(2))
    else:
        assert np.allclose(np.degrees(angles), [-50, 40, 0], atol=1e-9, rtol=0), angles
        assert np.array_equal(excess, np.zeros(3))
