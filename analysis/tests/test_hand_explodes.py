"""plot_hand_explodes: each plot function writes a non-empty PNG from a small fixture (one sweep
run stops early, as a diverged run does: its cells are empty)."""
import json
import os
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
import plot_hand_explodes as plot  # noqa: E402

BONES = """bone,parent,head_x,head_y,head_z,tail_x,tail_y,tail_z
wrist,,0,0,0,0,0,1
f,wrist,0,0,1,0.1,0,1.4
"""
TIMELINE = """step,kinetic_energy,max_limit_violation_deg,max_residual,ke_k1_c1,limit_k1_c1,ke_k100_c1,limit_k100_c1
1,0.1,0,0.5,0.1,0,0.1,0
2,0.05,0.5,0.4,0.2,1,50,30
3,0.01,0.2,0.3,0.1,0.5,,
"""
SWEEP = """torsion_k,damping,steps_run,diverged,converged,peak_kinetic_energy,max_limit_violation_deg,max_joint_separation,final_max_residual,explodes
1,1,3,0,0,0.2,1,0,0.3,0
100,1,2,1,0,50,30,0,2,1
"""


def write(folder, name, text):
    with open(os.path.join(folder, name), "w") as f:
        f.write(text)


def fixture(d):
    write(d, "timeline.csv", TIMELINE)
    write(d, "sweep.csv", SWEEP)
    write(d, "hand_0.csv", BONES)
    write(d, "hand_3.csv", BONES)
    write(d, "summary.json", json.dumps({"frames": ["hand_0.csv", "hand_3.csv"],
                                         "frame_steps": [0, 3]}))


class HandPlotTest(unittest.TestCase):
    def test_plot_timeline_writes_png(self):
        with tempfile.TemporaryDirectory() as d:
            fixture(d)
            png = plot.plot_timeline(os.path.join(d, "timeline.csv"), os.path.join(d, "t.png"))
            self.assertGreater(os.path.getsize(png), 1000)

    def test_plot_sweep_writes_png(self):
        with tempfile.TemporaryDirectory() as d:
            fixture(d)
            png = plot.plot_sweep(os.path.join(d, "sweep.csv"), os.path.join(d, "s.png"))
            self.assertGreater(os.path.getsize(png), 1000)

    def test_plot_poses_writes_png(self):
        with tempfile.TemporaryDirectory() as d:
            fixture(d)
            png = plot.plot_poses(d, ["hand_0.csv", "hand_3.csv"], [0, 3], os.path.join(d, "p.png"))
            self.assertGreater(os.path.getsize(png), 1000)

    def test_main_writes_every_figure(self):
        with tempfile.TemporaryDirectory() as d:
            fixture(d)
            plot.main([d])
            for png in ("hand_timeline.png", "hand_sweep.png", "hand_poses.png"):
                self.assertGreater(os.path.getsize(os.path.join(d, png)), 1000)


if __name__ == "__main__":
    unittest.main()
