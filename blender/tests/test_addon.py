"""Headless tests of the PhysIK add-on, run by Blender (ctest: blender_addon):

    blender -b --factory-startup --python-exit-code 1 --python blender/tests/test_addon.py -- \
        --repo . [--shared ../shared]

The add-on is enabled from the repository folder: blender/ goes on sys.path and
addon_utils.enable("physik_addon") imports and registers it (test_install.py covers the zip).
What is checked: the rig read from the paper's pinhead.blend against models/rigs/pinhead.json;
rig files round-tripping through an armature; control-point empties; poses, keyframes and reset;
Collide's floor, self-collision and box obstacles (the meshes of "PhysIK Obstacles", each box's
corners the mesh's world vertices); every bad input giving one Blender error report and no
traceback; the missing engine reported.
Tolerances: positions and frames 1e-6 (Blender keeps them in single precision: ~1e-7 of their
size), limits 1e-6 rad (Blender keeps radians in single precision: 160 deg comes back as
159.9999953 deg, 8e-8 rad off); against the 4-decimal pinhead.json, 1e-4.
"""
import json
import math
import os
import sys
import tempfile
import unittest

import addon_utils
import bpy
from mathutils import Quaternion, Vector


sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
# tests/scene_boxes.py: the box oracle the viewer test shares
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tests"))
from blender_harness import box_mesh, clear_scene, enable_addon, script_args  # noqa: E402
from scene_boxes import box_corners  # noqa: E402
from test_rig_format import EVERY_FIELD  # noqa: E402

ARGS = script_args((["--shared"], {"default": None, "help": "folder with data/pinhead.blend"}))
REPO = os.path.abspath(ARGS.repo)
RIGS = os.path.join(REPO, "models", "rigs")
MOD = enable_addon(REPO, "test_addon.py")

from physik_addon import (armature_io, bone_targets, control_points, engine,  # noqa: E402
                          operators, rig_format, scene_dict, settings)

POS_TOL = 1e-6    # rig units
FRAME_TOL = 1e-6  # axis components
LIMIT_TOL = 1e-6  # rad




def angle_between(q1, q2):
    """Angle (rad) of the rotation between two unit quaternions, sign-blind, in double precision
    and without acos near 1: 4 asin(|q1 -+ q2| / 2)."""
    a, b = [float(c) for c in q1], [float(c) for c in q2]
    d = min(math.dist(a, b), math.dist(a, [-c for c in b]))
    return 4.0 * math.asin(min(1.0, d / 2.0))


def max_diff(a, b):
    return max(abs(x - y) for x, y in zip(a, b))


def run_op(op, **kw):
    """Run an operator; return None on success or the error report's text."""
    try:
        op(**kw)
        return None
    except RuntimeError as e:
        return str(e)


def build(name, **kw):
    rig = rig_format.load_rig(os.path.join(RIGS, name + ".json"))
    return rig, armature_io.rig_to_armature(rig, bpy.context, **kw)


class Base(unittest.TestCase):
    def setUp(self):
        if bpy.context.object is not None and bpy.context.object.mode != 'OBJECT':
            bpy.ops.object.mode_set(mode='OBJECT')
        clear_scene()

    def assert_report(self, message, *fragments):
        """An operator failed with one report holding every fragment, and no traceback."""
        self.assertIsNotNone(message, "the operator succeeded; expected an error report")
        self.assertNotIn("Traceback", message)
        for f in fragments:
            self.assertIn(f, message)

    def assert_same_rig(self, want, got, pos_tol, frame_tol, limit_tol_deg):
        """Canonical or file-form rigs: same bones and parents in order, positions, frames and
        limits within the tolerances (limits in degrees)."""
        self.assertEqual([b["name"] for b in want["bones"]], [b["name"] for b in got["bones"]])
        for a, b in zip(want["bones"], got["bones"]):
            self.assertEqual(a["parent"], b["parent"], a["name"])
            self.assertLess(max_diff(a["head"], b["head"]), pos_tol, a["name"])
            self.assertLess(max_diff(a["tail"], b["tail"]), pos_tol, a["name"])
            for k in range(3):
                self.assertLess(max_diff(a["rest_frame"][k], b["rest_frame"][k]), frame_tol,
                                "%s axis %d" % (a["name"], k))
            la, lb = a.get("limits_deg", {}), b.get("limits_deg", {})
            self.assertEqual(sorted(la), sorted(lb), a["name"])
            for axis in la:
                self.assertLess(max_diff(la[axis], lb[axis]), limit_tol_deg, a["name"] + axis)


class TestEnable(Base):
    def test_registered(self):
        for op in ("import_rig", "export_rig", "add_control_point", "solve", "simulate", "bake",
                   "reset"):
            self.assertTrue(hasattr(bpy.types, "PHYSIK_OT_" + op), op)
        self.assertTrue(hasattr(bpy.types, "PHYSIK_PT_panel"))
        s = bpy.context.scene.physik
        if engine.available():  # test_engine.py checks the fields against the engine's table
            self.assertEqual(s.preset, engine.param_table()["default_preset"])
        else:  # no engine: only the add-on's own fields, and no params typed here
            self.assertFalse(hasattr(s, "preset"))
            self.assertEqual(settings.params_dict(s), {})
            self.assertEqual((s.steps_per_frame, s.bake_every, s.max_steps), (1, 1, 600))

    def test_unregister_and_register_again(self):
        addon_utils.disable("physik_addon")
        self.assertFalse(hasattr(bpy.types.Scene, "physik"))
        self.assertIsNotNone(addon_utils.enable("physik_addon", default_set=True,
                                                handle_error=None))
        self.assertTrue(hasattr(bpy.types.Scene, "physik"))


def shared_blend():
    folder = ARGS.shared
    path = os.path.join(folder, "data", "pinhead.blend") if folder else None
    return path if path and os.path.isfile(path) else None


