"""What goes into Blender comes out: rig files through an armature and back (ctest:
blender_round_trip, with the physik module and the CLI):

    blender -b --factory-startup --python-exit-code 1 --python blender/tests/test_round_trip.py \
        -- --repo . --pythonpath build/python --binary build/physik \
        [--mjcf /usr/share/mujoco/model/humanoid/humanoid.xml]

The rigs: every shipped rig (models/rigs/*.json), MuJoCo's humanoid converted by
`physik rig from-mjcf`, pinhead through BVH (`physik rig to-bvh`, then `rig from-bvh`: the
project's BVH reader), and a rig with every optional field of the format. Each is imported with
the operator (the engine's reader: physik.Rig.load) and exported with the operator, then:
  - field by field, the exported file equals the original: every key, every string, every
    number exactly (tolerance 0: the armature keeps the file's doubles, rig_record.py; Blender's
    own single-precision copy is ~1e-7 of each value off, which is enough to change a run);
  - the same run: physik.Simulation of the same scene on the exported rig and on the original
    gives the same final_state_hash and step count (a scene pulling the last bone, the root's
    head held; for pinhead also Fig 9's own scene);
  - Blender's own values (the records removed) are the engine's canonical rig within single
    precision (positions 1e-6 of the rig's size, frame components 1e-5, limits 1e-4 deg); their
    run's hash is printed, not asserted (it may or may not differ);
  - Solve on the imported humanoid with a control point is `physik simulate` on the rig file
    with the same control points and settings (same state hash, steps, converged);
  - the add-on's own reader (rig_format.py, used without the module) builds the same armature
    as the engine's reader, bit for bit (heads, tails, rest matrices, IK settings, properties),
    which is why the add-on keeps it.
The table printed at the end is the result per rig.
"""
import copy
import json
import math
import os
import subprocess
import sys
import tempfile
import unittest

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from blender_harness import clear_scene, enable_addon, script_args  # noqa: E402
from test_rig_format import EVERY_FIELD  # noqa: E402

ARGS = script_args(
    (["--pythonpath"], {"required": True, "help": "the folder holding the physik package"}),
    (["--binary"], {"required": True, "help": "the physik CLI"}),
    (["--mjcf"], {"default": "/usr/share/mujoco/model/humanoid/humanoid.xml",
                  "help": "a MuJoCo model to convert (Debian: libmujoco-samples)"}))
REPO = os.path.abspath(ARGS.repo)
enable_addon(REPO, "test_round_trip.py", ARGS.pythonpath)

from physik_addon import (armature_io, control_points, engine, rig_format,  # noqa: E402
                          rig_record, scene_dict)

POS_TOL = 1e-6     # x the rig's size: Blender's single-precision positions
FRAME_TOL = 1e-5   # frame components: single precision, chained from the parents in object mode
LIMIT_TOL = 1e-4   # degrees: a single-precision radian, 8e-8 rad at 160 deg
TMP = tempfile.TemporaryDirectory()
RESULTS = []       # one row per rig, printed at the end


def cli(*args):
    p = subprocess.run([ARGS.binary] + list(args), capture_output=True, text=True)
    if p.returncode != 0:
        raise RuntimeError("physik %s: %s" % (" ".join(args), p.stderr.strip()))


def rig_files():
    """{name: path} of every rig the test round-trips."""
    rigs = os.path.join(REPO, "models", "rigs")
    out = {n[:-5]: os.path.join(rigs, n) for n in sorted(os.listdir(rigs)) if n.endswith(".json")}
    if not os.path.isfile(ARGS.mjcf):
        raise SystemExit("test_round_trip.py: %s is missing (Debian: apt-get install "
                         "libmujoco-samples; scripts/install-deps.sh does)" % ARGS.mjcf)
    out["humanoid (from-mjcf)"] = os.path.join(TMP.name, "humanoid.json")
    cli("rig", "from-mjcf", ARGS.mjcf, "--out", out["humanoid (from-mjcf)"])
    bvh = os.path.join(TMP.name, "pinhead.bvh")
    cli("rig", "to-bvh", out["pinhead"], "--out", bvh)
    out["pinhead (from-bvh)"] = os.path.join(TMP.name, "pinhead_bvh.json")
    cli("rig", "from-bvh", bvh, "--out", out["pinhead (from-bvh)"])
    out["every field"] = os.path.join(TMP.name, "every_field.json")
    with open(out["every field"], "w") as f:
        json.dump(EVERY_FIELD, f)
    return out


