"""Each plot function runs on a small fixture and writes a non-empty PNG; the report renders."""
import json
import os
import re
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
import physik_plot  # noqa: E402
import plot_pose  # noqa: E402
import plot_rest_poses  # noqa: E402
import plot_scaling  # noqa: E402
import report  # noqa: E402
import report_html  # noqa: E402

FIXTURE_BONES = """bone,parent,head_x,head_y,head_z,tail_x,tail_y,tail_z
a,,0,0,0,0,0,1
b,a,0,0,1,0.5,0,1.5
"""


def write(folder, name, text):
    path = os.path.join(folder, name)
    with open(path, "w") as f:
        f.write(text)
    return path


class RestPoseTest(unittest.TestCase):
    def test_plot_rest_pose_writes_png(self):
        with tempfile.TemporaryDirectory() as d:
            csv_path = write(d, "two.csv", FIXTURE_BONES)
            png = physik_plot.plot_rest_pose(csv_path, os.path.join(d, "two.png"))
            self.assertGreater(os.path.getsize(png), 1000)

    def test_script_draws_every_rig_in_summary(self):
        with tempfile.TemporaryDirectory() as d:
            write(d, "two.csv", FIXTURE_BONES)
            write(d, "summary.json", json.dumps({"rigs": [
                {"name": "two", "csv": "two.csv", "figure": "two.png", "bones": 2, "joints": 1}]}))
            plot_rest_poses.main([d])
            self.assertGreater(os.path.getsize(os.path.join(d, "two.png")), 1000)

    def test_empty_table_is_an_error(self):
        with tempfile.TemporaryDirectory() as d:
            csv_path = write(d, "empty.csv", FIXTURE_BONES.splitlines()[0] + "\n")
            with self.assertRaises(ValueError):
                physik_plot.read_bones_csv(csv_path)