@unittest.skipIf(shared_blend() is None, "no --shared folder with data/pinhead.blend")
class TestPaperBlend(Base):
    """The paper's own file against the project's rig: models/rigs/pinhead.json names each bone's
    Blender name in its comment ("Blender bone Bone.013")."""

    def setUp(self):
        bpy.ops.wm.open_mainfile(filepath=shared_blend())
        self.arm = bpy.data.objects["Armature"]
        with open(os.path.join(RIGS, "pinhead.json")) as f:
            self.ref = json.load(f)
        self.name_of = {b["comment"].split("Blender bone ")[1]: b["name"]
                        for b in self.ref["bones"]}

    def renamed(self, rig):
        for b in rig["bones"]:
            b["name"] = self.name_of[b["name"]]
            b["parent"] = self.name_of[b["parent"]] if b["parent"] else None
        return rig

    def test_rig_equals_pinhead_json(self):
        got = self.renamed(armature_io.armature_to_rig(self.arm))
        self.assert_same_rig(self.ref, got, 1e-4, 1e-4, 1e-4)
        worst = {"head/tail": 0.0, "frame": 0.0, "limit_deg": 0.0}
        for a, b in zip(self.ref["bones"], got["bones"]):
            worst["head/tail"] = max(worst["head/tail"], max_diff(a["head"], b["head"]),
                                     max_diff(a["tail"], b["tail"]))
            worst["frame"] = max([worst["frame"]] + [
                max_diff(a["rest_frame"][k], b["rest_frame"][k]) for k in range(3)])
            for axis, lim in a.get("limits_deg", {}).items():
                worst["limit_deg"] = max(worst["limit_deg"], max_diff(lim, b["limits_deg"][axis]))
            # mass: the file's fwik_mass is the original add-on's mass per length
            self.assertEqual(b["mass_per_length"], a["mass_per_length"], a["name"])
        self.assertEqual(got["defaults"], self.ref["defaults"])
        print("\npinhead.blend vs models/rigs/pinhead.json, largest differences:", worst)

    def test_saved_control_points(self):
        # the original add-on's empties (fwik_*), as shared/data/pinhead_rig.json lists them
        with open(os.path.join(os.path.dirname(shared_blend()), "pinhead_rig.json")) as f:
            saved = json.load(f)["control_points_saved_in_file"]
        got = control_points.read_control_points(bpy.context.scene, self.arm)
        self.assertEqual(len(got), len(saved))
        for want in saved:
            match = [c for c in got if c["bone"] == want["bone"]]
            self.assertEqual(len(match), 1, want["bone"])
            self.assertLess(max_diff(match[0]["target"], want["target"]), 1e-4)
            self.assertEqual(match[0]["alpha"], want["bone_alpha"])
            self.assertEqual(match[0]["k"], want["spring_constant"])


class TestRoundTrip(Base):
    """Rig file -> armature -> rig: the canonical rig (what the engine builds) comes back."""

    def check(self, name):
        rig, obj = build(name)
        back = armature_io.armature_to_rig(obj)
        self.assert_same_rig(rig, back, POS_TOL, FRAME_TOL, math.degrees(LIMIT_TOL))
        # the read-back file parses to the same canonical rig
        self.assert_same_rig(rig, rig_format.parse_rig(back, "back"), POS_TOL, FRAME_TOL,
                             math.degrees(LIMIT_TOL))
        self.assertEqual(back["name"], rig["name"])
        self.assertEqual(back["defaults"], rig["defaults"])
        for a, b in zip(rig["bones"], back["bones"]):
            for key in ("mass", "mass_per_length", "radius"):
                self.assertEqual(a.get(key), b.get(key), a["name"] + " " + key)
        return rig, obj

    def test_pinhead(self):
        self.check("pinhead")

    def test_hand(self):
        self.check("hand")

    def test_elbow(self):
        self.check("elbow")

    def test_chain3(self):
        self.check("chain3")

    def test_locked_axis_is_locked_in_blender(self):
        _, obj = self.check("hand")
        pb = obj.pose.bones["index.2"]  # limits x [0, 10], y and z [0, 0]
        self.assertEqual((pb.lock_ik_x, pb.lock_ik_y, pb.lock_ik_z), (False, True, True))
        self.assertAlmostEqual(math.degrees(pb.ik_max_x), 10.0, places=5)

    def test_lock_ik_alone_reads_as_locked(self):
        _, obj = build("chain3")
        pb = obj.pose.bones["b1"]
        pb.lock_ik_z = True  # Blender's lock, no limit flag
        pb.use_ik_limit_x, pb.ik_min_x, pb.ik_max_x = True, math.radians(-20), math.radians(30)
        got = armature_io.armature_to_rig(obj)["bones"][1]["limits_deg"]
        self.assertEqual(sorted(got), ["x", "z"])
        self.assertEqual(got["z"], [0.0, 0.0])
        self.assertLess(max_diff(got["x"], (-20, 30)), 1e-5)

    def test_masses_radii_defaults(self):
        doc = {"name": "m", "defaults": {"mass_per_length": 2.5, "radius": 0.1}, "bones": [
            {"name": "a", "parent": None, "head": [0, 0, 0], "tail": [0, 0, 1], "mass": 3.0},
            {"name": "b", "parent": "a", "head": [0, 0, 1], "tail": [0, 1, 1],
             "mass_per_length": 0.5, "radius": 0.2, "roll_deg": 30}]}
        rig = rig_format.parse_rig(doc, "m")
        back = armature_io.armature_to_rig(armature_io.rig_to_armature(rig, bpy.context))
        self.assertEqual(back["defaults"], {"mass_per_length": 2.5, "radius": 0.1})
        self.assertEqual(back["bones"][0]["mass"], 3.0)
        self.assertEqual((back["bones"][1]["mass_per_length"], back["bones"][1]["radius"]),
                         (0.5, 0.2))
        self.assert_same_rig(rig, back, POS_TOL, FRAME_TOL, math.degrees(LIMIT_TOL))

    def test_object_transform_is_applied(self):
        rig, obj = build("elbow")
        obj.location = (1.0, -2.0, 0.5)
        obj.rotation_euler = (0.3, -0.2, 1.1)
        obj.scale = (2.0, 2.0, 2.0)
        bpy.context.view_layer.update()
        m = obj.matrix_world
        r = m.to_3x3().normalized()
        back = armature_io.armature_to_rig(obj)
        for a, b in zip(rig["bones"], back["bones"]):
            self.assertLess(max_diff(m @ Vector(a["head"]), b["head"]), 1e-5)
            self.assertLess(max_diff(m @ Vector(a["tail"]), b["tail"]), 1e-5)
            for k in range(3):
                self.assertLess(max_diff(r @ Vector(a["rest_frame"][k]), b["rest_frame"][k]), 1e-5)

    def test_operators_import_export(self):
        path = os.path.join(RIGS, "hand.json")
        self.assertIsNone(run_op(bpy.ops.physik.import_rig, filepath=path))
        obj = bpy.context.active_object
        self.assertEqual(obj.type, 'ARMATURE')
        with tempfile.TemporaryDirectory() as tmp:
            out = os.path.join(tmp, "hand_out.json")
            self.assertIsNone(run_op(bpy.ops.physik.export_rig, filepath=out))
            back = rig_format.load_rig(out)
        self.assert_same_rig(rig_format.load_rig(path), back, POS_TOL, FRAME_TOL,
                             math.degrees(LIMIT_TOL))

    def test_edit_mode_reads_edit_bones(self):
        rig, obj = build("chain3")
        bpy.ops.object.mode_set(mode='EDIT')
        obj.data.edit_bones["b2"].tail = (0.0, 1.0, 2.0)  # not yet in the saved bones
        got = armature_io.armature_to_rig(obj)
        self.assertLess(max_diff(got["bones"][2]["tail"], (0.0, 1.0, 2.0)), 1e-6)
        bpy.ops.object.mode_set(mode='OBJECT')


