"""The add-on's rig reader (blender/physik_addon/rig_format.py) against the engine's own loader,
without Blender (ctest: blender_rig_format, /usr/bin/python3):
  - every shipped rig gives the canonical rig that `physik rig limits RIG {}` writes (snapped
    heads, re-orthonormalised frames, masses) to 1e-12;
  - every bad rig file gives exactly the CLI's one-line message (and the CLI exits 2);
  - the quaternion helpers on known rotations.
PHYSIK_BINARY names the CLI (ctest passes it); without it the cross-checks are skipped.
"""
import json
import math
import os
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.abspath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, os.path.join(REPO, "blender"))
from physik_addon import rig_format as rf  # noqa: E402

BINARY = os.environ.get("PHYSIK_BINARY")
A = {"name": "a", "parent": None, "head": [0, 0, 0], "tail": [0, 0, 1]}
B = {"name": "b", "parent": "a", "head": [0, 0, 1], "tail": [0, 0, 2]}
C = {"name": "c", "parent": "a", "head": [0, 0, 1], "tail": [1, 0, 1]}
D = {"name": "d", "parent": "b", "head": [0, 0, 2], "tail": [0, 0, 3]}
BAD = {
    "zero": [A, dict(B, tail=[0, 0, 1])],
    "parent": [A, dict(B, parent="zz")],
    "roots": [A, dict(B, parent=None)],
    "gap": [A, dict(B, head=[0, 0, 1.5])],
    "minmax": [A, dict(B, limits_deg={"x": [20.5, 10]})],
    "range": [A, dict(B, limits_deg={"z": [-190, 10]})],
    "axis": [dict(A, limits_deg={"w": [0, 1]})],
    "unknown": [dict(A, wings=1)],
    "nonnum": [dict(A, head=[0, "q", 0])],
    "dup": [A, dict(B, name="a")],
    "cycle": [dict(A, parent="b"), B],
    "frame": [dict(A, rest_frame=[[0, 1, 0], [1, 0, 0], [0, 0, 1]])],
    "frame_y": [dict(A, rest_frame=[[1, 0, 0], [0, 1, 0], [0, 0, 1]])],
    "mass": [dict(A, mass=-1)],
    "both_mass": [dict(A, mass=1, mass_per_length=1)],
    "roll_and_frame": [dict(A, roll_deg=3, rest_frame=[[1, 0, 0], [0, 0, 1], [0, -1, 0]])],
    "empty_name": [dict(A, name="")],
    "missing_tail": [{"name": "a", "parent": None, "head": [0, 0, 0]}],
    "not_object": [5],
    "parent_empty": [A, dict(B, parent="")],
    "parent_type": [A, dict(B, parent=5)],
    "name_type": [dict(A, name=5)],
    "control_char": [dict(A, name="a\tb")],
    "coordinate": [dict(A, tail=[0, 0, 2e9])],
    "mass_range": [dict(A, mass=1e10)],
    "mass_null": [dict(A, mass=None)],
    "mpl_range": [dict(A, mass_per_length=1e-12)],
    "radius_range": [dict(A, radius=1e-10)],
    "inertia_sign": [dict(A, inertia_local=[1, -1, 1])],
    "inertia_range": [dict(A, inertia_local=[1, 1, 1e-30])],
    "inertia_triangle": [dict(A, inertia_local=[1, 1, 3])],
    # welds (rig.h "Welds"): C and D are children of A beside B
    "weld_root": [dict(A, weld="a")],
    "weld_type": [A, dict(B, weld=5)],
    "weld_empty": [A, dict(B, weld="")],
    "weld_unknown": [A, dict(B, weld="zz")],
    "weld_itself": [A, dict(B, weld="b")],
    "weld_limits": [A, dict(B, weld="a", limits_deg={"x": [-10, 10]})],
    "weld_cycle": [A, dict(B, weld="c"), dict(C, weld="b")],
    "weld_later": [A, dict(B, weld="c"), C],
    "weld_cousin": [A, B, C, dict(D, weld="c")],
    "root_limits": [dict(A, limits_deg={"x": [-10, 10]})],
}
# a valid rig with every optional field: roll, an inexact frame, an unsnapped head, mass and
# mass per length, radius, explicit moments (and moments the engine reads as none: all within
# Eigen's isZero()), defaults, free text
EVERY_FIELD = {
    "name": "every", "comment": "c", "source": ["s", "t"], "units": "m",
    "collision_exclude": [["a", "c"]],
    "defaults": {"mass_per_length": 2.5, "radius": 0.25},
    "bones": [
        dict(A, roll_deg=33.3, mass=1.5, inertia_local=[0.3, 0.2, 0.25], comment="root"),
        dict(B, head=[0, 0, 1.0004], tail=[0.1, 0.2, 2], mass_per_length=0.7, radius=0.1),
        {"name": "c", "parent": "b", "head": [0.1, 0.2, 2], "tail": [0.1, 1.2, 2],
         "rest_frame": [[0.9999, 0, 0], [0, 1, 0], [0, 0, 1]], "inertia_local": [1e-13] * 3,
         "limits_deg": {"x": [-10, 20], "z": [0, 0]}},
    ]}
