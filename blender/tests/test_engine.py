"""Headless tests of the add-on with the engine plugged in (ctest: blender_engine):

    blender -b --factory-startup --python-exit-code 1 --python blender/tests/test_engine.py -- \
        --repo . --pythonpath build/python --binary build/physik

The add-on reaches `import physik` (on --pythonpath). What is checked:
  - Solve on Fig 9's control points (pinhead built from models/rigs/pinhead.json, the panel's
    k = 30 as the scene's): the engine's final state in Blender is `physik simulate`'s on the
    same scene dict (identical final_state_hash; every bone's world head and tail to 1e-9 from
    final_pose.csv, written with 10 significant digits), and the operator leaves the armature in
    that pose (1e-5: Blender keeps poses in single precision);
  - Bake keys the frames of every N-th step and the last, in the engine's poses;
  - a live simulation's n-step calls follow the same states as one run;
  - the panel's presets, fields and defaults are the engine's parameter table's;
  - Solve reports INFO when converged, a WARNING with the largest residual when not;
  - damping 'auto' with the implicit step solves (the engine's damping_auto); a diverged Solve or
    Bake gives one Blender error, nothing changed;
  - Collide: the scene dict's floor and self-collision run in the engine as in `physik simulate`
    (the same final_state_hash), whose run folder records the ground contacts; the arm pulled
    toward a target below the floor stays on it (its capsules sink less than 0.05 rig units
    into it) where without Collide it goes through; a cube in "PhysIK Obstacles" under its way
    down holds it on the cube's top (as `physik simulate` runs the scene), where the floor alone
    lets it lower;
  - Blender's undo works across Solve, Bake and Reset: each operator, called as the panel's
    button calls it (with an undo push: bpy.ops.physik.solve('EXEC_DEFAULT', True)), is one undo
    step; bpy.ops.ed.undo() returns the armature to exactly the pose before it (the channels and
    the posed heads and tails compare equal: the memfile undo restores the stored floats; Bake's
    keyframes are gone) and bpy.ops.ed.redo() gives exactly the operator's result again.
    Headless (-b) Blender keeps a real undo stack (a window manager with one window is set up);
    tests/test_window.py does the same with real Ctrl+Z key events in a window (Xvfb).
"""
import csv
import json
import math
import os
import subprocess
import sys
import tempfile
import unittest

import bpy
from mathutils import Quaternion, Vector


sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from blender_harness import box_mesh, clear_scene, enable_addon, script_args  # noqa: E402

ARGS = script_args(
    (["--pythonpath"], {"required": True, "help": "the folder holding the physik package"}),
    (["--binary"], {"required": True, "help": "the physik CLI"}))
REPO = os.path.abspath(ARGS.repo)
enable_addon(REPO, "test_engine.py", ARGS.pythonpath)

from physik_addon import (armature_io, bone_targets, control_points, engine,  # noqa: E402
                          operators, rig_format, scene_dict, settings)

ENGINE_TOL = 1e-9  # rig units: the engine's arrays against the CLI's final_pose.csv
POSED_TOL = 1e-5   # rig units: Blender's single-precision posed bones against the engine


def run_op(op, **kw):
    """Run an operator; None on success or the error report's text."""
    try:
        op(**kw)
        return None
    except RuntimeError as e:
        return str(e)




def fig9_armature():
    """pinhead with Fig 9's control points and params (models/scenes/fig9_outstretched.json)."""
    with open(os.path.join(REPO, "models", "scenes", "fig9_outstretched.json")) as f:
        doc = json.load(f)
    rig = rig_format.load_rig(os.path.join(REPO, "models", "rigs", "pinhead.json"))
    arm = armature_io.rig_to_armature(rig, bpy.context)
    for cp in doc["control_points"]:
        control_points.add_control_point(bpy.context, arm, cp["bone"], cp["alpha"], cp["target"],
                                         name=cp["name"])
    s = bpy.context.scene.physik
    s.preset = doc["params"]["preset"]
    s.control_k = doc["params"]["control_k"]
    s.max_steps = doc["steps"]
    bpy.context.view_layer.objects.active = arm
    return arm


