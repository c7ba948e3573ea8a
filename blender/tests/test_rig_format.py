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
}


def cli(*args):
    return subprocess.run([BINARY] + list(args), capture_output=True, text=True)


@unittest.skipIf(not BINARY, "PHYSIK_BINARY not set")
class TestAgainstTheEngine(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.nolimits = os.path.join(self.tmp.name, "none.json")
        with open(self.nolimits, "w") as f:
            json.dump({"limits_deg": {}}, f)

    def tearDown(self):
        self.tmp.cleanup()

    def test_shipped_rigs_are_canonicalised_as_the_engine_does(self):
        rigs = os.path.join(REPO, "models", "rigs")
        for name in sorted(os.listdir(rigs)):
            path = os.path.join(rigs, name)
            out = os.path.join(self.tmp.name, name)
            run = cli("rig", "limits", path, self.nolimits, "--out", out)
            self.assertEqual(run.returncode, 0, run.stderr)
            with open(out) as f:
                engine = json.load(f)
            mine = rf.load_rig(path)
            self.assertEqual([b["name"] for b in mine["bones"]], [b["name"] for b in engine["bones"]])
            for a, b in zip(mine["bones"], engine["bones"]):
                self.assertEqual(a["parent"], b["parent"])
                for key in ("head", "tail"):
                    self.assertLess(max(abs(x - y) for x, y in zip(a[key], b[key])), 1e-12, name)
                for k in range(3):
                    self.assertLess(max(abs(x - y) for x, y in zip(a["rest_frame"][k],
                                                                   b["rest_frame"][k])), 1e-12, name)
                self.assertAlmostEqual(rf.bone_mass(mine, a), b["mass"], delta=1e-12)
                self.assertAlmostEqual(rf.bone_radius(mine, a), b["radius"], delta=1e-15)
                self.assertEqual(a.get("limits_deg", {}).keys(), b.get("limits_deg", {}).keys())

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