def import_file(path):
    """Import a rig file with the operator; the new armature."""
    assert run_op(bpy.ops.physik.import_rig, filepath=path) is None
    return bpy.context.active_object


def export_file(obj, folder, name="back.json"):
    """Export an armature with the operator; the file's dict."""
    bpy.context.view_layer.objects.active = obj
    path = os.path.join(folder, name)
    msg = run_op(bpy.ops.physik.export_rig, filepath=path)
    assert msg is None, msg
    with open(path) as f:
        return json.load(f)


def differing_fields(want, got):
    """{(bone or "", field)} where two rig dicts differ (bones matched by name)."""
    out = {("", k) for k in set(want) | set(got) if k != "bones" and want.get(k) != got.get(k)}
    a = {b["name"]: b for b in want["bones"]}
    b = {b["name"]: b for b in got["bones"]}
    out |= {(n, "(bone)") for n in set(a) ^ set(b)}
    for n in set(a) & set(b):
        out |= {(n, k) for k in set(a[n]) | set(b[n]) if a[n].get(k) != b[n].get(k)}
    return out


class TestFileRoundTrip(Base):
    """A rig file imported and exported comes back as it was, field by field and bit for bit
    (rig_record.py; without the module: the add-on's own reader; test_round_trip.py does the
    same through the engine's reader and checks the runs); what is changed in Blender comes
    from Blender."""

    def setUp(self):
        super().setUp()
        self.tmp = tempfile.TemporaryDirectory()

    def tearDown(self):
        self.tmp.cleanup()

    def original(self, path):
        with open(path) as f:
            return json.load(f)

    def test_every_shipped_rig_comes_back_as_it_was(self):
        for name in sorted(os.listdir(RIGS)):
            path = os.path.join(RIGS, name)
            back = export_file(import_file(path), self.tmp.name)
            self.assertEqual(differing_fields(self.original(path), back), set(), name)
            self.assertEqual(back, self.original(path), name)

    def test_every_optional_field_comes_back(self):
        path = write_json(self.tmp.name, "every.json", EVERY_FIELD)
        back = export_file(import_file(path), self.tmp.name)
        self.assertEqual(back, EVERY_FIELD)

    def test_in_edit_mode_and_after_saving_the_blend_file(self):
        path = os.path.join(RIGS, "pinhead.json")
        obj = import_file(path)
        bpy.ops.object.mode_set(mode='EDIT')
        self.assertEqual(export_file(obj, self.tmp.name), self.original(path))
        bpy.ops.object.mode_set(mode='OBJECT')
        blend = os.path.join(self.tmp.name, "saved.blend")
        bpy.ops.wm.save_as_mainfile(filepath=blend)
        bpy.ops.wm.open_mainfile(filepath=blend)
        self.assertEqual(export_file(bpy.data.objects["pinhead"], self.tmp.name),
                         self.original(path))

    def test_what_is_changed_in_blender_comes_from_blender(self):
        path = os.path.join(RIGS, "pinhead.json")
        want = self.original(path)
        obj = import_file(path)
        bpy.ops.object.mode_set(mode='EDIT')
        obj.data.edit_bones["hand.R"].tail += Vector((0.1, 0.0, 0.0))  # a leaf: its tail
        obj.data.edit_bones["torso"].roll += 0.3
        bpy.ops.object.mode_set(mode='OBJECT')
        obj.pose.bones["forearm.L"].ik_min_z = math.radians(-120.0)
        obj.pose.bones["thigh.R"]["physik_mass"] = 2.5
        del obj.pose.bones["thigh.R"]["physik_mass_per_length"]
        back = export_file(obj, self.tmp.name)
        self.assertEqual(differing_fields(want, back), {
            ("hand.R", "tail"), ("hand.R", "rest_frame"), ("torso", "rest_frame"),
            ("forearm.L", "limits_deg"), ("thigh.R", "mass"), ("thigh.R", "mass_per_length")})
        bones = {b["name"]: b for b in back["bones"]}
        hand = next(b for b in want["bones"] if b["name"] == "hand.R")
        self.assertLess(max_diff(bones["hand.R"]["tail"], Vector(hand["tail"]) +
                                 Vector((0.1, 0.0, 0.0))), POS_TOL)
        self.assertLess(abs(bones["forearm.L"]["limits_deg"]["z"][0] + 120.0), 1e-4)
        self.assertEqual(bones["thigh.R"]["mass"], 2.5)
        rig_format.parse_rig(back, "back")  # a valid rig

    def test_moving_the_object_moves_every_bone(self):
        path = os.path.join(RIGS, "hand.json")
        want = self.original(path)
        obj = import_file(path)
        obj.location = (1.0, 0.0, 0.0)
        bpy.context.view_layer.update()
        back = export_file(obj, self.tmp.name)
        self.assertEqual({f for _, f in differing_fields(want, back)}, {"head", "tail"})
        for a, b in zip(want["bones"], back["bones"]):
            for key in ("head", "tail"):
                self.assertLess(max_diff(Vector(a[key]) + Vector((1, 0, 0)), b[key]), POS_TOL)