def load(path):
    with open(path) as f:
        return json.load(f)


def leaves(value, where=""):
    """[(path, leaf)] of a JSON value; bones keyed by name, so order does not matter."""
    if isinstance(value, dict):
        # a rig's bones (a source skeleton's joint lists its bones by name: a list of strings)
        if isinstance(value.get("bones"), list) and all(isinstance(b, dict)
                                                          for b in value["bones"]):
            value = dict(value, bones={b["name"]: b for b in value["bones"]})
        return [p for k in sorted(value) for p in leaves(value[k], where + "/" + str(k))]
    if isinstance(value, list):
        return [p for i, v in enumerate(value) for p in leaves(v, "%s[%d]" % (where, i))]
    return [(where, value)]


def compare(want, got):
    """(values compared, paths that differ, largest numeric difference)."""
    a, b = dict(leaves(want)), dict(leaves(got))
    differ = sorted(p for p in set(a) | set(b) if a.get(p, "absent") != b.get(p, "absent"))
    nums = [abs(a[p] - b[p]) for p in set(a) & set(b)
            if isinstance(a[p], (int, float)) and isinstance(b[p], (int, float))]
    return len(a), differ, max(nums, default=0.0)


def import_rig(path):
    assert bpy.ops.physik.import_rig(filepath=path) == {'FINISHED'}
    return bpy.context.active_object


def export_rig(obj, name):
    path = os.path.join(TMP.name, name)
    bpy.context.view_layer.objects.active = obj
    assert bpy.ops.physik.export_rig(filepath=path) == {'FINISHED'}
    return load(path)


def scene_for(rig_doc):
    """A scene on the rig: the last bone's tail pulled by a quarter of the rig's size, the
    root's head held; the implicit step with damping auto (stable on every rig here)."""
    canonical = engine.canonical_rig(rig_doc, "scene rig")
    bones = canonical["bones"]
    points = [p for b in bones for p in (b["head"], b["tail"])]
    size = max(max(p[k] for p in points) - min(p[k] for p in points) for k in range(3))
    last, root = bones[-1], bones[0]
    pull = [c + 0.25 * size * d / math.sqrt(2.25) for c, d in zip(last["tail"], (1, -1, 0.5))]
    return {"rig": rig_doc, "steps": 150, "params": {"scheme": "implicit",
                                                     "damping": "auto"},
            "control_points": [
                {"name": "pull", "bone": last["name"], "alpha": 1.0, "target": pull},
                {"name": "hold", "bone": root["name"], "alpha": 0.0, "target": root["head"]}]}


def run(scene):
    physik = engine.module()
    sim = physik.Simulation(physik.Scene.from_dict(scene, source="round trip"))
    return sim.run()


def without_records(obj):
    """Blender's own values of an armature: its rig with the records removed (on a copy)."""
    dup = obj.copy()
    dup.data = obj.data.copy()
    bpy.context.scene.collection.objects.link(dup)
    for pb in dup.pose.bones:
        del pb[rig_record.PROP]
    del dup.data[rig_record.PROP]
    bpy.context.view_layer.update()
    return armature_io.armature_to_rig(dup)