# whole files (bytes): top-level fields, and what the JSON reader refuses
BAD_FILES = {
    "top_name": json.dumps({"name": 5, "bones": [A]}).encode(),
    "defaults_type": json.dumps({"defaults": [], "bones": [A]}).encode(),
    "defaults_value": json.dumps({"defaults": {"radius": -1}, "bones": [A]}).encode(),
    "no_bones": json.dumps({"bones": []}).encode(),
    "bones_type": json.dumps({"bones": {}}).encode(),
    "top_type": b"[1, 2]",
    "top_unknown": json.dumps({"wings": 1, "bones": [A]}).encode(),
    "root_value": json.dumps({"root": "hinged", "bones": [A]}).encode(),
    "root_type": json.dumps({"root": 1, "bones": [A]}).encode(),
    "fixed_root_limits": json.dumps(
        {"root": "fixed", "bones": [dict(A, limits_deg={"x": [-10, 10]})]}).encode(),
    "deep": b'{"comment": ' + b"[" * 300 + b"]" * 300 + b', "bones": []}',
    "source_type": json.dumps({"source": 5, "bones": [A]}).encode(),
    "source_note": json.dumps({"source": ["a", 5], "bones": [A]}).encode(),
    "exclude_type": json.dumps({"collision_exclude": 5, "bones": [A, B]}).encode(),
    "exclude_pair": json.dumps({"collision_exclude": [["a"]], "bones": [A, B]}).encode(),
    "exclude_unknown": json.dumps({"collision_exclude": [["a", "zz"]], "bones": [A, B]}).encode(),
    "exclude_itself": json.dumps({"collision_exclude": [["b", "b"]], "bones": [A, B]}).encode(),
}
# refused by both, in each JSON parser's own words after this common prefix
BAD_SYNTAX = {"syntax": b"{not json", "nan": b'{"bones": [NaN]}',
              "not_utf8": b'{"bones": [{"name": "a\xffb"}]}'}


def cli(*args):
    return subprocess.run([BINARY] + list(args), capture_output=True, text=True, errors="replace")