class TestControlPoints(Base):
    def test_round_trip(self):
        _, arm = build("pinhead")
        specs = [("hand.R", 1.0, (-2.4, -0.6, 1.5), 30.0, "capped", 0.5),
                 ("foot.L", 0.0, (0.4751, 0.0, -2.4269), None, None, None),
                 ("torso", 0.5, (0.1, 0.2, 1.0), 12.0, "linear", None)]
        for bone, alpha, target, k, spring, cap in specs:
            control_points.add_control_point(bpy.context, arm, bone, alpha, target, k, spring, cap)
        bpy.context.view_layer.update()
        got = {c["bone"]: c for c in control_points.read_control_points(bpy.context.scene, arm)}
        self.assertEqual(sorted(got), sorted(s[0] for s in specs))
        for bone, alpha, target, k, spring, cap in specs:
            c = got[bone]
            self.assertEqual(c["alpha"], alpha)
            self.assertLess(max_diff(c["target"], target), POS_TOL)
            self.assertEqual((c.get("k"), c.get("spring"), c.get("cap")), (k, spring, cap))

    def test_default_target_is_the_attachment_point(self):
        rig, arm = build("pinhead")
        empty = control_points.add_control_point(bpy.context, arm, "torso", 0.25)
        bpy.context.view_layer.update()
        b = next(b for b in rig["bones"] if b["name"] == "torso")
        want = Vector(b["head"]).lerp(Vector(b["tail"]), 0.25)
        self.assertLess((empty.matrix_world.translation - want).length, POS_TOL)

    def test_target_follows_a_parented_empty(self):
        _, arm = build("elbow")
        empty = control_points.add_control_point(bpy.context, arm, "forearm", 1.0, (1.0, 0.0, 3.0))
        holder = bpy.data.objects.new("holder", None)
        bpy.context.scene.collection.objects.link(holder)
        holder.location = (0.0, 2.0, 0.0)
        empty.parent = holder
        bpy.context.view_layer.update()
        (c,) = control_points.read_control_points(bpy.context.scene, arm)
        self.assertLess(max_diff(c["target"], (1.0, 2.0, 3.0)), POS_TOL)

    def test_other_armatures_points_are_not_read(self):
        _, a = build("elbow")
        _, b = build("chain3")
        control_points.add_control_point(bpy.context, a, "forearm")
        control_points.add_control_point(bpy.context, b, "b2")
        points = control_points.read_control_points(bpy.context.scene, a)
        self.assertEqual([c["bone"] for c in points], ["forearm"])

    def test_operator_uses_the_active_bone(self):
        _, arm = build("elbow")
        arm.data.bones.active = arm.data.bones["forearm"]
        self.assertIsNone(run_op(bpy.ops.physik.add_control_point, alpha=0.5))
        (c,) = control_points.read_control_points(bpy.context.scene, arm)
        self.assertEqual((c["bone"], c["alpha"]), ("forearm", 0.5))
        self.assertLess(max_diff(c["target"], (0.0, 0.0, 3.0)), POS_TOL)


class TestBoneTargets(Base):
    def test_orientation_and_aim_empties_are_in_the_scene(self):
        _, arm = build("pinhead")
        control_points.add_control_point(bpy.context, arm, "hand.L", 1.0, (1.5, -0.5, 1.2))
        q = Quaternion((0.9, 0.1, 0.3, 0.2)).normalized()
        bone_targets.add_orientation_target(bpy.context, arm, "hand.R", q, k=4.0,
                                            spring="capped", cap=0.5)
        bone_targets.add_aim_target(bpy.context, arm, "head", (1.0, -3.0, 2.0), axis=(0, 0, 1),
                                    k=5.0)
        bpy.context.view_layer.objects.active = arm
        scene = json.loads(json.dumps(scene_dict.build_scene(bpy.context, arm)))
        # the targets' empties are not control points
        self.assertEqual([c["bone"] for c in scene["control_points"]], ["hand.L"])
        (o,) = scene["orientation_targets"]
        self.assertEqual((o["bone"], o["k"], o["spring"], o["cap"]), ("hand.R", 4.0, "capped", 0.5))
        self.assertLess(angle_between(Quaternion(o["quaternion"]), q), 1e-6)
        self.assertAlmostEqual(sum(c * c for c in o["quaternion"]), 1.0, delta=1e-12)
        (a,) = scene["aim_targets"]
        self.assertEqual((a["bone"], a["axis"], a["k"]), ("head", [0, 0, 1], 5.0))
        self.assertLess(max_diff(a["point"], (1.0, -3.0, 2.0)), POS_TOL)

    def test_the_default_orientation_is_the_bones_frame_now(self):
        _, arm = build("pinhead")
        arm.rotation_euler = (0.0, 0.0, 0.7)
        head, rot = some_pose(arm)
        armature_io.apply_pose(arm, head, rot)
        bpy.context.view_layer.update()
        empty = bone_targets.add_orientation_target(bpy.context, arm, "forearm.R")
        bpy.context.view_layer.update()
        pb = arm.pose.bones["forearm.R"]
        want = (arm.matrix_world.to_3x3().normalized() @ pb.matrix.to_3x3()).to_quaternion()
        (o,) = bone_targets.read_bone_targets(bpy.context.scene, arm)["orientation_targets"]
        self.assertLess(angle_between(Quaternion(o["quaternion"]), want), 1e-6)
        self.assertLess((empty.matrix_world.translation - arm.matrix_world @ pb.head).length,
                        POS_TOL)

    def test_a_parented_empty_gives_its_world_rotation_and_the_aims_default_point(self):
        _, arm = build("elbow")
        empty = bone_targets.add_orientation_target(bpy.context, arm, "forearm", Quaternion())
        holder = bpy.data.objects.new("holder", None)
        bpy.context.scene.collection.objects.link(holder)
        holder.rotation_euler = (0.5, 0.0, 0.0)
        empty.parent = holder
        bone_targets.add_aim_target(bpy.context, arm, "forearm")  # one length beyond the tail
        bpy.context.view_layer.update()
        got = bone_targets.read_bone_targets(bpy.context.scene, arm)
        want = Quaternion((1, 0, 0), 0.5)
        self.assertLess(angle_between(Quaternion(got["orientation_targets"][0]["quaternion"]),
                                      want), 1e-6)
        self.assertLess(max_diff(got["aim_targets"][0]["point"], (0, 0, 6)), POS_TOL)
        self.assertNotIn("axis", got["aim_targets"][0])

    def test_the_operators_use_the_active_bone(self):
        _, arm = build("elbow")
        arm.data.bones.active = arm.data.bones["forearm"]
        bpy.context.view_layer.objects.active = arm
        self.assertIsNone(run_op(bpy.ops.physik.add_orientation_target))
        self.assertIsNone(run_op(bpy.ops.physik.add_aim_target))
        got = bone_targets.read_bone_targets(bpy.context.scene, arm)
        self.assertEqual([t["bone"] for t in got["orientation_targets"]], ["forearm"])
        self.assertEqual([t["bone"] for t in got["aim_targets"]], ["forearm"])
        self.assertEqual(control_points.read_control_points(bpy.context.scene, arm), [])

    def test_bad_bone_targets_are_one_error_naming_the_empty(self):
        _, arm = build("elbow")
        with self.assertRaises(rig_format.InputError) as e:
            bone_targets.add_aim_target(bpy.context, arm, "wrist")
        self.assertIn("unknown bone 'wrist'", str(e.exception))
        empty = bone_targets.add_orientation_target(bpy.context, arm, "forearm")
        for key, value, words in (("physik_target", "roll", "unknown target 'roll'"),
                                  ("physik_bone", "wrist", "unknown bone 'wrist'"),
                                  ("physik_spring", "stiff", "unknown law 'stiff'")):
            saved = empty.get(key)
            empty[key] = value
            with self.assertRaises(rig_format.InputError) as e:
                bone_targets.read_bone_targets(bpy.context.scene, arm)
            self.assertIn("empty '%s'" % empty.name, str(e.exception))
            self.assertIn(words, str(e.exception))
            if saved is None:
                del empty[key]
            else:
                empty[key] = saved
        del empty["physik_armature"]
        with self.assertRaises(rig_format.InputError) as e:
            bone_targets.read_bone_targets(bpy.context.scene, arm)
        self.assertIn("physik_armature", str(e.exception))


