#!/usr/bin/env python3
"""The viewer: `physik view` (cli/cmd_view.cpp, viewer/) on run folders.

ViewCommandTest (no browser): bad input exits 2 naming the folder and what is missing (not a
folder, not a run folder, an empty trajectory, a short row, rigs with other bones, a contact of
a bone the rig does not have, a first frame past the viewer's bounds, a step without its row of
targets); a value past the bounds later in a run (a diverged run's 5e193, a hand-edited 1e308)
ends the page's frames there with a note naming the file, line and column, and no decoded frame
array holds a non-finite number; long runs are decimated to the cap and the page says so; a run
folder's contacts.csv is in the page (only where there is one); a scene's box obstacles are in
the page with their names, centres, half extents and rotations (only where it has some); the
page loads nothing (no src or href, a content policy that forbids every load).

BrowserTest, in headless Chromium (Debian's chromium, chromium-driver and python3-selenium;
SwiftShader renders WebGL): the page loads from file:// with no console error and a canvas;
at 1200 px wide, for window heights around where the canvas makes the page scroll, no horizontal
scrollbar and the canvas within its stage;
moving the slider changes the rendered pixels and a paused frame stays the same; Play
advances; an overlay of two runs draws both colours; a rig bent past a locked joint is drawn
in the highlight colour; a rod dropped on the floor (a run with contacts.csv) shows no contact
marker while it falls and its two end contacts once it lies there, and the contacts toggle
hides them; a rod falling onto a turned box obstacle shows the box's colour inside the box's
outline (its corners from the scene's numbers, projected by the page's camera) and not outside
it, the "obstacles" toggle hides it, and a scene without a box shows none of its colour; a rig,
scene, folder and title of hostile names (</script><img ...>)
show as text and run nothing; REPORT.html (analysis/report.py) shows an experiment's runs in
the viewer, in an iframe beside its figure, with its hostile title as text. It skips, with a
message, only where Chromium cannot start.
Screenshots go to PHYSIK_VIEWER_SHOTS (default build/viewer_screenshots).

Run: PHYSIK_BINARY=build/physik python3 tests/viewer/test_viewer.py [ViewCommandTest|BrowserTest]
(ctest: viewer_command, viewer_browser; exit 77 = skipped).
"""
import base64
import colorsys
import io
import json
import math
import os
import re
import shutil
import struct
import subprocess
import sys
import tempfile
import time
import unittest
from html.parser import HTMLParser