@unittest.skipIf(not BINARY, "PHYSIK_BINARY not set")
class TestAgainstTheEngine(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.nolimits = os.path.join(self.tmp.name, "none.json")
        with open(self.nolimits, "w") as f:
            json.dump({"limits_deg": {}}, f)

    def tearDown(self):
        self.tmp.cleanup()

    def assert_canonical_as_the_engine(self, path):
        out = os.path.join(self.tmp.name, "canonical.json")
        run = cli("rig", "limits", path, self.nolimits, "--out", out)
        self.assertEqual(run.returncode, 0, run.stderr)
        with open(out) as f:
            engine = json.load(f)
        mine = rf.load_rig(path)
        name = os.path.basename(path)
        self.assertEqual([b["name"] for b in mine["bones"]], [b["name"] for b in engine["bones"]])
        for a, b in zip(mine["bones"], engine["bones"]):
            self.assertEqual(a["parent"], b["parent"])
            for key in ("head", "tail"):
                self.assertLess(max(abs(x - y) for x, y in zip(a[key], b[key])), 1e-12, name)
            for k in range(3):
                self.assertLess(max(abs(x - y) for x, y in zip(a["rest_frame"][k],
                                                               b["rest_frame"][k])), 1e-12, name)
            self.assertAlmostEqual(rf.bone_mass(a), b["mass"], delta=1e-12)
            # the engine writes a radius that most bones share once, in its defaults
            radius = b.get("radius", engine["defaults"]["radius"])
            self.assertAlmostEqual(rf.bone_radius(mine, a), radius, delta=1e-15)
            self.assertEqual(a.get("limits_deg", {}).keys(), b.get("limits_deg", {}).keys())
            # the engine writes moments only where they are not the cylinder's
            if "inertia_local" in b:
                self.assertEqual(list(a["inertia_local"]), b["inertia_local"], name)

    def test_shipped_rigs_are_canonicalised_as_the_engine_does(self):
        rigs = os.path.join(REPO, "models", "rigs")
        for name in sorted(os.listdir(rigs)):
            self.assert_canonical_as_the_engine(os.path.join(rigs, name))

    def test_every_optional_field_is_read_as_the_engine_does(self):
        path = os.path.join(self.tmp.name, "every_field.json")
        with open(path, "w") as f:
            json.dump(EVERY_FIELD, f)
        self.assert_canonical_as_the_engine(path)

    def test_a_byte_order_mark_is_skipped_as_the_engine_does(self):
        path = self.write("bom.json", b"\xef\xbb\xbf" + json.dumps(EVERY_FIELD).encode())
        self.assert_canonical_as_the_engine(path)

    def engine_message(self, path):
        run = cli("rig", "limits", path, self.nolimits)
        self.assertEqual(run.returncode, 2, path)
        return run.stderr.strip().replace("physik: error: ", "", 1)

    def mine_message(self, path):
        with self.assertRaises(rf.InputError, msg=path) as ctx:
            rf.load_rig(path)
        return str(ctx.exception)

    def write(self, name, data):
        path = os.path.join(self.tmp.name, name)
        with open(path, "wb") as f:
            f.write(data)
        return path

    def test_bad_whole_files_give_the_engine_message(self):
        for case, data in BAD_FILES.items():
            path = self.write(case + ".json", data)
            self.assertEqual(self.mine_message(path), self.engine_message(path), case)
        for case, data in BAD_SYNTAX.items():
            path = self.write(case + ".json", data)
            for message in (self.mine_message(path), self.engine_message(path)):
                self.assertTrue(message.startswith(path + ": invalid JSON: "), message)
        path = os.path.join(self.tmp.name, "absent.json")
        self.assertEqual(self.mine_message(path), self.engine_message(path))

    def test_bad_files_give_the_engine_message(self):
        for case, bones in BAD.items():
            path = os.path.join(self.tmp.name, case + ".json")
            with open(path, "w") as f:
                json.dump({"bones": bones}, f)
            run = cli("rig", "limits", path, self.nolimits)
            self.assertEqual(run.returncode, 2, case)
            engine = run.stderr.strip().replace("physik: error: ", "", 1)
            with self.assertRaises(rf.InputError, msg=case) as ctx:
                rf.load_rig(path)
            self.assertEqual(str(ctx.exception), engine, case)


class TestHelpers(unittest.TestCase):
    def test_quaternion_of_a_rotation(self):
        for axis, angle in (((1, 0, 0), 0.3), ((0, 1, 0), 2.9), ((0.6, 0, 0.8), math.pi - 1e-9),
                            ((0.48, -0.6, 0.64), 1.7), ((0, 0, 1), 0.0)):
            q = rf.quat_axis_angle(axis, angle)
            back = rf.quat_from_axes(rf.quat_axes(q))
            self.assertLess(min(max(abs(x - y) for x, y in zip(q, back)),
                                max(abs(x + y) for x, y in zip(q, back))), 1e-12)
            v = rf.rotation_vector(q)
            self.assertLess(max(abs(x - angle * a) for x, a in zip(v, axis)), 1e-9)

    def test_frame_from_roll(self):
        f = rf.frame_from_roll((0, 0, 0), (0, 0, 2), 0.0)  # +Y turned onto +Z about x
        self.assertLess(max(abs(x - y) for x, y in zip(f[1], (0, 0, 1))), 1e-15)
        self.assertLess(max(abs(x - y) for x, y in zip(f[2], (0, -1, 0))), 1e-15)
        f = rf.frame_from_roll((0, 0, 0), (0, -1, 0), math.pi / 2)  # antiparallel: pi about Z
        self.assertLess(max(abs(x - y) for x, y in zip(f[1], (0, -1, 0))), 1e-15)

    def test_bone_names(self):
        self.assertIsNone(rf.bone_name_problem("hand.L"))
        self.assertIsNone(rf.bone_name_problem("é" * 31))  # 62 bytes
        self.assertIn("63 bytes", rf.bone_name_problem("é" * 32))
        self.assertIn("CSV", rf.bone_name_problem('a"b'))


if __name__ == "__main__":
    unittest.main()