def some_pose(obj, seed=3):
    """A deterministic, non-trivial channel pose: every bone turned, the root moved."""
    rot = {}
    for i, pb in enumerate(armature_io.pose_bones_dfs(obj)):
        axis = Vector((math.sin(seed + i), math.cos(2 * seed + i), 0.5)).normalized()
        rot[pb.name] = Quaternion(axis, 0.1 + 0.05 * i)
    return Vector((0.3, -0.2, 2.5)), rot


class TestPoses(Base):
    def world(self, obj):
        bpy.context.view_layer.update()
        return [(h.copy(), t.copy()) for _, _, h, t in armature_io.posed_bones_world(obj)]

    def test_apply_then_read(self):
        _, obj = build("pinhead")
        head, rot = some_pose(obj)
        armature_io.apply_pose(obj, head, rot)
        got_head, got_rot = armature_io.read_pose(obj)
        self.assertLess((got_head - head).length, POS_TOL)
        for name, q in rot.items():
            self.assertLess(angle_between(q, got_rot[name]), 1e-6, name)
        self.assertLess((self.world(obj)[0][0] - head).length, POS_TOL)

    def test_world_orientations_give_the_channel_rotations(self):
        _, obj = build("pinhead")
        obj.rotation_euler = (0.0, 0.0, 0.7)  # an object turn must not leak into the channels
        head, rot = some_pose(obj)
        armature_io.apply_pose(obj, head, rot)
        bpy.context.view_layer.update()
        r = obj.matrix_world.to_3x3().normalized()
        world = {pb.name: (r @ pb.matrix.to_3x3()).to_quaternion() for pb in obj.pose.bones}
        local = armature_io.local_rotations_from_world(obj, world)
        for name, q in rot.items():
            self.assertLess(angle_between(q, local[name]), 1e-5, name)

    def test_other_rotation_modes(self):
        _, obj = build("elbow")
        q = Quaternion(Vector((1.0, 2.0, 0.5)).normalized(), 0.8)
        for mode in ('XYZ', 'ZXY', 'AXIS_ANGLE', 'QUATERNION'):
            pb = obj.pose.bones["forearm"]
            pb.rotation_mode = mode
            armature_io.set_rotation(pb, q)
            self.assertLess(angle_between(q, pb.matrix_basis.to_quaternion()), 1e-6, mode)

    def test_initial_pose_dict(self):
        _, obj = build("elbow")
        armature_io.apply_pose(obj, (0.0, 0.0, 1.0),
                               {"forearm": Quaternion((1, 0, 0), math.radians(-30))})
        ip = armature_io.initial_pose_dict(obj)
        self.assertLess(max_diff(ip["root_head"], (0, 0, 1)), POS_TOL)
        self.assertEqual(list(ip["rotation_deg"]), ["forearm"])
        self.assertLess(max_diff(ip["rotation_deg"]["forearm"], (-30, 0, 0)), 1e-4)

    def test_bones_csv(self):
        _, obj = build("elbow")
        with tempfile.TemporaryDirectory() as tmp:
            path = os.path.join(tmp, "bones.csv")
            armature_io.write_bones_csv(path, armature_io.posed_bones_world(obj))
            with open(path) as f:
                lines = f.read().splitlines()
        self.assertEqual(lines[0], "bone,parent,head_x,head_y,head_z,tail_x,tail_y,tail_z")
        self.assertEqual(lines[1:], ["upper_arm,,0,0,0,0,0,2", "forearm,upper_arm,0,0,2,0,0,4"])