REPO = os.environ.get("PHYSIK_SOURCE_DIR") or os.path.dirname(
    os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BINARY = os.environ.get("PHYSIK_BINARY") or os.path.join(REPO, "build", "physik")
sys.path.insert(0, os.path.join(REPO, "analysis"))
sys.path.insert(0, os.path.join(REPO, "tests"))
import headless_chromium  # noqa: E402
from scene_boxes import box_corners  # noqa: E402

SHOTS = os.environ.get("PHYSIK_VIEWER_SHOTS") or os.path.join(REPO, "build", "viewer_screenshots")
SKIPPED = 77

# the viewer's colours (viewer/viewer.js PALETTE, HIGHLIGHT, CONTACT_COLOR, BOX_COLOR): hues in
# degrees
BLUE, ORANGE, HIGHLIGHT, CONTACT, BOX = 205, 28, 346, 300, 44
AXIS_X, AXIS_Y, AXIS_Z = 0, 120, 225  # AXIS_COLORS
HOSTILE = '</script><img src=x onerror="window.__pwned=1;alert(1)">'
HOSTILE_BONE = '"><svg onload="window.__pwned=2">'
HOSTILE_POINT = "<script>window.__pwned=3</script>&amp;,\"tip\""
HOSTILE_FOLDER = "<img src=x onerror=alert(4)>"


def physik(*args):
    p = subprocess.run([BINARY] + [str(a) for a in args], capture_output=True, text=True)
    return p.returncode, p.stderr


def chain_rig(names=("b0", "b1", "b2"), name="chain3", locked_middle=False, middle_limits=None):
    """Three bones of length 1 up +Z, radius 0.2; optionally the middle joint locked, or limited
    by `middle_limits` (a limits_deg object)."""
    bones = []
    for k, n in enumerate(names):
        b = {"name": n, "parent": names[k - 1] if k else None, "head": [0, 0, k],
             "tail": [0, 0, k + 1], "radius": 0.2}
        if locked_middle and k == 1:
            b["limits_deg"] = {"x": [0, 0], "y": [0, 0], "z": [0, 0]}
        if middle_limits and k == 1:
            b["limits_deg"] = middle_limits
        bones.append(b)
    return {"name": name, "bones": bones}


def chain_scene(folder, rig, tip_x, point_names=("root", "tip"), steps=40):
    """A scene file in `folder`: the root's head pinned, the tip pulled sideways to x = tip_x."""
    os.makedirs(folder, exist_ok=True)
    with open(os.path.join(folder, "rig.json"), "w") as f:
        json.dump(rig, f)
    names = [b["name"] for b in rig["bones"]]
    scene = {"rig": "rig.json", "steps": steps, "control_points": [
        {"name": point_names[0], "bone": names[0], "alpha": 0.0, "target": [0, 0, 0]},
        {"name": point_names[1], "bone": names[2], "alpha": 1.0, "target": [tip_x, 0, 1.8]}]}
    path = os.path.join(folder, "scene.json")
    with open(path, "w") as f:
        json.dump(scene, f)
    return path


def drop_scene(folder):
    """A scene file in `folder`: a 1 m rod lying 0.3 above the floor (its capsule's underside
    0.24 above), falling under gravity onto the ground, where it lies from about 0.22 s on."""
    os.makedirs(folder, exist_ok=True)
    rig = {"name": "rod", "bones": [{"name": "rod", "parent": None, "head": [0, 0, 0.3],
                                     "tail": [1, 0, 0.3], "radius": 0.06}]}
    with open(os.path.join(folder, "rod.json"), "w") as f:
        json.dump(rig, f)
    scene = {"rig": "rod.json", "steps": 100, "gravity": [0, 0, -9.81], "ground": {"height": 0},
             "params": {"dt": 0.01}}
    path = os.path.join(folder, "scene.json")
    with open(path, "w") as f:
        json.dump(scene, f)
    return path


# a seat for the rod of drop_scene: its top at z = 0, its long side turned 30 deg about z (the
# rod, along x, lands across it with both ends on it)
SEAT = {"name": "seat", "box": {"center": [0.5, 0, -0.1], "half_extents": [0.6, 0.3, 0.1],
                                "rotation_deg": [0, 0, 30]}}
# a box away from the rod, turned about all three axes
SHELF = {"name": "shelf", "box": {"center": [0.2, 3, 0.5], "half_extents": [0.3, 0.2, 0.05],
                                  "rotation_deg": [10, -20, 35]}}


def box_scene(folder, obstacles):
    """drop_scene's rod falling onto `obstacles` (scene entries) instead of a floor."""
    path = drop_scene(folder)
    with open(path) as f:
        scene = json.load(f)
    del scene["ground"]
    scene["obstacles"] = obstacles
    with open(path, "w") as f:
        json.dump(scene, f)
    return path


def rotation_quaternion(rotation_deg):
    """The rotation of a rotation vector in degrees (the scene format's `rotation_deg`) as a unit
    quaternion, x y z w (w >= 0)."""
    v = [math.radians(x) for x in rotation_deg]
    a = math.sqrt(sum(x * x for x in v))
    if a == 0:
        return [0.0, 0.0, 0.0, 1.0]
    return [math.sin(a / 2) * c / a for c in v] + [math.cos(a / 2)]


def simulate(scene, out, *extra):
    status, err = physik("simulate", scene, "--out", out, "--quiet", *extra)
    if status != 0:
        raise RuntimeError("simulate %s: exit %d: %s" % (scene, status, err))
    return out


# each frame array of a run's page data and the typed array it decodes to (viewer/view_page.h)
FRAME_ARRAYS = {"steps": "i", "times": "d", "kinetic_energy": "f", "max_residual": "f",
                "max_residual_point": "i", "positions": "f", "targets": "f", "limit_excess": "f"}
CONTACT_ARRAYS = {"start": "i", "bones": "i", "values": "f"}


# bone targets given to chain_scene's run on the command line (cli/bone_target_options.cpp): b2
# turned toward the frame 90 deg about world x (w x y z), b1 aimed at a point, b0's head pinned
# where it starts (the origin)
TARGET_Q = (math.sqrt(0.5), math.sqrt(0.5), 0.0, 0.0)
BONE_TARGET_ARGS = ("--orientation-target", "b2=%r,%r,%r,%r" % TARGET_Q, "--aim", "b1=2,0,1",
                    "--pin", "b0")


def decoded(b64, code):
    """A base64 typed array of the page as a tuple of numbers."""
    raw = base64.b64decode(b64)
    size = struct.calcsize("<" + code)
    return struct.unpack("<%d%s" % (len(raw) // size, code), raw)


def page_frames(run):
    """Every frame array of one run's page data, decoded: {name: tuple}."""
    out = {k: decoded(run[k], c) for k, c in FRAME_ARRAYS.items() if run.get(k) is not None}
    for k, c in CONTACT_ARRAYS.items():
        if "contacts" in run:
            out["contacts." + k] = decoded(run["contacts"][k], c)
    return out


def page_data(path):
    """The runs' JSON of a page (its physik-data element)."""
    text = open(path, encoding="utf-8").read()
    m = re.search(r'<script type="application/json" id="physik-data">(.*?)</script>', text, re.S)
    return json.loads(m.group(1))


class _Loads(HTMLParser):
    """Every src or href attribute of the page's markup (script text is not markup)."""

    def __init__(self):
        super().__init__()
        self.loads = []
        self.policy = None

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        self.loads += [(tag, k, v) for k, v in attrs if k in ("src", "href")]
        if tag == "meta" and a.get("http-equiv") == "Content-Security-Policy":
            self.policy = a.get("content")


class ViewCommandTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="physik_view_")
        cls.run_dir = simulate(chain_scene(os.path.join(cls.tmp, "s"), chain_rig(), 1.5),
                           os.path.join(cls.tmp, "run"), "--steps", "100")

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def error(self, *args):
        status, err = physik("view", *args)
        self.assertEqual(status, 2, err)
        lines = [l for l in err.splitlines() if l.startswith("physik: error: ")]
        self.assertEqual(len(lines), 1, err)
        return lines[0]

    def copy_run(self, name):
        dst = os.path.join(self.tmp, name)
        shutil.copytree(self.run_dir, dst)
        return dst

    def test_not_a_folder(self):
        missing = os.path.join(self.tmp, "missing")
        msg = self.error(missing, "--out", os.path.join(self.tmp, "x.html"))
        self.assertIn(missing + ": not a run folder: no such folder", msg)
        self.assertFalse(os.path.exists(missing))  # nothing created on the way

    def test_not_a_run_folder(self):
        run = self.copy_run("no_trajectory")
        os.remove(os.path.join(run, "trajectory.csv"))
        msg = self.error(run, "--out", os.path.join(self.tmp, "x.html"))
        self.assertIn(run + ": not a run folder: no trajectory.csv", msg)

    def test_empty_trajectory(self):
        run = self.copy_run("empty")
        path = os.path.join(run, "trajectory.csv")
        header = open(path).readline()
        open(path, "w").write(header)
        msg = self.error(run, "--out", os.path.join(self.tmp, "x.html"))
        self.assertIn(path + ": an empty trajectory", msg)

    def test_a_short_row(self):
        run = self.copy_run("short")
        path = os.path.join(run, "trajectory.csv")
        lines = open(path).read().splitlines()
        lines[3] = lines[3].rsplit(",", 1)[0]
        open(path, "w").write("\n".join(lines) + "\n")
        msg = self.error(run, "--out", os.path.join(self.tmp, "x.html"))
        self.assertIn(path + ": line 4: ", msg)
        self.assertIn("fields where the header has", msg)

    def test_rigs_with_other_bones(self):
        other = simulate(chain_scene(os.path.join(self.tmp, "s2"), chain_rig(("a", "b", "c")), 1),
                         os.path.join(self.tmp, "other"), "--steps", "5")
        msg = self.error(self.run_dir, other, "--out", os.path.join(self.tmp, "x.html"))
        self.assertIn(other + ": scene.json rig: field 'bones[0]': 'a'", msg)
        self.assertIn("an overlay draws runs of the same bones", msg)

    def test_the_report_writes_a_page_per_rig(self):
        # an experiment whose runs have two rigs (the contacts experiment's coils beside pinhead):
        # report.py overlays the runs of each rig on its own page and links both
        results = os.path.join(self.tmp, "report_rigs")
        runs = os.path.join(results, "e", "runs")
        shutil.copytree(self.run_dir, os.path.join(runs, "first"))
        simulate(chain_scene(os.path.join(self.tmp, "s3"), chain_rig(("a", "b", "c")), 1),
                 os.path.join(runs, "other"), "--steps", "5")
        shutil.copytree(self.run_dir, os.path.join(runs, "again"))
        with open(os.path.join(runs, "order.txt"), "w") as f:
            f.write("first\nother\nagain\n")
        with open(os.path.join(results, "e", "summary.json"), "w") as f:
            json.dump({"report": {"title": "two rigs"}}, f)
        done = subprocess.run([sys.executable, os.path.join(REPO, "analysis", "report.py"),
                               results, "--physik", BINARY], check=True, capture_output=True,
                              text=True)
        said = done.stdout + done.stderr  # physik view's line per page
        self.assertIn("view: 2 runs, ", said)  # first and again, overlaid
        self.assertIn("-> " + os.path.join(results, "e", "view.html"), said)
        self.assertIn("view: 1 run, ", said)
        self.assertIn("-> " + os.path.join(results, "e", "view-2.html"), said)
        with open(os.path.join(results, "REPORT.md")) as f:
            report = f.read()
        self.assertIn("(e/view.html)", report)
        self.assertIn("(e/view-2.html)", report)

    def test_decimated_to_the_cap_and_said(self):
        out = os.path.join(self.tmp, "cap.html")
        self.assertEqual(physik("view", self.run_dir, "--max-frames", "10", "--out", out)[0], 0)
        run = page_data(out)["runs"][0]
        self.assertEqual(run["rows_recorded"], 101)  # step 0 and 100 steps
        self.assertEqual(run["frames"], 10)
        steps = struct.unpack("<10i", base64.b64decode(run["steps"]))
        self.assertEqual(steps, (0, 11, 22, 33, 44, 56, 67, 78, 89, 100))  # round(k 100 / 9)
        said = [n for n in run["notes"] if "decimated: 101 recorded rows shown as 10 frames" in n]
        self.assertEqual(len(said), 1, run["notes"])

    def test_within_the_cap_every_row_and_no_note(self):
        out = os.path.join(self.tmp, "whole.html")
        self.assertEqual(physik("view", self.run_dir, "--max-frames", "101", "--out", out)[0], 0)
        run = page_data(out)["runs"][0]
        self.assertEqual(struct.unpack("<101i", base64.b64decode(run["steps"])),
                         tuple(range(101)))
        self.assertEqual([n for n in run["notes"] if "decimated" in n], [])

    def test_a_cap_below_two_frames(self):
        msg = self.error(self.run_dir, "--max-frames", "1", "--out",
                         os.path.join(self.tmp, "x.html"))
        self.assertIn("--max-frames", msg)
        self.assertIn("must be at least 2", msg)

    def test_bone_orientations_and_limits_are_in_the_page(self):
        out = os.path.join(self.tmp, "axes.html")
        self.assertEqual(physik("view", self.run_dir, "--out", out)[0], 0)
        run = page_data(out)["runs"][0]
        bones = run["bones"]
        self.assertEqual(bones["lengths"], [1.0, 1.0, 1.0])
        self.assertEqual(bones["limits"], [[None] * 3] * 3)  # chain_rig's bones are free
        self.assertEqual(len(bones["rest_in_parent"]), 3)
        quats = struct.unpack("<%df" % (run["frames"] * 3 * 4),
                              base64.b64decode(run["orientations"]))
        # unit quaternions, and at step 0 the rest pose: every bone along +Z, so its frame is
        # +90 deg about x from the world's (local +y up the bone)
        for k in range(0, len(quats), 4):
            self.assertAlmostEqual(sum(q * q for q in quats[k:k + 4]), 1.0, places=5)
        s = math.sqrt(0.5)
        for b in range(3):
            self.assertEqual([round(q, 6) for q in quats[4 * b:4 * b + 4]],
                             [round(s, 6), 0.0, 0.0, round(s, 6)])

    def test_an_older_table_without_orientations_still_shows(self):
        run = self.copy_run("older_table")
        path = os.path.join(run, "targets_and_limits.csv")
        rows = [l.split(",") for l in open(path).read().splitlines()]
        keep = [k for k, name in enumerate(rows[0]) if ".orient_" not in name]
        self.assertEqual(len(rows[0]) - len(keep), 12)  # 3 bones x w x y z
        open(path, "w").write("\n".join(",".join(r[k] for k in keep) for r in rows) + "\n")
        out = os.path.join(self.tmp, "older.html")
        status, err = physik("view", run, "--out", out)
        self.assertEqual(status, 0, err)
        data = page_data(out)["runs"][0]
        self.assertIsNone(data["orientations"])
        self.assertTrue(any("no bone orientations" in n for n in data["notes"]), data["notes"])

    def test_contacts_are_in_the_page_only_where_recorded(self):
        drop = simulate(drop_scene(os.path.join(self.tmp, "d")), os.path.join(self.tmp, "drop"),
                        "--every", "5")
        out = os.path.join(self.tmp, "drop.html")
        self.assertEqual(physik("view", drop, "--out", out)[0], 0)
        run = page_data(out)["runs"][0]
        frames = run["frames"]
        start = struct.unpack("<%di" % (frames + 1), base64.b64decode(run["contacts"]["start"]))
        rows = open(os.path.join(drop, "contacts.csv")).read().splitlines()[1:]
        self.assertEqual(start[0], 0)
        self.assertEqual(start[-1], len(rows))  # every row, each at its frame
        self.assertEqual(start[1], 0)  # step 0: no contact
        self.assertEqual(start[-1] - start[-2], 2)  # lying on the floor: both ends
        plain = os.path.join(self.tmp, "plain_contacts.html")
        self.assertEqual(physik("view", self.run_dir, "--out", plain)[0], 0)
        self.assertNotIn("contacts", page_data(plain)["runs"][0])
        self.assertFalse(os.path.exists(os.path.join(self.run_dir, "contacts.csv")))

    def test_boxes_are_in_the_page_only_where_the_scene_has_them(self):
        run_dir = simulate(box_scene(os.path.join(self.tmp, "b"), [SEAT, SHELF]),
                           os.path.join(self.tmp, "boxes"), "--steps", "10")
        out = os.path.join(self.tmp, "boxes.html")
        self.assertEqual(physik("view", run_dir, "--out", out)[0], 0)
        boxes = page_data(out)["runs"][0]["boxes"]
        self.assertEqual([b["name"] for b in boxes], ["seat", "shelf"])  # the scene's order
        for got, given in zip(boxes, (SEAT, SHELF)):
            want = given["box"]
            for key in ("center", "half_extents"):
                self.assertEqual(len(got[key]), 3)
                for g, w in zip(got[key], want[key]):
                    self.assertAlmostEqual(g, w, delta=1e-12, msg=(given["name"], key))
            q, wq = got["quaternion"], rotation_quaternion(want["rotation_deg"])
            sign = 1 if q[3] >= 0 else -1  # q and -q are the same rotation
            self.assertEqual(len(q), 4)
            for g, w in zip(q, wq):
                self.assertAlmostEqual(sign * g, w, delta=1e-12, msg=(given["name"], q, wq))
        for plain in (self.run_dir,  # no contacts at all
                      simulate(drop_scene(os.path.join(self.tmp, "d3")),
                               os.path.join(self.tmp, "ground_only"), "--steps", "5")):
            page = os.path.join(self.tmp, "no_boxes.html")
            self.assertEqual(physik("view", plain, "--out", page)[0], 0)
            self.assertNotIn("boxes", page_data(page)["runs"][0])

    def test_bone_targets_are_in_the_page_only_where_the_scene_has_them(self):
        run_dir = simulate(chain_scene(os.path.join(self.tmp, "s_targets"), chain_rig(), 1.5),
                           os.path.join(self.tmp, "targets"), "--steps", "60", *BONE_TARGET_ARGS)
        # the run folder carries them: its scene.json is the scene as run
        with open(os.path.join(run_dir, "scene.json")) as f:
            scene = json.load(f)
        self.assertEqual([t["bone"] for t in scene["orientation_targets"]], ["b2"])
        self.assertEqual(scene["aim_targets"][0]["point"], [2, 0, 1])
        self.assertEqual(scene["pins"][0]["point"], [0, 0, 0])
        out = os.path.join(self.tmp, "targets.html")
        self.assertEqual(physik("view", run_dir, "--out", out)[0], 0)
        run = page_data(out)["runs"][0]
        bt = run["bone_targets"]
        self.assertEqual(len(bt["orientations"]), 1)
        self.assertEqual(bt["orientations"][0]["bone"], 2)
        w, x, y, z = TARGET_Q
        for got, want in zip(bt["orientations"][0]["quaternion"], (x, y, z, w)):  # x y z w
            self.assertAlmostEqual(got, want, delta=1e-12)
        self.assertEqual(bt["aims"], [{"bone": 1, "point": [2.0, 0.0, 1.0]}])
        self.assertEqual(bt["pins"], [{"bone": 0, "alpha": 0.0, "point": [0.0, 0.0, 0.0]}])
        self.assert_all_finite(run)
        page = os.path.join(self.tmp, "no_targets.html")
        self.assertEqual(physik("view", self.run_dir, "--out", page)[0], 0)
        self.assertNotIn("bone_targets", page_data(page)["runs"][0])

    def test_a_contact_of_a_bone_the_rig_has_not(self):
        drop = simulate(drop_scene(os.path.join(self.tmp, "d2")), os.path.join(self.tmp, "bad"),
                        "--every", "5")
        path = os.path.join(drop, "contacts.csv")
        lines = open(path).read().splitlines()
        fields = lines[-1].split(",")
        fields[2] = "1"  # the rod is bone 0, the only one
        lines[-1] = ",".join(fields)
        open(path, "w").write("\n".join(lines) + "\n")
        msg = self.error(drop, "--out", os.path.join(self.tmp, "x.html"))
        self.assertIn(path + ": line %d: field 'bone': '1' is not a bone of the rig" % len(lines),
                      msg)

    def assert_all_finite(self, run):
        for name, values in page_frames(run).items():
            bad = [v for v in values if not math.isfinite(v)]
            self.assertEqual(bad, [], "%s holds non-finite numbers" % name)

    def edited_run(self, name, table, line, column, text):
        """A copy of the run with one cell of one table replaced (line 1 = the header)."""
        run = self.copy_run(name)
        path = os.path.join(run, table)
        lines = open(path).read().splitlines()
        fields = lines[line - 1].split(",")
        fields[column - 1] = text
        lines[line - 1] = ",".join(fields)
        open(path, "w").write("\n".join(lines) + "\n")
        return run, path

    def test_values_past_the_bounds_end_the_frames_with_a_note(self):
        # a diverged run's 5e193 in a position, a hand-edited 1e308 in the kinetic energy (past a
        # float's range) or in a target: the frames from that row on are left out, said in the
        # page with the file, line and column; no array holds a non-finite number
        header = open(os.path.join(self.run_dir, "trajectory.csv")).readline().strip().split(",")
        position = header.index("b1.head_z") + 1
        targets_header = open(os.path.join(self.run_dir, "targets_and_limits.csv")).readline()
        target = targets_header.strip().split(",").index("tip.target_x") + 1
        cases = [("trajectory.csv", 41, position, "5e193", "b1.head_z",
                  "beyond the rig's coordinate bound"),
                 ("trajectory.csv", 61, 3, "1e308", "kinetic_energy",
                  "beyond the viewer's float range"),
                 ("targets_and_limits.csv", 31, target, "1e308", "tip.target_x",
                  "beyond the rig's coordinate bound")]
        for k, (table, line, column, text, field, why) in enumerate(cases):
            with self.subTest(table=table, field=field):
                run, path = self.edited_run("bounds%d" % k, table, line, column, text)
                out = os.path.join(self.tmp, "bounds%d.html" % k)
                status, err = physik("view", run, "--out", out)
                self.assertEqual(status, 0, err)
                data = page_data(out)["runs"][0]
                self.assertEqual(data["frames"], line - 2)  # the rows before it (step 0 first)
                self.assertEqual(decoded(data["steps"], "i"), tuple(range(line - 2)))
                note = [n for n in data["notes"] if "left out" in n]
                self.assertEqual(len(note), 1, data["notes"])
                self.assertIn("frames from step %d on left out: %s line %d, column %d ('%s'): "
                              "'%s' is %s" % (line - 2, path, line, column, field, text, why),
                              note[0])
                self.assert_all_finite(data)

    def test_a_first_frame_past_the_bounds_is_refused(self):
        run, path = self.edited_run("bounds_first", "trajectory.csv", 2, 9, "1e308")
        msg = self.error(run, "--out", os.path.join(self.tmp, "x.html"))
        self.assertIn(path + ": line 2, column 9: field '", msg)
        self.assertIn("'1e308' is beyond the rig's coordinate bound", msg)
        self.assertIn("in the first frame: no frame to show", msg)

    def test_a_step_without_its_targets_row_is_refused(self):
        run = self.copy_run("no_targets_row")
        path = os.path.join(run, "targets_and_limits.csv")
        lines = open(path).read().splitlines()
        del lines[11]  # step 10
        open(path, "w").write("\n".join(lines) + "\n")
        msg = self.error(run, "--out", os.path.join(self.tmp, "x.html"))
        self.assertIn(path + ": field 'step': no row for step 10 of trajectory.csv", msg)

    def test_a_diverged_run_shows_finite_frames(self):
        # the paper's tight hand diverges (exit 3); its run folder plays up to there
        out = os.path.join(self.tmp, "tight")
        status, err = physik("simulate", os.path.join(REPO, "models", "scenes", "hand_tight.json"),
                             "--out", out, "--quiet")
        self.assertEqual(status, 3, err)
        page = os.path.join(self.tmp, "tight.html")
        status, err = physik("view", out, "--out", page)
        self.assertEqual(status, 0, err)
        data = page_data(page)["runs"][0]
        self.assertGreater(data["frames"], 1)
        self.assert_all_finite(data)

    def test_a_solve_folder_shows_its_solved_pose(self):
        scene = chain_scene(os.path.join(self.tmp, "s_solve"), chain_rig(), 1.5)
        solved = os.path.join(self.tmp, "solved")
        status, err = physik("solve", scene, "--solver", "dls", "--out", solved, "--quiet")
        self.assertEqual(status, 0, err)
        page = os.path.join(self.tmp, "solved.html")
        status, err = physik("view", solved, "--out", page)
        self.assertEqual(status, 0, err)
        run = page_data(page)["runs"][0]
        frames = page_frames(run)
        self.assertEqual(frames["steps"], (0,))  # one pose, at step 0
        tip = frames["positions"][2 * 6 + 3:2 * 6 + 6]  # b2's tail, the tip point's target
        for got, want in zip(tip, (1.5, 0.0, 1.8)):
            self.assertAlmostEqual(got, want, delta=1e-3)

    def test_the_page_loads_nothing(self):
        out = os.path.join(self.tmp, "plain.html")
        self.assertEqual(physik("view", self.run_dir, "--out", out)[0], 0)
        parser = _Loads()
        parser.feed(open(out, encoding="utf-8").read())
        self.assertEqual(parser.loads, [])
        self.assertIn("default-src 'none'", parser.policy)


def of_hue(rgb, h, tol):
    """A saturated pixel of hue h (degrees) within tol."""
    hh, s, v = colorsys.rgb_to_hsv(rgb[0] / 255, rgb[1] / 255, rgb[2] / 255)
    return s >= 0.35 and v >= 0.15 and abs((360 * hh - h + 180) % 360 - 180) <= tol


def hue_counts(png, hues, tol=18, size=(250, 250)):
    """Pixels (of a PNG screenshot, resized to `size` unless None) of each hue, in degrees, among
    the saturated ones."""
    from PIL import Image
    img = Image.open(io.BytesIO(png)).convert("RGB")
    if size:
        img = img.resize(size)
    counts = {h: 0 for h in hues}
    for rgb in img.getdata():
        for h in hues:
            if of_hue(rgb, h, tol):
                counts[h] += 1
    return counts


class BrowserTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.driver, why = headless_chromium.start()
        if cls.driver is None:
            raise unittest.SkipTest(why)
        cls.tmp = tempfile.mkdtemp(prefix="physik_view_browser_")
        os.makedirs(SHOTS, exist_ok=True)
        t = cls.tmp
        right = simulate(chain_scene(t + "/s1", chain_rig(), 1.5), t + "/right", "--every", "2")
        left = simulate(chain_scene(t + "/s2", chain_rig(), -1.5), t + "/left", "--every", "2")
        hostile_rig = chain_rig((HOSTILE, HOSTILE_BONE, "b2"), name=HOSTILE, locked_middle=True)
        # the paper's scheme, whose locked joint is held by torsion springs that give under the pull
        # (the exact and implicit schemes weld it: a joint locked on every axis never turns)
        hostile = simulate(chain_scene(t + "/s3", hostile_rig, 3.0, (HOSTILE, HOSTILE_POINT)),
                           os.path.join(t, HOSTILE_FOLDER), "--every", "2", "--set",
                           "preset=original")
        drop = simulate(drop_scene(t + "/s4"), t + "/drop", "--every", "2")
        seated = simulate(box_scene(t + "/s5", [SEAT]), t + "/seated", "--every", "2")
        limited_rig = chain_rig(middle_limits={"x": [-30, 60], "z": [-10, 10], "y": [0, 0]})
        limited = simulate(chain_scene(t + "/s6", limited_rig, 1.5), t + "/limited", "--every",
                           "2")
        solved = t + "/solved"
        status, err = physik("solve", chain_scene(t + "/s7", chain_rig(), 1.5), "--solver",
                             "dls", "--out", solved, "--quiet")
        if status != 0:
            raise RuntimeError("physik solve: " + err)
        targeted = simulate(chain_scene(t + "/s8", chain_rig(), 1.5), t + "/targeted", "--every",
                            "2", *BONE_TARGET_ARGS)
        cls.pages = {"single": t + "/single.html", "overlay": t + "/overlay.html",
                     "targeted": t + "/targeted.html",
                     "solved": t + "/solved.html",
                     "hostile": t + "/hostile.html", "drop": t + "/drop.html",
                     "seated": t + "/seated.html", "limited": t + "/limited.html"}
        for args in ([right, "--out", cls.pages["single"]], [drop, "--out", cls.pages["drop"]],
                     [solved, "--out", cls.pages["solved"]],
                     [targeted, "--out", cls.pages["targeted"]],
                     [seated, "--out", cls.pages["seated"]],
                     [limited, "--out", cls.pages["limited"]],
                     [right, left, "--out", cls.pages["overlay"]],
                     [hostile, "--title", HOSTILE, "--out", cls.pages["hostile"]]):
            status, err = physik("view", *args)
            if status != 0:
                raise RuntimeError("physik view %s: %s" % (args, err))

    @classmethod
    def tearDownClass(cls):
        cls.driver.quit()
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def js(self, script, *args):
        return self.driver.execute_script(script, *args)

    def wait_for(self, script, what, timeout=30):
        end = time.time() + timeout
        while time.time() < end:
            value = self.js(script)
            if value:
                return value
            time.sleep(0.05)
        self.fail("timed out waiting for " + what)

    def load(self, name, query=""):
        self.driver.get_log("browser")  # drop what earlier pages logged
        self.driver.get("file://" + self.pages[name] + query)
        self.wait_for("return window.physikViewers && window.physikViewers[0].renders > 0",
                      "the first frame of " + name)
        return self.driver.find_element("css selector", ".physik-viewer canvas")

    def settled_canvas(self, canvas):
        """The canvas once every requested frame is drawn."""
        self.wait_for("return !window.physikViewers[0].renderQueued", "the render")
        return canvas.screenshot_as_png

    def errors(self):
        return [l for l in self.driver.get_log("browser") if l["level"] == "SEVERE"]

    def shot(self, name):
        path = os.path.join(SHOTS, name + ".png")
        self.driver.save_screenshot(path)
        return path

    def test_page_loads_with_a_canvas_and_no_console_error(self):
        canvas = self.load("single")
        self.assertTrue(canvas.is_displayed())
        self.assertGreater(canvas.size["width"], 100)
        self.assertEqual(self.errors(), [])
        self.shot("single_frame0")

    def test_no_horizontal_scrollbar_at_1200_pixels(self):
        # The canvas was sized to the page's width before it had a vertical scrollbar; where the
        # canvas itself then made the page taller than the window (at 1200 px wide, windows about
        # 990 px high for the two-run page), the scrollbar took 15 px from a canvas already that
        # wide: a horizontal scrollbar. Nor may the canvas stick out of its stage (its border).
        try:
            for height in range(940, 1061, 6):
                self.driver.set_window_size(1200, height)
                self.load("overlay")
                m = self.js(
                    "var e = document.documentElement, c = document.querySelector("
                    "'.physik-viewer canvas'), s = c.parentNode;"
                    "return {scroll: e.scrollWidth, client: e.clientWidth, inner: innerHeight,"
                    "  canvas: c.getBoundingClientRect().right,"
                    "  stage: s.getBoundingClientRect().left + s.clientLeft + s.clientWidth,"
                    "  buffer: c.width / devicePixelRatio, shown: c.clientWidth};")
                what = "window 1200 x %d: %s" % (height, m)
                self.assertLessEqual(m["scroll"], m["client"], what)
                self.assertLessEqual(m["canvas"], m["stage"] + 0.5, what)
                self.assertEqual(m["buffer"], m["shown"], what)  # drawn at the size shown
        finally:
            self.driver.set_window_size(1000, 1000)  # headless_chromium.start's, for the others
        self.assertEqual(self.errors(), [])

    def test_slider_changes_pixels_and_a_paused_frame_stays(self):
        from selenium.webdriver.common.keys import Keys
        canvas = self.load("single")
        first = self.settled_canvas(canvas)
        slider = self.driver.find_element("css selector", ".physik-viewer input.frame")
        slider.send_keys(Keys.END)  # the keyboard, as a user moves it
        self.wait_for("var v = window.physikViewers[0]; return v.frame === v.times.length - 1",
                      "the slider's last frame")
        last = self.settled_canvas(canvas)
        self.assertNotEqual(first, last)
        time.sleep(0.5)  # paused: nothing may change
        self.assertEqual(self.settled_canvas(canvas), last)
        label = self.driver.find_element("css selector", ".physik-viewer .time").text
        self.assertRegex(label, r"t = 2\.000 s, step 40, frame 21/21")
        self.shot("single_last_frame")
        self.assertEqual(self.errors(), [])

    def test_the_url_opens_at_a_chosen_frame(self):
        canvas = self.load("single", "?frame=last")
        self.assertTrue(self.js("return !window.physikViewers[0].playing"))
        label = self.driver.find_element("css selector", ".physik-viewer .time").text
        self.assertRegex(label, r"t = 2\.000 s, step 40, frame 21/21")
        last = self.settled_canvas(canvas)
        self.shot("single_url_last_frame")
        canvas = self.load("single", "?frame=5")
        self.assertEqual(self.js("return window.physikViewers[0].frame"), 4)
        self.assertNotEqual(self.settled_canvas(canvas), last)
        self.assertEqual(self.errors(), [])

    def test_the_url_plays_on_load(self):
        self.load("single", "?play=1")
        self.assertTrue(self.js("return window.physikViewers[0].playing || "
                                "window.physikViewers[0].frame > 0"))
        self.wait_for("return window.physikViewers[0].frame > 3", "playback on load")
        self.assertEqual(self.errors(), [])

    def test_a_solve_folder_opens_on_its_pose(self):
        canvas = self.load("solved")
        self.assertTrue(canvas.is_displayed())
        label = self.driver.find_element("css selector", ".physik-viewer .time").text
        self.assertRegex(label, r"step 0, frame 1/1")
        self.shot("solved_pose")
        self.assertEqual(self.errors(), [])

    def test_play_advances_the_frame(self):
        self.load("single")
        self.driver.find_element("css selector", ".physik-viewer button.play").click()
        self.wait_for("return window.physikViewers[0].frame > 3", "playback")

    def test_overlay_draws_both_colours(self):
        canvas = self.load("overlay")
        self.js("var v = window.physikViewers[0]; v.setFrame(v.times.length - 1);")
        counts = hue_counts(self.settled_canvas(canvas), (BLUE, ORANGE))
        self.shot("overlay_last_frame")
        self.assertGreater(counts[BLUE], 300, counts)
        self.assertGreater(counts[ORANGE], 300, counts)
        self.assertEqual(self.errors(), [])

    def test_a_bone_past_its_limit_is_outlined_and_keeps_its_colour(self):
        data = page_data(self.pages["hostile"])["runs"][0]
        canvas = self.load("hostile")
        before = hue_counts(self.settled_canvas(canvas), (HIGHLIGHT, BLUE))
        self.assertEqual(before[HIGHLIGHT], 0)
        self.js("var v = window.physikViewers[0]; v.setFrame(v.times.length - 1);")
        readout = self.wait_for(
            "var t = document.querySelectorAll('.physik-viewer tbody td')[5].textContent;"
            "return t !== 'none' && t", "the limit readout")
        self.assertIn(HOSTILE_BONE, readout)  # the locked joint's bone, by name
        counts = hue_counts(self.settled_canvas(canvas), (HIGHLIGHT, BLUE))
        self.shot("limit_highlighted")
        self.assertGreater(counts[HIGHLIGHT], 50, (counts, data["notes"]))
        # the bones keep the run's colour: the outline is around them, not instead of them
        self.assertGreater(counts[BLUE], 0.6 * before[BLUE], (before, counts))
        self.assertGreater(counts[BLUE], counts[HIGHLIGHT], counts)

    def axis_counts(self, canvas):
        # at the canvas's own resolution: the axes are lines one pixel wide
        return hue_counts(self.settled_canvas(canvas), (AXIS_X, AXIS_Y, AXIS_Z), tol=12,
                          size=None)

    def test_axes_and_limit_ranges_show_with_their_toggle(self):
        canvas = self.load("limited")
        off = self.axis_counts(canvas)
        toggle = [l for l in self.driver.find_elements("css selector", ".physik-viewer label")
                  if l.text.strip() == "axes and limits"]
        self.assertEqual(len(toggle), 1)
        toggle[0].find_element("css selector", "input").click()
        self.wait_for("return window.physikViewers[0].runs[0].axes.visible", "the axes")
        on = self.axis_counts(canvas)
        self.shot("axes_and_limits")
        for hue in (AXIS_X, AXIS_Y, AXIS_Z):
            self.assertGreater(on[hue], off[hue] + 20, (off, on))
        # two fans on the middle bone (x and z: y is locked), each an arc 0.4 of its length from
        # its head and its two end radii, spanning the limit: [-30, 60] about x is 90 deg
        fans = self.js("var r = window.physikViewers[0].runs[0]; return r.fans.map("
                       "function (f) { return [f.bone, f.axis, f.min, f.max]; })")
        self.assertEqual([f[:2] for f in fans], [[1, 0], [1, 2]])
        self.assertAlmostEqual(math.degrees(fans[0][3] - fans[0][2]), 90.0, places=6)
        geometry = self.js(
            "var v = window.physikViewers[0], r = v.runs[0], f = r.frameAt[v.frame];"
            "var p = r.axes.geometry.attributes.position.array, o = 6 * 9;"  # after 9 axes
            "var h = [r.positions[(f * 3 + 1) * 6], r.positions[(f * 3 + 1) * 6 + 1],"
            "         r.positions[(f * 3 + 1) * 6 + 2]];"
            "var d = []; for (var i = 0; i < 18; i++) {"
            "  var k = o + 6 * i + 3; d.push(Math.hypot(p[k] - h[0], p[k + 1] - h[1],"
            "                                           p[k + 2] - h[2])); }"
            "var a = [p[o + 3] - h[0], p[o + 4] - h[1], p[o + 5] - h[2]],"
            "    b = [p[o + 105] - h[0], p[o + 106] - h[1], p[o + 107] - h[2]];"  # 6 x 17 + 3
            "var c = (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) / (Math.hypot.apply(null, a) *"
            "        Math.hypot.apply(null, b));"
            "return [d, Math.acos(Math.max(-1, Math.min(1, c))) * 180 / Math.PI];")
        for dist in geometry[0][:17]:
            self.assertAlmostEqual(dist, 0.4, places=4)  # on the arc, 0.4 x length 1
        self.assertAlmostEqual(geometry[1], 90.0, places=3)  # the min's and max's radii
        self.assertEqual(self.errors(), [])

    def test_bone_targets_are_drawn_at_their_bones(self):
        canvas = self.load("targeted", "?frame=last")
        shown = self.settled_canvas(canvas)
        # the triad at b2's head along the target frame's axes (0.6 of its length, 1), the aim's
        # line from b1's head to its point, the pin's marker at the origin
        got = self.js(
            "var v = window.physikViewers[0], r = v.runs[0], f = r.frameAt[v.frame];"
            "var head = function (b) { var o = (f * r.nbone + b) * 6;"
            "  return [r.positions[o], r.positions[o + 1], r.positions[o + 2]]; };"
            "return [Array.from(r.triads.geometry.attributes.position.array), head(2),"
            "        Array.from(r.aimLines.geometry.attributes.position.array), head(1),"
            "        r.targetGroup.children.filter(function (c) { return c.isMesh; })"
            "          .map(function (c) { return [c.geometry.type, c.position.toArray()]; })];")
        triad, head2, aim, head1, marks = got
        w, x, y, z = TARGET_Q
        # the target frame's columns (world<-bone): 90 deg about x takes y to z and z to -y
        axes = ((1, 0, 0), (0, 0, 1), (0, -1, 0))
        for k, axis in enumerate(axes):
            start, end = triad[6 * k:6 * k + 3], triad[6 * k + 3:6 * k + 6]
            for c in range(3):
                self.assertAlmostEqual(start[c], head2[c], places=5)
                self.assertAlmostEqual(end[c] - start[c], 0.6 * axis[c], places=5)
        self.assertEqual([round(c, 5) for c in aim[:3]], [round(c, 5) for c in head1])
        self.assertEqual(aim[3:], [2, 0, 1])
        self.assertIn(["BoxBufferGeometry", [0, 0, 0]], marks)  # the pin
        self.assertIn(["SphereBufferGeometry", [2, 0, 1]], marks)  # the aim's point
        for values in (triad, aim):
            self.assertTrue(all(math.isfinite(c) for c in values))
        self.shot("bone_targets")
        self.js("window.physikViewers[0].setTargetsShown(false);")
        self.assertNotEqual(self.settled_canvas(canvas), shown)
        self.assertEqual(self.errors(), [])

    def test_a_floor_grid_only_where_the_scene_has_a_ground(self):
        grids = "return window.physikViewers[0].scene.children.filter(" \
                "function (c) { return c instanceof THREE.GridHelper; }).length"
        self.load("single")
        self.assertEqual(self.js(grids), 0)
        self.load("drop")
        self.assertEqual(self.js(grids), 1)

    def dark_pixels(self, canvas):
        from PIL import Image
        img = Image.open(io.BytesIO(self.settled_canvas(canvas))).convert("RGB")
        return sum(1 for p in img.getdata() if max(p) < 40)

    def test_targets_have_their_own_colour(self):
        canvas = self.load("overlay")
        shown = self.dark_pixels(canvas)
        self.js("window.physikViewers[0].setTargetsShown(false);")
        hidden = self.dark_pixels(canvas)
        # the targets of both runs are drawn in TARGET_COLOR (black), nothing else is that dark
        self.assertGreater(shown, 100, (shown, hidden))
        self.assertLess(hidden, 0.1 * shown, (shown, hidden))

    def contacts_at(self, canvas, frame):
        """At timeline entry `frame`: the markers placed, the readout's contacts cell, and the
        contact colour's pixels."""
        self.js("window.physikViewers[0].setFrame(arguments[0]);", frame)
        pixels = hue_counts(self.settled_canvas(canvas), (CONTACT,), tol=10)[CONTACT]
        placed = self.js("return window.physikViewers[0].runs[0].contactDots.count")
        cell = self.js("return document.querySelectorAll('.physik-viewer tbody td')[6]"
                       ".textContent")
        return placed, cell, pixels

    def test_contacts_show_where_the_run_has_them(self):
        canvas = self.load("drop")
        last = self.js("return window.physikViewers[0].times.length - 1")
        # 0.1 s: still falling (the rod reaches the floor after sqrt(2 0.24 / 9.81) = 0.22 s)
        placed, cell, pixels = self.contacts_at(canvas, 5)
        self.assertEqual((placed, cell, pixels), (0, "none", 0))
        self.shot("contacts_falling")
        placed, cell, pixels = self.contacts_at(canvas, last)
        self.shot("contacts_lying")
        self.assertEqual(placed, 2)
        self.assertTrue(cell.startswith("2, largest force "), cell)
        self.assertGreater(pixels, 20)
        box = self.driver.find_element(
            "xpath", "//label[contains(., 'contacts')]/input[@type='checkbox']")
        box.click()  # the toggle hides them
        self.assertEqual(hue_counts(self.settled_canvas(canvas), (CONTACT,), tol=10)[CONTACT], 0)
        box.click()
        self.assertGreater(hue_counts(self.settled_canvas(canvas), (CONTACT,), tol=10)[CONTACT],
                           20)
        self.assertEqual(self.errors(), [])

    def box_pixels(self, canvas, box, tol=10):
        """Pixels of the box colour on the canvas, (inside, outside) the box's outline: its six
        faces with their corners from the scene's numbers (box_corners, not the page's),
        projected by the viewer's camera, the outline widened by 3 pixels (anti-aliasing)."""
        from PIL import Image, ImageDraw
        img = Image.open(io.BytesIO(self.settled_canvas(canvas))).convert("RGB")
        width, points = self.js(
            "var v = window.physikViewers[0], c = v.renderer.domElement;"
            "return [c.clientWidth, arguments[0].map(function (p) {"
            "  var n = new THREE.Vector3(p[0], p[1], p[2]).project(v.camera);"
            "  return [(n.x + 1) / 2 * c.clientWidth, (1 - n.y) / 2 * c.clientHeight]; })];",
            box_corners(box))
        scale = img.width / width  # screenshot pixels per CSS pixel
        points = [(x * scale, y * scale) for x, y in points]
        mask = Image.new("L", img.size, 0)
        draw = ImageDraw.Draw(mask)
        for a in range(3):  # the faces at -1 and +1 along axis a: corners in a cycle
            b, c = [x for x in range(3) if x != a]
            for side in (0, 1):
                face = [points[side << a | i << b | j << c] for i, j in ((0, 0), (1, 0), (1, 1),
                                                                         (0, 1))]
                draw.polygon(face, fill=255)
                draw.line(face + face[:1], fill=255, width=int(round(6 * scale)) + 1)
        inside = outside = 0
        for rgb, m in zip(img.getdata(), mask.getdata()):
            if of_hue(rgb, BOX, tol):
                if m:
                    inside += 1
                else:
                    outside += 1
        return inside, outside, sum(1 for m in mask.getdata() if m)

    def test_a_box_obstacle_is_drawn_where_the_scene_puts_it(self):
        canvas = self.load("seated")
        last = self.js("return window.physikViewers[0].times.length - 1")
        for frame in (0, last):  # falling toward it, lying on it
            self.js("window.physikViewers[0].setFrame(arguments[0]);", frame)
            inside, outside, area = self.box_pixels(canvas, SEAT["box"])
            self.shot("box_frame%d" % frame)
            self.assertGreater(inside, area // 2, (frame, inside, outside, area))
            self.assertLessEqual(outside, area // 100, (frame, inside, outside, area))
        legend = self.driver.find_element("css selector", ".physik-viewer .legend").text
        self.assertIn("obstacle: seat", legend)
        toggle = self.driver.find_element(
            "xpath", "//label[contains(., 'obstacles')]/input[@type='checkbox']")
        toggle.click()  # the toggle hides it
        self.assertEqual(self.box_pixels(canvas, SEAT["box"])[:2], (0, 0))
        toggle.click()
        self.assertGreater(self.box_pixels(canvas, SEAT["box"])[0], 0)
        self.assertEqual(self.errors(), [])

    def test_no_box_where_the_scene_has_none(self):
        canvas = self.load("drop")  # a floor, and no box
        self.js("var v = window.physikViewers[0]; v.setFrame(v.times.length - 1);")
        self.assertEqual(hue_counts(self.settled_canvas(canvas), (BOX,), tol=10)[BOX], 0)
        self.assertEqual(self.driver.find_elements(
            "xpath", "//label[contains(., 'obstacles')]"), [])
        self.assertEqual(self.errors(), [])

    def test_hostile_names_show_as_text_and_run_nothing(self):
        from selenium.common.exceptions import NoAlertPresentException
        self.load("hostile")
        self.js("var v = window.physikViewers[0]; v.setFrame(v.times.length - 1);")
        time.sleep(0.3)
        with self.assertRaises(NoAlertPresentException):
            self.driver.switch_to.alert.text
        self.assertIsNone(self.js("return window.__pwned"))
        self.assertEqual(self.js("return document.querySelectorAll('img, svg').length"), 0)
        text = self.js("return document.body.innerText")
        for name in (HOSTILE, HOSTILE_FOLDER, HOSTILE_POINT):
            self.assertIn(name, text)  # shown, as text
        self.assertEqual(self.driver.title, HOSTILE)
        self.assertEqual(self.errors(), [])
        self.shot("hostile_names")

    def test_the_report_page_embeds_the_viewer_beside_the_figures(self):
        results = os.path.join(self.tmp, "results")
        runs = os.path.join(results, "e", "runs")
        for name in ("right", "left"):
            shutil.copytree(os.path.join(self.tmp, name), os.path.join(runs, name))
        with open(os.path.join(runs, "order.txt"), "w") as f:
            f.write("right\nleft\n")
        shutil.copy(self.shot("for_the_report"), os.path.join(results, "e", "fig.png"))
        with open(os.path.join(results, "e", "summary.json"), "w") as f:
            json.dump({"report": {"title": HOSTILE, "figures": ["fig.png"]}}, f)
        subprocess.run([sys.executable, os.path.join(REPO, "analysis", "report.py"), results,
                        "--physik", BINARY], check=True, capture_output=True)
        self.driver.get_log("browser")
        self.driver.get("file://" + os.path.join(results, "REPORT.html"))
        self.assertIn(HOSTILE, self.js(
            "return Array.from(document.querySelectorAll('h2')).map(h => h.textContent)"))
        self.assertEqual(self.js("return document.querySelectorAll('.figures img').length"), 1)
        frame = self.driver.find_element("css selector", ".figures iframe")
        self.js("arguments[0].scrollIntoView()", frame)  # the frame loads lazily
        self.driver.switch_to.frame(frame)
        try:
            self.wait_for("return window.physikViewers && window.physikViewers[0].renders > 0",
                          "the embedded viewer's first frame")
            self.assertEqual(self.js("return window.physikViewers[0].runs.length"), 2)
        finally:
            self.driver.switch_to.default_content()
        self.shot("report_page")
        self.assertEqual(self.errors(), [])


def main():
    names = sys.argv[1:] or ["ViewCommandTest", "BrowserTest"]
    suite = unittest.TestSuite(
        unittest.defaultTestLoader.loadTestsFromName(n, sys.modules[__name__]) for n in names)
    result = unittest.TextTestRunner(verbosity=2).run(suite)
    if not result.wasSuccessful():
        return 1
    for test, reason in result.skipped:
        print("SKIPPED %s: %s" % (test, reason))
    return SKIPPED if result.skipped and result.testsRun == len(result.skipped) else 0


if __name__ == "__main__":
    sys.exit(main())
