"""Each plot function runs on a small fixture and writes a non-empty PNG; the report renders."""
import json
import os
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
import physik_plot  # noqa: E402
import plot_rest_poses  # noqa: E402
import report  # noqa: E402

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
            self.assertIn("| exp | c1 | m1 | no |", text)
            self.assertIn("](exp/f.png)", text)


if __name__ == "__main__":
    unittest.main()