def blender_data(obj):
    """Everything Blender holds of an armature's rig, as Python values (exact)."""
    out = {}
    for b in obj.data.bones:
        pb = obj.pose.bones[b.name]
        ik = [getattr(pb, "%s_%s" % (f, a)) for f in ("lock_ik", "use_ik_limit", "ik_min",
                                                      "ik_max") for a in "xyz"]
        out[b.name] = (tuple(b.head_local), tuple(b.tail_local),
                       tuple(tuple(r) for r in b.matrix_local), tuple(ik),
                       json.dumps({k: pb[k] for k in pb.keys() if k != rig_record.PROP},
                                  default=list, sort_keys=True))
    return out


class TestRoundTrip(unittest.TestCase):
    def setUp(self):
        if bpy.context.object is not None and bpy.context.object.mode != 'OBJECT':
            bpy.ops.object.mode_set(mode='OBJECT')
        clear_scene()

    def check_blender_values(self, name, doc, own):
        """Blender's own copy against the engine's canonical rig: (position, frame, limit)."""
        canonical = {b["name"]: b for b in engine.canonical_rig(doc, name)["bones"]}
        files = {b["name"]: b for b in doc["bones"]}
        points = [p for b in canonical.values() for p in (b["head"], b["tail"])]
        size = max(max(abs(c) for c in p) for p in points)
        worst = [0.0, 0.0, 0.0]
        for b in own["bones"]:
            want = canonical[b["name"]]
            for key in ("head", "tail"):
                worst[0] = max(worst[0], max(abs(x - y) for x, y in zip(b[key], want[key])))
            for k in range(3):
                worst[1] = max(worst[1], max(abs(x - y) for x, y in
                                             zip(b["rest_frame"][k], want["rest_frame"][k])))
            for axis, lim in files[b["name"]].get("limits_deg", {}).items():
                worst[2] = max(worst[2], max(abs(x - y) for x, y in
                                             zip(lim, b["limits_deg"][axis])))
        self.assertLess(worst[0], POS_TOL * max(1.0, size), name)
        self.assertLess(worst[1], FRAME_TOL, name)
        self.assertLess(worst[2], LIMIT_TOL, name)
        return worst

    def check_rig(self, name, path):
        doc = load(path)
        obj = import_rig(path)
        back = export_rig(obj, "back.json")
        count, differ, largest = compare(doc, back)
        self.assertEqual(differ, [], name)
        self.assertEqual(back, doc, name)
        scene = scene_for(doc)
        want, got = run(scene), run(dict(scene, rig=back))
        self.assertFalse(want["diverged"], (name, want["divergence_reason"]))
        self.assertEqual((got["final_state_hash"], got["steps_run"]),
                         (want["final_state_hash"], want["steps_run"]), name)
        own = without_records(obj)
        worst = self.check_blender_values(name, doc, own)
        own_hash = run(dict(scene, rig=own))["final_state_hash"]
        RESULTS.append((name, len(doc["bones"]), count, largest, got["final_state_hash"],
                        "%d%s" % (got["steps_run"], "" if got["converged"] else "*"), worst,
                        own_hash == want["final_state_hash"]))
        return doc, back

    def test_every_rig(self):
        for name, path in rig_files().items():
            with self.subTest(rig=name):
                clear_scene()
                self.check_rig(name, path)

    def test_fig9_runs_the_same_on_the_round_tripped_pinhead(self):
        path = os.path.join(REPO, "models", "rigs", "pinhead.json")
        back = export_rig(import_rig(path), "pinhead_back.json")
        scene = load(os.path.join(REPO, "models", "scenes", "fig9_outstretched.json"))
        want, got = run(dict(scene, rig=load(path))), run(dict(scene, rig=back))
        self.assertTrue(want["converged"])
        self.assertEqual((got["final_state_hash"], got["steps_run"], got["steps_to_converge"]),
                         (want["final_state_hash"], want["steps_run"], want["steps_to_converge"]))
        # and the CLI on the scene file itself: the same run again
        out = os.path.join(TMP.name, "fig9")
        cli("simulate", os.path.join(REPO, "models", "scenes", "fig9_outstretched.json"),
            "--out", out, "--quiet")
        self.assertEqual(load(os.path.join(out, "summary.json"))["final_state_hash"],
                         got["final_state_hash"])

    def test_solve_on_the_imported_humanoid_is_the_cli_on_its_file(self):
        # what a user does: import a converted model, add a control point, Solve; the CLI on
        # the rig file with the same control points and settings runs the same steps
        path = rig_files()["humanoid (from-mjcf)"]
        arm = import_rig(path)
        s = bpy.context.scene.physik
        s.max_steps, s.scheme, s.damping_mode = 400, "implicit", 'AUTO'  # stable here
        control_points.add_control_point(bpy.context, arm, "right_lower_arm", 1.0,
                                         (0.4, -0.5, 1.3))
        bpy.context.view_layer.objects.active = arm
        scene = scene_dict.build_scene(bpy.context, arm, solve=True)
        self.assertEqual(scene["rig"], load(path))
        self.assertEqual(scene["initial_pose"], {"rotation_deg": {}})
        _, summary = engine.solve(scene)
        file_scene = dict(scene, rig=path)
        scene_path = os.path.join(TMP.name, "humanoid_scene.json")
        with open(scene_path, "w") as f:
            json.dump(file_scene, f)
        out = os.path.join(TMP.name, "humanoid_run")
        p = subprocess.run([ARGS.binary, "simulate", scene_path, "--out", out, "--quiet"],
                           capture_output=True, text=True)
        self.assertIn(p.returncode, (0, 3), p.stderr)
        cli_summary = load(os.path.join(out, "summary.json"))
        for key in ("final_state_hash", "steps_run", "converged", "diverged"):
            self.assertEqual(summary[key], cli_summary[key], key)
        print("\nSolve on the imported humanoid: %d steps, converged %s, largest residual %.3g; "
              "physik simulate on its file: the same state hash %s"
              % (summary["steps_run"], summary["converged"], max(summary["final_residuals"]),
                 cli_summary["final_state_hash"]))

    def test_the_add_ons_own_reader_builds_the_same_armature(self):
        for name, path in rig_files().items():
            with self.subTest(rig=name):
                clear_scene()
                doc = load(path)
                by_engine = armature_io.rig_to_armature(
                    engine.canonical_rig(doc, path), bpy.context, doc=copy.deepcopy(doc))
                by_addon = armature_io.rig_to_armature(
                    rig_format.parse_rig(doc, path), bpy.context, doc=copy.deepcopy(doc))
                self.assertEqual(blender_data(by_addon), blender_data(by_engine), name)
                self.assertEqual(armature_io.armature_to_rig(by_addon), doc, name)
                self.assertEqual(armature_io.armature_to_rig(by_engine), doc, name)


def print_results():
    print("\nround trip through a Blender armature (records: the file's doubles kept; own: "
          "Blender's single-precision values)")
    print("%-22s %5s %7s %9s %-18s %6s %-27s %s" % (
        "rig", "bones", "values", "max diff", "state hash (both)", "steps",
        "own: pos / frame / limit deg", "own: same hash"))
    for name, bones, count, largest, digest, steps, worst, same in RESULTS:
        print("%-22s %5d %7d %9.3g %-18s %6s %-27s %s" % (
            name, bones, count, largest, digest, steps, "%.1e / %.1e / %.1e" % tuple(worst),
            "yes" if same else "no"))
    print("(steps: * = not converged within the scene's 150 steps; both runs alike)")


def main():
    suite = unittest.defaultTestLoader.loadTestsFromModule(sys.modules[__name__])
    result = unittest.TextTestRunner(verbosity=2, stream=sys.stdout).run(suite)
    print_results()
    TMP.cleanup()
    sys.exit(0 if result.wasSuccessful() else 1)


main()