def simulate_cli(scene, tmp):
    """`physik simulate` on the scene dict: (summary, {bone: (head, tail)})."""
    path = os.path.join(tmp, "scene.json")
    with open(path, "w") as f:
        json.dump(scene, f)
    out = os.path.join(tmp, "out")
    p = subprocess.run([ARGS.binary, "simulate", path, "--out", out, "--quiet"],
                       capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    with open(os.path.join(out, "summary.json")) as f:
        summary = json.load(f)
    with open(os.path.join(out, "final_pose.csv")) as f:
        bones = {r["bone"]: ([float(r["head_" + a]) for a in "xyz"],
                             [float(r["tail_" + a]) for a in "xyz"]) for r in csv.DictReader(f)}
    return summary, bones


def posed_world(arm):
    bpy.context.view_layer.update()
    return {name: (h.copy(), t.copy()) for name, _, h, t in armature_io.posed_bones_world(arm)}


class Base(unittest.TestCase):
    def setUp(self):
        if bpy.context.object is not None and bpy.context.object.mode != 'OBJECT':
            bpy.ops.object.mode_set(mode='OBJECT')
        clear_scene()
        bpy.context.scene.physik.preset = "original"


class TestSettingsFromTheEngine(Base):
    """The panel's presets, fields and defaults are the engine's parameter table's."""

    def setUp(self):
        super().setUp()
        self.table = engine.param_table()
        self.rows = {r["name"]: r for r in self.table["params"]}
        self.s = bpy.context.scene.physik

    def assert_fields_hold(self, preset):
        for name in settings.PANEL_ROWS:
            want = self.rows[name]["defaults"][preset]
            got = getattr(self.s, name)
            if isinstance(want, float):
                self.assertAlmostEqual(got, want, delta=1e-7 * abs(want), msg=(preset, name))
            else:
                self.assertEqual(got, want, (preset, name))
        auto = self.rows["damping_auto"]["defaults"][preset]
        self.assertEqual(self.s.damping_mode, 'AUTO' if auto else 'VALUE', preset)

    def test_the_panel_has_every_row_it_shows(self):
        for name in settings.PANEL_ROWS + ("damping_auto",):
            self.assertIn(name, self.rows)  # a renamed row fails here, not silently
        for name in settings.PANEL_ROWS:
            if self.rows[name]["kind"] == "choice":
                items = self.s.bl_rna.properties[name].enum_items.keys()
                self.assertEqual(list(items), self.rows[name]["choices"], name)

    def test_a_new_scene_has_the_engines_default_preset(self):
        default = self.table["default_preset"]
        fresh = bpy.data.scenes.new("fresh")
        try:
            self.s = fresh.physik
            self.assertEqual(self.s.preset, default)
            self.assert_fields_hold(default)
            self.assertEqual(settings.params_dict(self.s), {"preset": default})
        finally:
            bpy.data.scenes.remove(fresh)

    def test_each_preset_fills_the_fields(self):
        presets = [p for p, _, _ in settings._preset_items(self.table)]
        self.assertEqual(presets, self.table["presets"])
        for preset in presets + presets[:1]:
            self.s.preset = preset
            self.assert_fields_hold(preset)
            self.assertEqual(settings.params_dict(self.s), {"preset": preset})

    def test_changed_fields_are_sent(self):
        self.s.preset = "original"
        self.s.control_k = self.rows["control_k"]["defaults"]["original"] + 2.0
        self.s.control_spring = "capped"
        p = settings.params_dict(self.s)
        self.assertEqual((p["control_k"], p["control_spring"]),
                         (self.s.control_k, "capped"))
        self.s.damping_mode = 'AUTO'
        self.assertEqual(settings.params_dict(self.s)["damping"], "auto")
        self.s.damping_mode = 'VALUE'
        self.s.damping = 5.0
        self.assertEqual(settings.params_dict(self.s)["damping"], 5.0)


class TestSolve(Base):
    def test_engine_is_reachable(self):
        self.assertTrue(engine.available())

    def test_fig9_solve_equals_simulate(self):
        arm = fig9_armature()
        scene = scene_dict.build_scene(bpy.context, arm, solve=True)
        (head, rotations), summary = engine.solve(scene)
        self.assertTrue(summary["converged"], summary)
        with tempfile.TemporaryDirectory() as tmp:
            cli, bones = simulate_cli(scene, tmp)
        self.assertEqual(summary["final_state_hash"], cli["final_state_hash"])
        self.assertEqual(summary["steps_run"], cli["steps_run"])
        names = [b["name"] for b in scene["rig"]["bones"]]
        self.assertEqual(sorted(names), sorted(bones))
        worst = 0.0
        for i, name in enumerate(names):
            ends = (summary["heads_world"][i], summary["tails_world"][i])
            for got, want in zip(ends, bones[name]):
                worst = max(worst, max(abs(a - b) for a, b in zip(got, want)))
        self.assertLess(worst, ENGINE_TOL)
        print("\nFig 9 Solve: %d steps, engine in Blender vs physik simulate: same state hash, "
              "largest head/tail difference %.2e" % (summary["steps_run"], worst))

    def test_solve_operator_poses_the_armature(self):
        arm = fig9_armature()
        scene = scene_dict.build_scene(bpy.context, arm, solve=True)
        _, summary = engine.solve(scene)
        self.assertIsNone(run_op(bpy.ops.physik.solve))
        posed = posed_world(arm)
        worst = 0.0
        for i, b in enumerate(scene["rig"]["bones"]):
            h, t = posed[b["name"]]
            worst = max(worst, (h - Vector(summary["heads_world"][i])).length,
                        (t - Vector(summary["tails_world"][i])).length)
        self.assertLess(worst, POSED_TOL)
        # the hand reached its target (the scene's residual tolerance: 1e-3 x height)
        hand = posed["hand.R"][1]
        self.assertLess((hand - Vector((-2.4, -0.6, 1.5))).length, summary["residual_tol"])


class TestBoneTargets(Base):
    def elbow(self):
        """elbow (upright from the origin) with its root head held at the origin."""
        rig = rig_format.load_rig(os.path.join(REPO, "models", "rigs", "elbow.json"))
        arm = armature_io.rig_to_armature(rig, bpy.context)
        control_points.add_control_point(bpy.context, arm, "upper_arm", 0.0, (0, 0, 0))
        bpy.context.view_layer.objects.active = arm
        bpy.context.scene.physik.preset = "robust"
        bpy.context.scene.physik.max_steps = 2000
        return arm

    def test_the_empty_frame_is_the_engines_bone_frame(self):
        # an orientation target made at the bone's frame now is the engine's frame of that bone
        # at the start: Blender's bone matrix and the rig's bone frame are one convention. The
        # paper's scheme keeps the forearm a ball (its locked axes springs), so that a turn about
        # every axis is its start; the exact and implicit schemes make it a hinge
        arm = self.elbow()
        bpy.context.scene.physik.preset = "original"
        armature_io.apply_pose(arm, (0.0, 0.0, 0.0),
                               {"forearm": Quaternion(Vector((1, 2, 0.5)).normalized(), 0.7)})
        bone_targets.add_orientation_target(bpy.context, arm, "forearm")
        scene = scene_dict.build_scene(bpy.context, arm)
        physik = engine.module()
        sim = physik.Simulation(physik.Scene.from_dict(scene))
        x, y, z, w = sim.pose.orientations[1]
        (o,) = scene["orientation_targets"]
        # q and -q are one rotation
        dot = abs(sum(a * b for a, b in zip(o["quaternion"], (w, x, y, z))))
        self.assertLess(2.0 * math.acos(min(1.0, dot)), 1e-5, (o["quaternion"], (w, x, y, z)))

    def test_a_turned_empty_turns_its_bone_and_an_aim_empty_aims_it(self):
        arm = self.elbow()
        target = bone_targets.add_orientation_target(
            bpy.context, arm, "forearm", Quaternion((1, 0, 0), math.radians(60)), k=50.0)
        scene = scene_dict.build_scene(bpy.context, arm, solve=True)
        self.assertIsNone(run_op(bpy.ops.physik.solve))
        # the forearm's +Y (head to tail) turned to the empty's +Y: 60 deg from upright at start
        posed = posed_world(arm)
        h, t = posed["forearm"]
        want = target.matrix_world.to_3x3() @ Vector((0, 1, 0))
        angle = math.degrees((t - h).angle(want))
        self.assertLess(angle, 5.0, (angle, scene["orientation_targets"]))
        # the empty moved off: an aim empty at (0, 3, 2) turns it there instead
        bpy.data.objects.remove(target)
        bone_targets.add_aim_target(bpy.context, arm, "forearm", (0.0, 3.0, 2.0), k=50.0)
        self.assertIsNone(run_op(bpy.ops.physik.solve))
        h, t = posed_world(arm)["forearm"]
        angle = math.degrees((t - h).angle(Vector((0.0, 3.0, 2.0)) - h))
        self.assertLess(angle, 5.0, angle)


class TestCollide(Base):
    def arm_pulled_down(self, collide):
        """elbow (upright from the origin, 4 long) with its root head held and its forearm's tail
        pulled toward (0, 3, -1.5), below the floor Collide puts at -0.12; engine.solve's
        (scene, summary)."""
        rig = rig_format.load_rig(os.path.join(REPO, "models", "rigs", "elbow.json"))
        arm = armature_io.rig_to_armature(rig, bpy.context)
        control_points.add_control_point(bpy.context, arm, "upper_arm", 0.0, (0, 0, 0))
        control_points.add_control_point(bpy.context, arm, "forearm", 1.0, (0, 3, -1.5))
        bpy.context.view_layer.objects.active = arm
        s = bpy.context.scene.physik
        # the implicit step: the explicit schemes need dt < 0.01 s with contacts (models/README.md)
        s.preset, s.collide, s.max_steps = "robust", collide, 400
        try:
            scene = scene_dict.build_scene(bpy.context, arm)
        finally:
            s.collide = False
        return scene, engine.solve(scene)[1]

    def test_the_floor_holds_the_arm_as_the_cli_runs_it(self):
        scene, summary = self.arm_pulled_down(True)
        floor = scene["ground"]["height"]
        self.assertAlmostEqual(floor, -0.12, delta=1e-9)
        lowest = min(min(h[2], t[2]) for h, t in zip(summary["heads_world"],
                                                     summary["tails_world"]))
        self.assertGreater(lowest - 0.12, floor - 0.05)  # the capsules' bottoms (0.06 x 2)
        with tempfile.TemporaryDirectory() as tmp:
            cli_summary, _ = simulate_cli(scene, tmp)
            self.assertEqual(cli_summary["final_state_hash"], summary["final_state_hash"])
            with open(os.path.join(tmp, "out", "contacts.csv")) as f:
                rows = list(csv.DictReader(f))
        last = [r for r in rows if int(r["step"]) == cli_summary["steps_run"]]
        self.assertTrue(last and all(r["other_bone"] == "-1" for r in last), last)

    def test_an_obstacle_box_holds_the_arm_above_the_floor(self):
        # a cube in "PhysIK Obstacles" under the forearm's way down: 2 wide in x, from y = 0.5
        # to 4, its top at z = 0.5; the forearm's tail (its capsule 0.12) comes to rest on the
        # top, sinking less than 0.05 into it, where the floor alone lets it down to about 0
        step = box_mesh("step")
        step.location, step.scale = (0, 2.25, 0.25), (1, 1.75, 0.25)
        scene, summary = self.arm_pulled_down(True)
        self.assertEqual(scene["obstacles"], [{"name": "step", "box": {
            "center": [0.0, 2.25, 0.25], "half_extents": [1.0, 1.75, 0.25],
            "rotation_deg": [0.0, 0.0, 0.0]}}])
        tail = summary["tails_world"][1]  # the forearm's
        self.assertTrue(0.5 < tail[1] < 4, tail)  # over the box
        self.assertGreater(tail[2] - 0.12, 0.5 - 0.05, tail)
        self.assertLess(tail[2] - 0.12, 0.5 + 0.05, tail)  # on it, not held up above it
        with tempfile.TemporaryDirectory() as tmp:
            cli_summary, _ = simulate_cli(scene, tmp)
        self.assertEqual(cli_summary["final_state_hash"], summary["final_state_hash"])
        clear_scene()  # the box too
        floor_scene, floor_only = self.arm_pulled_down(True)
        self.assertNotIn("obstacles", floor_scene)
        self.assertLess(floor_only["tails_world"][1][2], 0.5, floor_only["tails_world"])

    def test_without_collide_the_arm_goes_through(self):
        scene, summary = self.arm_pulled_down(False)
        self.assertNotIn("ground", scene)
        self.assertLess(min(t[2] for t in summary["tails_world"]), -0.5)


class TestBakeAndLive(Base):
    def test_bake_keys_every_n_steps_in_the_engines_poses(self):
        arm = fig9_armature()
        s = bpy.context.scene.physik
        s.max_steps, s.bake_every = 22, 5
        bpy.context.scene.frame_set(3)
        poses = engine.trajectory(scene_dict.build_scene(bpy.context, arm), 22)
        self.assertEqual(len(poses), 23)
        self.assertIsNone(run_op(bpy.ops.physik.bake))
        fc = arm.animation_data.action.fcurves
        keyed = sorted({round(k.co[0]) for f in fc for k in f.keyframe_points})
        self.assertEqual(keyed, [3, 4, 5, 6, 7, 8])  # steps 0, 5, 10, 15, 20 and the last, 22
        for frame, step in zip(keyed, (0, 5, 10, 15, 20, 22)):
            bpy.context.scene.frame_set(frame)
            head, rotations = armature_io.read_pose(arm)
            self.assertLess((head - Vector(poses[step][0])).length, POSED_TOL, frame)
            for name, q in poses[step][1].items():
                got = rotations[name]
                d = min(sum((a - b) ** 2 for a, b in zip(got, q)),
                        sum((a + b) ** 2 for a, b in zip(got, q))) ** 0.5
                self.assertLess(d, 1e-5, (frame, name))

    def test_live_steps_follow_one_run(self):
        arm = fig9_armature()
        scene = scene_dict.build_scene(bpy.context, arm)
        live = engine.Live(scene)
        for _ in range(4):
            pose = live.step(10)
        self.assertEqual(live.sim.step_count, 40)
        physik = engine.module()
        ref = physik.Simulation(physik.Scene.from_dict(scene))
        ref.step(40)
        self.assertEqual(live.sim.summary["final_state_hash"], ref.summary["final_state_hash"])
        self.assertEqual(pose, ref.pose.as_blender())


class TestEngineErrors(Base):
    def test_simulate_in_background_mode_is_one_report(self):
        # no event loop in -b: the modal operator would never step (tests/test_window.py runs it)
        arm = fig9_armature()
        before = armature_io.read_pose(arm)[0].copy()
        msg = run_op(bpy.ops.physik.simulate)
        self.assertIsNotNone(msg)
        self.assertIn("background mode", msg)
        self.assertNotIn("Traceback", msg)
        self.assertLess((armature_io.read_pose(arm)[0] - before).length, 1e-12)


    def test_auto_damping_and_implicit_solve(self):
        # the panel's Auto is the engine's damping_auto; Implicit its implicit step: both solve
        arm = fig9_armature()
        s = bpy.context.scene.physik
        s.damping_mode = 'AUTO'
        s.scheme = 'implicit'
        before = armature_io.read_pose(arm)[0].copy()
        self.assertIsNone(run_op(bpy.ops.physik.solve))
        self.assertGreater((armature_io.read_pose(arm)[0] - before).length, 1e-3)
        scene = scene_dict.build_scene(bpy.context, arm, solve=True)
        self.assertEqual(scene["params"]["damping"], "auto")
        sim = engine._simulation(scene)
        sim.run()
        self.assertGreater(sim.summary["damping_auto_value"], 0.0)
        self.assertFalse(sim.summary["diverged"])

    def test_divergence_is_one_error_and_nothing_applied(self):
        arm = fig9_armature()
        s = bpy.context.scene.physik
        s.damping, s.control_k = 0.0, 1e6  # stiff springs, no damping, dt 0.05: explodes
        before = snapshot(arm.name)
        for op in (bpy.ops.physik.solve, bpy.ops.physik.bake):
            msg = run_op(op)
            self.assertIsNotNone(msg, op)
            self.assertIn("diverged", msg)
            self.assertNotIn("Traceback", msg)
            self.assertEqual(operators.LAST_REPORT["level"], 'ERROR')
            self.assertEqual(snapshot(arm.name), before)  # every channel, exactly
        self.assertNotIn(operators.START_POSE, arm)
        self.assertIsNone(arm.animation_data)  # Bake keyed nothing


class TestSolveReports(Base):
    """Solve says whether the control points were met, with the largest residual."""

    def solve_and_report(self, steps=None):
        arm = fig9_armature()
        if steps is not None:
            bpy.context.scene.physik.max_steps = steps
        _, summary = engine.solve(scene_dict.build_scene(bpy.context, arm, solve=True))
        before = snapshot(arm.name)
        self.assertIsNone(run_op(bpy.ops.physik.solve))
        self.assertNotEqual(snapshot(arm.name), before)  # the pose is applied either way
        worst = max(summary["final_residuals"])
        self.assertIn("largest residual %.3g (tolerance %.3g)" % (worst, summary["residual_tol"]),
                      operators.LAST_REPORT["text"])
        return summary, worst

    def test_converged_is_info(self):
        summary, worst = self.solve_and_report()
        self.assertTrue(summary["converged"])
        self.assertLess(worst, summary["residual_tol"])
        self.assertEqual(operators.LAST_REPORT["level"], 'INFO')
        self.assertIn("converged", operators.LAST_REPORT["text"])

    def test_not_converged_is_a_warning_with_the_residual(self):
        summary, worst = self.solve_and_report(steps=5)  # far too few for Fig 9 (about 110)
        self.assertFalse(summary["converged"])
        self.assertFalse(summary["diverged"])
        self.assertGreater(worst, summary["residual_tol"])
        self.assertEqual(operators.LAST_REPORT["level"], 'WARNING')
        self.assertIn("not converged: 5 steps", operators.LAST_REPORT["text"])


def snapshot(name):
    """The armature's pose, exactly: every channel's location and rotation as stored, and the
    posed heads and tails. Looked up by name: an undo replaces the Python objects."""
    arm = bpy.data.objects[name]
    bpy.context.view_layer.update()
    channels = {pb.name: (tuple(pb.location), tuple(pb.rotation_quaternion),
                          tuple(pb.rotation_euler), tuple(pb.rotation_axis_angle))
                for pb in arm.pose.bones}
    posed = {n: (tuple(h), tuple(t)) for n, _, h, t in armature_io.posed_bones_world(arm)}
    return channels, posed


def keyed_frames(name):
    arm = bpy.data.objects[name]
    action = arm.animation_data.action if arm.animation_data else None
    if action is None:
        return []
    return sorted({round(k.co[0]) for f in action.fcurves for k in f.keyframe_points})


class TestUndo(Base):
    """Undo across Solve, Bake and Reset (tolerance: none, the poses compare equal)."""

    def setUp(self):
        super().setUp()
        self.name = fig9_armature().name
        bpy.ops.ed.undo_push(message="fig9 set up")
        self.before = snapshot(self.name)

    def undo_step(self, op):
        """Run op as one undo step (what a button press does); return its pose."""
        self.assertEqual(op('EXEC_DEFAULT', True), {'FINISHED'})
        return snapshot(self.name)

    def test_undo_and_redo_across_solve(self):
        solved = self.undo_step(bpy.ops.physik.solve)
        hand = Vector(solved[1]["hand.R"][1])
        self.assertLess((hand - Vector((-2.4, -0.6, 1.5))).length, 5e-3)  # the Solve moved it
        self.assertEqual(bpy.ops.ed.undo(), {'FINISHED'})
        self.assertEqual(snapshot(self.name), self.before)
        self.assertEqual(bpy.ops.ed.redo(), {'FINISHED'})
        self.assertEqual(snapshot(self.name), solved)

    def test_undo_and_redo_across_bake(self):
        s = bpy.context.scene.physik
        s.max_steps, s.bake_every = 12, 4
        bpy.context.scene.frame_set(1)
        self.assertEqual(keyed_frames(self.name), [])
        baked = self.undo_step(bpy.ops.physik.bake)
        self.assertEqual(keyed_frames(self.name), [1, 2, 3, 4])
        # Bake shows the current frame's key: the start pose (single precision)
        for n, (h, t) in baked[1].items():
            self.assertLess((Vector(h) - Vector(self.before[1][n][0])).length, 1e-6, n)
        self.assertEqual(bpy.ops.ed.undo(), {'FINISHED'})
        self.assertEqual(keyed_frames(self.name), [])
        self.assertEqual(snapshot(self.name), self.before)
        self.assertEqual(bpy.ops.ed.redo(), {'FINISHED'})
        self.assertEqual(keyed_frames(self.name), [1, 2, 3, 4])
        self.assertEqual(snapshot(self.name), baked)

    def test_undo_and_redo_across_reset(self):
        solved = self.undo_step(bpy.ops.physik.solve)
        self.assertNotEqual(solved, self.before)
        self.assertEqual(self.undo_step(bpy.ops.physik.reset), self.before)
        self.assertEqual(bpy.ops.ed.undo(), {'FINISHED'})
        self.assertEqual(snapshot(self.name), solved)
        self.assertEqual(bpy.ops.ed.undo(), {'FINISHED'})
        self.assertEqual(snapshot(self.name), self.before)
        self.assertEqual(bpy.ops.ed.redo(), {'FINISHED'})
        self.assertEqual(bpy.ops.ed.redo(), {'FINISHED'})
        self.assertEqual(snapshot(self.name), self.before)  # Reset's result: the start pose again

    def test_a_failed_solve_adds_no_undo_step(self):
        # a cancelled operator pushes nothing: after Solve and a diverging Solve, one undo goes
        # back to the set-up (an extra step would hold the solved pose)
        solved = self.undo_step(bpy.ops.physik.solve)
        s = bpy.context.scene.physik
        s.damping, s.control_k = 0.0, 1e6
        with self.assertRaises(RuntimeError):
            bpy.ops.physik.solve('EXEC_DEFAULT', True)
        self.assertEqual(snapshot(self.name), solved)
        self.assertEqual(bpy.ops.ed.undo(), {'FINISHED'})
        self.assertEqual(snapshot(self.name), self.before)


def main():
    suite = unittest.defaultTestLoader.loadTestsFromModule(sys.modules[__name__])
    result = unittest.TextTestRunner(verbosity=2, stream=sys.stdout).run(suite)
    sys.exit(0 if result.wasSuccessful() else 1)


main()