class ReportTest(unittest.TestCase):
    def test_claims_and_figures_are_listed(self):
        with tempfile.TemporaryDirectory() as d:
            os.makedirs(os.path.join(d, "exp"))
            write(os.path.join(d, "exp"), "summary.json", json.dumps({"report": {
                "title": "Fig X", "claims": [{"claim": "c1", "measured": "m1", "holds": "no"}],
                "figures": ["f.png"]}}))
            report.main([d])
            text = open(os.path.join(d, "REPORT.md")).read()
            self.assertIn("| exp | c1 | no | m1 |", text)
            self.assertIn("- **c1**: no. m1", text)  # whole, in the experiment's section
            self.assertIn("](exp/f.png)", text)

    def test_summary_rows_fit_and_sections_keep_the_whole_claim(self):
        long_measured = "; ".join("rig %d converged in %d steps" % (k, 10 * k) for k in range(60))
        claims = [{"claim": "A claim stated at some length, " * 6, "measured": long_measured,
                   "holds": "partly (only in the transient)", "name": "long-one"},
                  {"claim": "short", "measured": "m", "holds": "yes"}]
        with tempfile.TemporaryDirectory() as d:
            os.makedirs(os.path.join(d, "exp"))
            write(os.path.join(d, "exp"), "summary.json",
                  json.dumps({"report": {"title": "X", "claims": claims}}))
            readme = write(d, "README.md", "<!-- headline: exp/long-one -->\n")
            text = report.render(report.collect(d), None, readme)
            rows = [l for l in text.splitlines() if l.startswith("| exp |")]
            self.assertEqual(len(rows), 2)
            self.assertTrue(all(len(r) <= report.ROW_MAX for r in rows), rows)
            self.assertIn("\u2026", rows[0])
            self.assertIn("| partly |", rows[0])
            for piece in long_measured.split("; "):  # the section has it whole, in short bullets
                self.assertIn("  - " + piece, text)
            case = "Fig 6: linear springs over-bend a limited elbow more than capped ones " \
                   "(near target (the figure's geometry), cap c = 0.1)"
            short = report.shorten_claim(case, 105)
            self.assertLessEqual(len(short), 105)
            self.assertTrue(short.endswith("(near target (the figure's geometry), cap c = 0.1)"), short)
            self.assertIn("(only in the transient)", text)
            self.assertIn("README's headline cites claim `exp/long-one`: **partly", text)
            write(d, "README.md", "<!-- headline: exp/missing -->\n")
            self.assertIn("which this run did not report",
                          report.render(report.collect(d), None, readme))

    def test_a_sentence_in_the_holds_cell_is_refused(self):
        # the contacts experiment once wrote "no: a resting pose that moves ..." as a verdict,
        # which the summary table showed whole where every other row says one word
        for ok in ("yes", "no", "partly", "n/a", "no (a run diverged)", "n/a (quick run)"):
            self.assertTrue(report.is_verdict(ok), ok)
        for bad in ("no: a resting pose that moves by more than 2%", "maybe", "yes because",
                    "no (", "no ()", "partly (unclosed", ""):
            self.assertFalse(report.is_verdict(bad), bad)
        with tempfile.TemporaryDirectory() as d:
            os.makedirs(os.path.join(d, "exp"))
            write(os.path.join(d, "exp"), "summary.json", json.dumps({"report": {
                "title": "X", "claims": [{"claim": "c", "measured": "m",
                                          "holds": "no: a resting pose that moves"}]}}))
            with self.assertRaises(SystemExit) as e:
                report.collect(d)
            self.assertIn("summary.json: claim 'c': holds 'no: a resting pose that moves' is not "
                          "a verdict", str(e.exception))

    def test_no_line_is_longer_than_600_characters(self):
        # details as one bullet made lines of 1,265 characters: long measured phrases, notes,
        # settings, a headline and a table with a long cell all fit in lines of at most 600, and
        # the HTML page (report_html) still holds every word of them
        long_measured = "; ".join("rig %d (Gauss-Seidel) converged in %d steps" % (k, 10 * k)
                                  for k in range(60))
        long_note = " ".join("word%d" % k for k in range(250))
        claims = [{"claim": "A claim stated at some length, " * 6, "measured": long_measured,
                   "holds": "partly (only in the transient)", "name": "long-one"}]
        table = {"title": "wide", "columns": ["case", "what"],
                 "rows": [["a", "x" * 40 + " " + " ".join(["cell"] * 200)], ["b", "short"]]}
        settings = {"setting_%d" % k: "value %d" % k for k in range(80)}
        with tempfile.TemporaryDirectory() as d:
            os.makedirs(os.path.join(d, "exp"))
            write(os.path.join(d, "exp"), "summary.json", json.dumps({"report": {
                "title": "X", "claims": claims, "notes": [long_note], "tables": [table],
                "settings": settings}}))
            readme = write(d, "README.md", "<!-- headline: exp/long-one -->\n")
            text = report.render(report.collect(d), None, readme)
            longest = max(text.splitlines(), key=len)
            self.assertLessEqual(len(longest), report.LINE_MAX, longest[:200])
            page = report_html.to_html(text)
            flat = " ".join(re.sub(r"<[^>]+>", " ", page).split())
            for piece in long_measured.split("; ") + [long_note, "setting_79 = value 79"]:
                self.assertIn(piece, flat)
            self.assertIn(" ".join(["cell"] * 200), flat)
            self.assertNotIn("Gauss- Seidel", flat)  # wrapped at spaces, never at a hyphen

    def test_settings_table_takes_values_and_units_from_params_json(self):
        def row(name, kind, unit, original, paper, **extra):
            return dict(name=name, kind=kind, unit=unit, defaults={"original": original, "paper": paper}, **extra)
        table = {"presets": ["original", "paper"], "default_preset": "original", "params": [
            row("dt", "real", "s", 0.05, 0.05), row("damping", "real", "N s/m", 7.0, 21.0),
            row("control_k", "real", "N/m", 10.0, 30.0), row("joint_eps", "real", "rig units/s^2", 1e-3, 1e-3),
            row("max_passes", "integer", "passes", 0, 0, zero_means="5 n^2"),
            row("torsion_k", "real", "N m/rad", 10.0, 10.0), row("torsion_tolerance", "real", "1", 0.25, 0.1),
            row("control_cap", "real", "rig units", 1.0, 1.0),
            row("free_rods", "boolean", "", True, False)]}
        with tempfile.TemporaryDirectory() as d:
            os.makedirs(os.path.join(d, "exp"))
            write(d, "params.json", json.dumps(table))
            write(os.path.join(d, "exp"), "summary.json", json.dumps({"report": {
                "title": "X", "settings": {"control_k": 12.5}}}))
            report.main([d])
            text = open(os.path.join(d, "REPORT.md")).read()
            self.assertIn("| `damping` | 21 N s/m | 7 N s/m (the original code's) |", text)
            self.assertIn("| `control_k` | 30 N/m | 12.5 N/m in every paper scene |", text)
            self.assertIn("| `joint_eps` | 0.001 rig units/s^2 | 0.001 rig units/s^2 |", text)
            self.assertIn("| 5 n^2 (the original code's) |", text)
            self.assertIn("| 10 N m/rad, 25% inside each limit (the original's) |", text)
            self.assertIn("| 1 rig unit (the original hard-codes 1) |", text)
            self.assertIn("| true (the original code's: FK from the root) |", text)
            # a cell naming a parameter the table lacks is an error, not a blank
            table["params"] = [r for r in table["params"] if r["name"] != "dt"]
            write(d, "params.json", json.dumps(table))
            with self.assertRaises(KeyError):
                report.main([d])

    def test_tables_render_as_markdown_and_a_short_row_is_an_error(self):
        with tempfile.TemporaryDirectory() as d:
            os.makedirs(os.path.join(d, "exp"))
            tab = {"title": "T", "columns": ["rig", "us"], "rows": [["chain", 5.2], ["tree2", "skipped"]]}
            write(os.path.join(d, "exp"), "summary.json", json.dumps({"report": {"title": "X", "tables": [tab]}}))
            report.main([d])
            text = open(os.path.join(d, "REPORT.md")).read()
            self.assertIn("**T**\n\n| rig | us |\n|---|---|\n| chain | 5.2 |\n| tree2 | skipped |", text)
            tab["rows"].append(["chain"])
            write(os.path.join(d, "exp"), "summary.json", json.dumps({"report": {"title": "X", "tables": [tab]}}))
            with self.assertRaises(ValueError):
                report.main([d])

    def test_settings_table_needs_params_json(self):
        with tempfile.TemporaryDirectory() as d:
            report.main([d])
            self.assertIn("no params.json here", open(os.path.join(d, "REPORT.md")).read())