class TestBakeAndReset(Base):
    def trajectory(self, obj, n):
        """n poses: the forearm turning 10 deg per step, the root rising 0.1 per step."""
        return [((0.0, 0.0, 0.1 * s), {"forearm": Quaternion((1, 0, 0), math.radians(-10 * s))})
                for s in range(n)]

    def keyed_frames(self, obj, path):
        fc = [f for f in obj.animation_data.action.fcurves if f.data_path == path]
        return sorted({round(k.co[0]) for f in fc for k in f.keyframe_points})

    def test_keys_every_n_steps_and_the_last(self):
        _, obj = build("elbow")
        frames = armature_io.bake_keyframes(obj, self.trajectory(obj, 11), frame_start=5, every=3)
        self.assertEqual(frames, [5, 6, 7, 8, 9])  # steps 0, 3, 6, 9 and the last, 10
        self.assertEqual(self.keyed_frames(obj, 'pose.bones["forearm"].rotation_quaternion'),
                         frames)
        self.assertEqual(self.keyed_frames(obj, 'pose.bones["upper_arm"].location'), frames)
        for frame, step in zip(frames, (0, 3, 6, 9, 10)):
            bpy.context.scene.frame_set(frame)
            pb = obj.pose.bones["forearm"]
            angle = pb.rotation_quaternion.to_axis_angle()[1]
            self.assertAlmostEqual(math.degrees(angle), 10 * step, places=3)
            self.assertAlmostEqual(armature_io.read_pose(obj)[0].z, 0.1 * step, places=6)

    def test_bad_every(self):
        _, obj = build("elbow")
        with self.assertRaises(rig_format.InputError):
            armature_io.bake_keyframes(obj, self.trajectory(obj, 3), every=0)

    def test_reset_returns_to_the_saved_start(self):
        _, obj = build("pinhead")
        head, rot = some_pose(obj)
        armature_io.apply_pose(obj, head, rot)
        operators._save_start_pose(obj)
        armature_io.apply_pose(obj, (0, 0, 0), {n: Quaternion() for n in rot})
        self.assertIsNone(run_op(bpy.ops.physik.reset))
        got_head, got_rot = armature_io.read_pose(obj)
        self.assertLess((got_head - head).length, POS_TOL)
        for name, q in rot.items():
            self.assertLess(angle_between(q, got_rot[name]), 1e-6, name)

    def test_reset_without_a_start_goes_to_rest(self):
        rig, obj = build("pinhead")
        head, rot = some_pose(obj)
        armature_io.apply_pose(obj, head, rot)
        self.assertIsNone(run_op(bpy.ops.physik.reset))
        got_head, got_rot = armature_io.read_pose(obj)
        self.assertLess(max_diff(got_head, rig["bones"][0]["head"]), POS_TOL)
        self.assertTrue(all(q.angle < 1e-9 for q in got_rot.values()))


class TestSettingsAndScene(Base):
    def test_scene_dict_is_json_and_complete(self):
        _, arm = build("pinhead")
        control_points.add_control_point(bpy.context, arm, "hand.R", 1.0, (-2.4, -0.6, 1.5))
        bpy.context.view_layer.objects.active = arm
        scene = scene_dict.build_scene(bpy.context, arm, solve=True)
        text = json.dumps(scene)
        self.assertEqual(sorted(json.loads(text)), ["control_points", "convergence", "initial_pose",
                                                    "params", "rig", "steps"])
        self.assertEqual(len(scene["rig"]["bones"]), 18)
        self.assertEqual(scene["control_points"][0]["bone"], "hand.R")

    def scene_of(self, arm, bone):
        control_points.add_control_point(bpy.context, arm, bone, 1.0)
        bpy.context.view_layer.objects.active = arm
        return scene_dict.build_scene(bpy.context, arm)

    def test_collide_off_adds_no_contacts(self):
        _, arm = build("elbow")
        bpy.context.scene.physik.collide = False
        scene = self.scene_of(arm, "forearm")
        self.assertNotIn("ground", scene)
        self.assertNotIn("self_collision", scene)
        self.assertNotIn("gravity", scene)

    def test_collide_puts_the_floor_under_the_rest_capsules(self):
        # elbow: the upper arm's head at the origin, length 2, so its capsule (0.06 x 2) reaches
        # 0.12 below it; the object moved up by 1.5 (Blender units are rig units) moves the floor
        _, arm = build("elbow")
        arm.location = (0.3, -0.2, 1.5)
        bpy.context.scene.physik.collide = True
        try:
            scene = self.scene_of(arm, "forearm")
        finally:
            bpy.context.scene.physik.collide = False
        self.assertEqual(scene["ground"]["normal"], [0.0, 0.0, 1.0])
        self.assertAlmostEqual(scene["ground"]["height"], 1.5 - 0.12, delta=POS_TOL)
        self.assertIs(scene["self_collision"], True)
        self.assertNotIn("gravity", scene)  # the add-on has no gravity setting
        self.assertNotIn("obstacles", scene)  # no collection "PhysIK Obstacles"
        json.dumps(scene)

    def assert_box_of(self, box, obj):
        """The box's corners are the mesh's world vertices (each to the nearest, both ways)."""
        corners = box_corners(box)
        verts = [list(obj.matrix_world @ v.co) for v in obj.data.vertices]
        for a, b in ((verts, corners), (corners, verts)):
            for p in a:
                self.assertLess(min(math.dist(p, q) for q in b), POS_TOL, (obj.name, p, box))

    def test_collide_makes_the_obstacle_collections_meshes_boxes(self):
        _, arm = build("elbow")
        seat = box_mesh("seat")  # Blender's cube, turned and scaled
        seat.location, seat.rotation_euler, seat.scale = (1, 2.5, 0.5), (0.3, -0.2, 0.7), (
            0.5, 1.5, 0.25)
        # a box off its origin, mirrored, under an empty (in the collection: not a mesh, left
        # out) turned and scaled 2
        holder = bpy.data.objects.new("holder", None)
        bpy.data.collections["PhysIK Obstacles"].objects.link(holder)
        holder.location, holder.rotation_euler, holder.scale = (-3, 1, 0), (0, 0, 0.5), (2, 2, 2)
        shelf = box_mesh("shelf", lo=(0, 0, 0), hi=(2, 1, 0.2))
        shelf.parent = holder
        shelf.location, shelf.scale = (0.5, 0, 1), (-1, 1, 1)
        box_mesh("elsewhere", collection="Not obstacles")
        bpy.context.scene.physik.collide = True
        try:
            scene = self.scene_of(arm, "forearm")
        finally:
            bpy.context.scene.physik.collide = False
        self.assertEqual([o["name"] for o in scene["obstacles"]], ["seat", "shelf"])
        seat_box, shelf_box = (o["box"] for o in scene["obstacles"])
        self.assertLess(max_diff(seat_box["center"], (1, 2.5, 0.5)), POS_TOL)
        self.assertLess(max_diff(seat_box["half_extents"], (0.5, 1.5, 0.25)), POS_TOL)
        self.assertLess(max_diff(shelf_box["half_extents"], (2, 1, 0.2)), POS_TOL)  # x 2
        self.assert_box_of(seat_box, seat)
        self.assert_box_of(shelf_box, shelf)
        self.assertIn("ground", scene)  # with the floor and self-collision
        self.assertIs(scene["self_collision"], True)
        json.dumps(scene)
        self.assertNotIn("obstacles", self.scene_of(arm, "upper_arm"))  # Collide off

    def test_collide_takes_a_bones_own_collision_radius(self):
        # chain3 (three bones of length 1 up from z = 0) with the root's capsule 0.25 wide; a pose
        # does not move the floor: it is the rest pose's
        with open(os.path.join(RIGS, "chain3.json")) as f:
            rig = json.load(f)
        rig["bones"][0]["collision_radius"] = 0.25
        with tempfile.TemporaryDirectory() as tmp:
            arm = import_file(write_json(tmp, "wide_root.json", rig))
        lowest = min(min(b["head"][2], b["tail"][2]) for b in rig["bones"])
        arm.pose.bones[rig["bones"][1]["name"]].rotation_mode = 'XYZ'
        arm.pose.bones[rig["bones"][1]["name"]].rotation_euler = (2.5, 0.0, 0.0)  # bent down
        bpy.context.scene.physik.collide = True
        try:
            scene = self.scene_of(arm, rig["bones"][2]["name"])
        finally:
            bpy.context.scene.physik.collide = False
        self.assertAlmostEqual(scene["ground"]["height"], lowest - 0.25, delta=POS_TOL)

    def test_a_control_point_selects_its_armature(self):
        _, arm = build("elbow")
        empty = control_points.add_control_point(bpy.context, arm, "forearm")
        bpy.context.view_layer.objects.active = empty
        self.assertEqual(scene_dict.active_armature(bpy.context), arm)


