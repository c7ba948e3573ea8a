"""plot_fig11_sit: each plot function writes a non-empty PNG from a small fixture."""
import json
import os
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
import plot_fig11_sit as plot  # noqa: E402

BONES = """bone,parent,head_x,head_y,head_z,tail_x,tail_y,tail_z
a,,0,0,2,0,0,1
b,a,0,0,1,0,0.5,0.5
"""
RESIDUALS = """step,kinetic_energy,residual_pelvis,residual_heel.L
1,0.5,0.3,0.001
2,0.2,0.1,0.002
3,0.0,0.01,0.0
"""


def write(folder, name, text):
    with open(os.path.join(folder, name), "w") as f:
        f.write(text)


def fixture(d):
    frames = []
    for s in (0, 2, 3):
        write(d, "sit_%d.csv" % s, BONES)
        frames.append({"step": s, "file": "sit_%d.csv" % s})
    write(d, "residuals.csv", RESIDUALS)
    write(d, "summary.json", json.dumps({
        "frames": frames, "schedule_steps": [2],
        "control_points": [{"name": "heel.L", "moving": False, "target": [0, 0.5, 0.5]},
                           {"name": "pelvis", "moving": True, "target": [0, 0, 1]}]}))
    return frames


class Fig11PlotTest(unittest.TestCase):
    def test_plot_frames_writes_png(self):
        with tempfile.TemporaryDirectory() as d:
            frames = fixture(d)
            png = plot.plot_frames(d, frames, os.path.join(d, "f.png"), targets=[[0, 0.5, 0.5]])
            self.assertGreater(os.path.getsize(png), 1000)

    def test_plot_residuals_writes_png(self):
        with tempfile.TemporaryDirectory() as d:
            fixture(d)
            png = plot.plot_residuals(os.path.join(d, "residuals.csv"), os.path.join(d, "r.png"),
                                      [2])
            self.assertGreater(os.path.getsize(png), 1000)

    def test_main_writes_both_figures(self):
        with tempfile.TemporaryDirectory() as d:
            fixture(d)
            plot.main([d])
            for png in ("fig11_frames.png", "fig11_residuals.png"):
                self.assertGreater(os.path.getsize(os.path.join(d, png)), 1000)


if __name__ == "__main__":
    unittest.main()