SCALING_CSV = """kind,nbone,method,status,us_per_step,us_per_bone,steps,batches,passes_per_step,force_error,gap_vs_exact,compile_s
chain,10,exact,"ok",5,0.5,100,3,1,,,
chain,100,exact,"ok",50,0.5,100,3,1,,,
chain,100,mj_step,"skipped: projected 3 s per step > 2 s",,,0,0,,,,
tree2,10,exact,"ok",5,0.5,100,3,1,,,
"""


class ScalingPlotTest(unittest.TestCase):
    def test_draws_the_rows_that_ran(self):
        with tempfile.TemporaryDirectory() as d:
            write(d, "scaling.csv", SCALING_CSV)
            write(d, "summary.json", json.dumps({"exponents": [
                {"kind": "chain", "method": "exact", "exponent": 1.0, "sizes": [100]}]}))
            self.assertEqual(plot_scaling.series(physik_plot.read_table(os.path.join(d, "scaling.csv")),
                                                 "chain", "exact"), ([10.0, 100.0], [5.0, 50.0]))
            plot_scaling.main([d])
            self.assertGreater(os.path.getsize(os.path.join(d, "scaling.png")), 1000)

    def test_empty_table_is_an_error(self):
        with tempfile.TemporaryDirectory() as d:
            write(d, "scaling.csv", SCALING_CSV.splitlines()[0] + "\n")
            write(d, "summary.json", json.dumps({"exponents": []}))
            with self.assertRaises(ValueError):
                plot_scaling.main([d])


if __name__ == "__main__":
    unittest.main()