def write_json(folder, name, doc):
    path = os.path.join(folder, name)
    with open(path, "w") as f:
        json.dump(doc, f) if not isinstance(doc, str) else f.write(doc)
    return path


TWO = [{"name": "a", "parent": None, "head": [0, 0, 0], "tail": [0, 0, 1]},
       {"name": "b", "parent": "a", "head": [0, 0, 1], "tail": [0, 0, 2]}]


class TestBadInput(Base):
    """Every bad input: one error report naming what is wrong, {'CANCELLED'}, no traceback, and
    nothing half-made left behind."""

    ENGINE_OPS = ("solve", "simulate", "bake")

    def ops_on_active(self):
        return [getattr(bpy.ops.physik, n) for n in self.ENGINE_OPS + ("export_rig", "reset",
                                                                        "add_control_point")]

    def armature_with_point(self):
        _, arm = build("elbow")
        empty = control_points.add_control_point(bpy.context, arm, "forearm", 1.0, (1.0, 0.0, 3.0))
        bpy.context.view_layer.objects.active = arm
        return arm, empty

    def test_no_active_object(self):
        bpy.context.view_layer.objects.active = None
        for op in self.ops_on_active():
            kw = {"filepath": "/tmp/never.json"} if op.idname() == "PHYSIK_OT_export_rig" else {}
            self.assert_report(run_op(op, **kw), "no armature selected")

    def test_active_object_not_an_armature(self):
        bpy.ops.mesh.primitive_cube_add()
        for op in self.ops_on_active():
            kw = {"filepath": "/tmp/never.json"} if op.idname() == "PHYSIK_OT_export_rig" else {}
            self.assert_report(run_op(op, **kw), "no armature selected", "'Cube'", "mesh")

    def import_bad(self, doc, *fragments):
        with tempfile.TemporaryDirectory() as tmp:
            path = write_json(tmp, "bad.json", doc)
            before = len(bpy.data.objects)
            self.assert_report(run_op(bpy.ops.physik.import_rig, filepath=path), "bad.json",
                               *fragments)
            self.assertEqual(len(bpy.data.objects), before, "a failed import left an object")

    def test_zero_length_bone_in_a_rig_file(self):
        bones = [dict(TWO[0]), dict(TWO[1], tail=[0, 0, 1])]
        self.import_bad({"bones": bones}, "bones[1] 'b'", "field 'tail'", "zero-length bone")

    def test_zero_length_bone_in_edit_mode(self):
        _, arm = build("chain3")
        bpy.ops.object.mode_set(mode='EDIT')
        eb = arm.data.edit_bones["b2"]
        eb.tail = eb.head.copy()
        with tempfile.TemporaryDirectory() as tmp:
            msg = run_op(bpy.ops.physik.export_rig, filepath=os.path.join(tmp, "x.json"))
            self.assertFalse(os.path.exists(os.path.join(tmp, "x.json")))
        self.assert_report(msg, "armature 'chain3'", "bone 'b2'", "zero-length bone")

    def test_invalid_bone_names_in_a_rig_file(self):
        for name, why in (("", "empty bone name"), ("a,b", "the bones CSV"), ("x" * 64, "63 bytes"),
                          (7, "expected a string")):
            self.import_bad({"bones": [dict(TWO[0], name=name)]}, "field 'name'", why)

    def test_invalid_bone_name_in_an_armature(self):
        _, arm = build("elbow")
        arm.data.bones["forearm"].name = "fore,arm"
        bpy.context.view_layer.objects.active = arm
        with tempfile.TemporaryDirectory() as tmp:
            msg = run_op(bpy.ops.physik.export_rig, filepath=os.path.join(tmp, "x.json"))
        self.assert_report(msg, "bone 'fore,arm'", "field 'name'", "the bones CSV")

    def test_an_obstacle_that_is_no_box(self):
        self.armature_with_point()

        def flat():  # a plane
            return box_mesh("flat", lo=(-1, -1, 0), hi=(1, 1, 0))

        def squashed():
            obj = box_mesh("squashed")
            obj.scale = (1, 0, 1)
            return obj

        def sheared():  # turned under a parent scaled unevenly
            holder = bpy.data.objects.new("holder", None)
            bpy.context.scene.collection.objects.link(holder)
            holder.scale = (1, 3, 1)
            obj = box_mesh("sheared")
            obj.parent, obj.rotation_euler = holder, (0, 0, 0.5)
            return obj

        bpy.context.scene.physik.collide = True
        try:
            for make, field, why in ((flat, "field 'dimensions'", "no thickness along its local z"),
                                     (squashed, "field 'dimensions'", "along its local y axis"),
                                     (sheared, "field 'scale'", "its axes are sheared")):
                obj = make()
                for op in self.ENGINE_OPS:
                    self.assert_report(run_op(getattr(bpy.ops.physik, op)),
                                       "obstacle '%s' (collection 'PhysIK Obstacles')" % obj.name,
                                       field, why)
                bpy.data.objects.remove(obj)
        finally:
            bpy.context.scene.physik.collide = False

    def test_other_rig_file_errors(self):
        self.import_bad("{not json", "invalid JSON")
        self.import_bad({"bones": [TWO[0], dict(TWO[1], parent="zz")]}, "unknown bone 'zz'")
        self.import_bad({"bones": [TWO[0], dict(TWO[1], parent=None)]}, "a second root")
        self.import_bad({"bones": [TWO[0], dict(TWO[1], head=[0, 0, 1.5])]},
                        "does not meet the tail")
        self.import_bad({"bones": [TWO[0], dict(TWO[1], limits_deg={"x": [20, 10]})]},
                        "limits_deg.x", "greater than max")
        self.import_bad({"bones": [TWO[0], dict(TWO[1], limits_deg={"x": [10, 20]})]},
                        "limits_deg.x", "cannot be a Blender IK limit")
        self.import_bad({"bones": [dict(TWO[0], wings=2)]}, "field 'wings'", "unknown field")
        self.import_bad({"bones": [dict(TWO[0], head=[0, "a", 0])]}, "head[1]", "expected a number")
        with tempfile.TemporaryDirectory() as tmp:
            msg = run_op(bpy.ops.physik.import_rig, filepath=os.path.join(tmp, "absent.json"))
        self.assert_report(msg, "absent.json", "cannot open file")

    def test_control_point_with_no_bone(self):
        arm, empty = self.armature_with_point()
        del empty["physik_bone"]
        for n in self.ENGINE_OPS:
            self.assert_report(run_op(getattr(bpy.ops.physik, n)), "empty '%s'" % empty.name,
                               "field 'physik_bone'", "no bone")

    def test_control_point_with_an_unknown_bone(self):
        arm, empty = self.armature_with_point()
        empty["physik_bone"] = "wing"
        self.assert_report(run_op(bpy.ops.physik.solve), "unknown bone 'wing'", "armature 'elbow'")

    def test_control_point_with_an_invalid_bone_name(self):
        arm, empty = self.armature_with_point()
        for bad, why in ((5, "expected a string"), ("fore,arm", "the bones CSV")):
            empty["physik_bone"] = bad
            self.assert_report(run_op(bpy.ops.physik.solve), "not a valid bone name", why)

    def test_control_point_with_no_armature_or_bad_alpha(self):
        arm, empty = self.armature_with_point()
        empty["physik_alpha"] = 1.5
        self.assert_report(run_op(bpy.ops.physik.solve), "physik_alpha", "outside [0, 1]")
        empty["physik_alpha"] = 1.0
        empty["physik_spring"] = "rubber"
        self.assert_report(run_op(bpy.ops.physik.solve), "physik_spring", "unknown law")
        del empty["physik_spring"]
        del empty["physik_armature"]
        self.assert_report(run_op(bpy.ops.physik.solve), "physik_armature", "no armature")

    def test_add_control_point_bad_bone(self):
        _, arm = build("elbow")
        arm.data.bones.active = None
        self.assert_report(run_op(bpy.ops.physik.add_control_point), "no active bone")
        self.assert_report(run_op(bpy.ops.physik.add_control_point, bone="wing"),
                           "unknown bone 'wing'")
        self.assertEqual([o.type for o in bpy.data.objects], ['ARMATURE'])

    def test_no_control_points(self):
        _, arm = build("elbow")
        self.assert_report(run_op(bpy.ops.physik.solve), "control points", "none: add one")

    def test_two_roots_and_a_loose_child(self):
        _, arm = build("chain3")
        bpy.ops.object.mode_set(mode='EDIT')
        arm.data.edit_bones["b2"].use_connect = False
        arm.data.edit_bones["b2"].head = (0.0, 0.5, 2.0)  # away from b1's tail
        bpy.ops.object.mode_set(mode='OBJECT')
        control_points.add_control_point(bpy.context, arm, "b2")
        bpy.context.view_layer.objects.active = arm
        self.assert_report(run_op(bpy.ops.physik.solve), "bone 'b2'", "does not meet the tail")
        bpy.ops.object.mode_set(mode='EDIT')
        arm.data.edit_bones["b2"].parent = None
        bpy.ops.object.mode_set(mode='OBJECT')
        self.assert_report(run_op(bpy.ops.physik.solve), "a second root")

    def test_sheared_object(self):
        arm, _ = self.armature_with_point()
        arm.scale = (1.0, 2.0, 1.0)
        bpy.context.view_layer.update()
        self.assert_report(run_op(bpy.ops.physik.solve), "non-uniform object scale")

    def test_missing_engine_is_reported(self):
        from physik_addon import engine
        if engine.available():
            self.skipTest("the physik module is importable here")
        arm, _ = self.armature_with_point()
        head, rot = armature_io.read_pose(arm)
        for n in self.ENGINE_OPS:
            self.assert_report(run_op(getattr(bpy.ops.physik, n)),
                               "the physik Python module is not built; see blender/README.md")
        # nothing moved and no start pose was recorded
        self.assertNotIn(operators.START_POSE, arm)
        self.assertLess((armature_io.read_pose(arm)[0] - head).length, 1e-12)


def main():
    suite = unittest.defaultTestLoader.loadTestsFromModule(sys.modules[__name__])
    result = unittest.TextTestRunner(verbosity=2, stream=sys.stdout).run(suite)
    sys.exit(0 if result.wasSuccessful() else 1)


main()
