"""plot_fig9_outstretched: each plot function writes a non-empty PNG from a small fixture."""
import json
import os
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
import plot_fig9_outstretched as plot  # noqa: E402

BONES = """bone,parent,head_x,head_y,head_z,tail_x,tail_y,tail_z
a,,0,0,2,0,0,1
b,a,0,0,1,-1,-0.2,1
"""
MEASURES = """method,shoulder_turn_deg,lean_deg,lean_forward_deg,lean_side_deg,head_tilt_deg,neck_bend_deg,off_chain_rotation_rad,off_reach_rotation_rad,max_residual,max_limit_excess_deg
physik,5,3,2,-1,4,1,0.5,1.2,0.01,0
dls,0.5,0,0,0,0.2,0,0.1,0.2,0.001,0
itasc,-15,0,0,0,0.2,0.2,1.0,1.1,0.0001,0.02
"""


def write(folder, name, text):
    with open(os.path.join(folder, name), "w") as f:
        f.write(text)


class Fig9PlotTest(unittest.TestCase):
    def test_plot_poses_writes_png(self):
        with tempfile.TemporaryDirectory() as d:
            for name in ("rest.csv", "physik_final.csv", "dls_final.csv"):
                write(d, name, BONES)
            png = plot.plot_poses(d, os.path.join(d, "poses.png"), targets=[[-1, -0.2, 1]])
            self.assertGreater(os.path.getsize(png), 1000)

    def test_plot_measures_writes_png(self):
        with tempfile.TemporaryDirectory() as d:
            write(d, "measures.csv", MEASURES)
            png = plot.plot_measures(os.path.join(d, "measures.csv"), os.path.join(d, "m.png"))
            self.assertGreater(os.path.getsize(png), 1000)

    def test_itasc_pose_is_drawn_when_the_experiment_wrote_it(self):
        with tempfile.TemporaryDirectory() as d:
            for name in ("rest.csv", "physik_final.csv", "dls_final.csv", "mujoco_final.csv"):
                write(d, name, BONES)
            labels = [p[1] for p in plot.poses_present(d)]
            self.assertNotIn("Blender iTaSC", labels)  # no Blender: three columns
            write(d, "itasc_final.csv", BONES)
            labels = [p[1] for p in plot.poses_present(d)]
            self.assertEqual(labels, ["PhysIK", "damped least squares", "Blender iTaSC",
                                      "MuJoCo, same forces"])
            png = plot.plot_poses(d, os.path.join(d, "poses.png"), targets=[[-1, -0.2, 1]])
            self.assertGreater(os.path.getsize(png), 1000)

    def test_main_writes_both_figures(self):
        with tempfile.TemporaryDirectory() as d:
            for name in ("rest.csv", "physik_final.csv", "dls_final.csv", "mujoco_final.csv"):
                write(d, name, BONES)
            write(d, "measures.csv", MEASURES)
            write(d, "summary.json", json.dumps({"targets": [[-1, -0.2, 1]]}))
            plot.main([d])
            for png in ("fig9_poses.png", "fig9_measures.png"):
                self.assertGreater(os.path.getsize(os.path.join(d, png)), 1000)


if __name__ == "__main__":
    unittest.main()