# a rig facing +x, as MuJoCo's humanoid: its left side at +y
HUMANOID_BONES = """bone,parent,head_x,head_y,head_z,tail_x,tail_y,tail_z
torso,,0,0,1,0,0,1.5
left_arm,torso,0,0.2,1.5,0,0.6,1.5
right_arm,torso,0,-0.2,1.5,0,-0.6,1.5
left_leg,torso,0,0.1,1,0,0.1,0
right_leg,torso,0,-0.1,1,0,-0.1,0
"""
# the same figure facing -y, as pinhead: its left (.L) at +x
PINHEAD_BONES = """bone,parent,head_x,head_y,head_z,tail_x,tail_y,tail_z
torso,,0,0,1,0,0,1.5
arm.L,torso,0.2,0,1.5,0.6,0,1.5
arm.R,torso,-0.2,0,1.5,-0.6,0,1.5
leg.L,torso,0.1,0,1,0.1,0,0
leg.R,torso,-0.1,0,1,-0.1,0,0
"""


class PlotPoseTest(unittest.TestCase):
    """plot_pose.py frames a rig from its own facing: the front view shows its width whichever
    way it faces (the fixed x-z view showed MuJoCo's humanoid from its side)."""

    def bones(self, text):
        with tempfile.TemporaryDirectory() as d:
            return physik_plot.read_bones_csv(write(d, "pose.csv", text))

    def test_facing_from_the_left_and_right_names(self):
        self.assertEqual(plot_pose.rig_facing(self.bones(HUMANOID_BONES)), (1.0, 0.0))
        self.assertEqual(plot_pose.rig_facing(self.bones(PINHEAD_BONES)), (0.0, -1.0))

    def test_facing_from_the_extent_without_names(self):
        anon = lambda text: text.replace("arm.L", "a1").replace("arm.R", "a2").replace(  # noqa
            "leg.L", "g1").replace("leg.R", "g2")
        wide_in_x = self.bones(anon(PINHEAD_BONES))
        self.assertEqual([round(c, 9) for c in plot_pose.rig_facing(wide_in_x)], [0.0, -1.0])
        wide_in_y = [dict(b, head=(b["head"][1], b["head"][0], b["head"][2]),
                          tail=(b["tail"][1], b["tail"][0], b["tail"][2])) for b in wide_in_x]
        self.assertEqual([round(c, 9) for c in plot_pose.rig_facing(wide_in_y)], [1.0, 0.0])

    def test_the_front_view_spreads_the_rig_across_its_width(self):
        for text in (HUMANOID_BONES, PINHEAD_BONES):
            bones = self.bones(text)
            turned = plot_pose.in_view_frame(bones, plot_pose.rig_facing(bones))
            front = {b["bone"]: b["tail"][0] for b in turned}  # the front view's horizontal
            side = {b["bone"]: b["tail"][1] for b in turned}
            left = [k for k in front if plot_pose.LEFT.search(k) and "leg" not in k][0]
            right = [k for k in front if plot_pose.RIGHT.search(k) and "leg" not in k][0]
            self.assertAlmostEqual(front[left], 0.6)  # its left on the picture's right
            self.assertAlmostEqual(front[right], -0.6)
            self.assertAlmostEqual(side[left], 0.0)  # the side view sees the arms end on
        # the world's x-z view (the old front view) saw the humanoid's arms on top of each other
        hum = {b["bone"]: b["tail"][0] for b in self.bones(HUMANOID_BONES)}
        self.assertEqual(hum["left_arm"], hum["right_arm"])

    def test_the_script_writes_the_views(self):
        with tempfile.TemporaryDirectory() as d:
            pose = write(d, "final_pose.csv", HUMANOID_BONES)
            scene = write(d, "scene.json", json.dumps({"control_points": [
                {"bone": "left_arm", "target": [0.3, 0.7, 1.6]}]}))
            out = os.path.join(d, "pose.png")
            plot_pose.main([pose, "--scene", scene, "--out", out])
            self.assertGreater(os.path.getsize(out), 1000)
            plot_pose.main([pose, "--facing=-y", "--out", out])
            self.assertGreater(os.path.getsize(out), 1000)
