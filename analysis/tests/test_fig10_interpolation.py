"""plot_fig10_interpolation: each plot function writes a non-empty PNG from a small fixture."""
import json
import os
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
import plot_fig10_interpolation as plot  # noqa: E402

BONES = """bone,parent,head_x,head_y,head_z,tail_x,tail_y,tail_z
a,,0,0,2,0,0,1
b,a,0,0,1,1,0,1.5
"""


def motion_csv(nstep=6):
    cols = ["step"]
    for p in ("polar", "linear"):
        cols += [p + s for s in ("_off_chain_rad", "_off_arm_rad", "_kinetic_energy", "_tip_x",
                                 "_tip_y", "_tip_z", "_target_x", "_target_y", "_target_z")]
    rows = [",".join(cols)]
    for k in range(1, nstep + 1):
        vals = [str(k)]
        for scale in (1.0, 2.0):
            vals += [str(0.01 * k * scale), str(0.02 * k * scale), str(0.1 / k), str(1 + 0.1 * k),
                     "0", str(1.5 + 0.1 * k), str(1 + 0.1 * k), "0", str(1.6 + 0.1 * k)]
        rows.append(",".join(vals))
    return "\n".join(rows) + "\n"


def write(folder, name, text):
    with open(os.path.join(folder, name), "w") as f:
        f.write(text)


def fixture(d):
    frames = {}
    for key, prefix in (("polar_com", "polar-com"), ("linear", "linear")):
        names = []
        for s in (0, 3, 6):
            names.append("%s_%d.csv" % (prefix, s))
            write(d, names[-1], BONES)
        frames[key] = {"frames": names, "frame_steps": [0, 3, 6]}
    write(d, "secondary_motion.csv", motion_csv())
    summary = dict(frames, interpolation_steps=3)
    write(d, "summary.json", json.dumps(summary))
    return summary


class Fig10PlotTest(unittest.TestCase):
    def test_plot_frames_writes_png(self):
        with tempfile.TemporaryDirectory() as d:
            summary = fixture(d)
            png = plot.plot_frames(d, summary, os.path.join(d, "f.png"))
            self.assertGreater(os.path.getsize(png), 1000)

    def test_plot_secondary_motion_writes_png(self):
        with tempfile.TemporaryDirectory() as d:
            fixture(d)
            png = plot.plot_secondary_motion(os.path.join(d, "secondary_motion.csv"),
                                             os.path.join(d, "s.png"), 3)
            self.assertGreater(os.path.getsize(png), 1000)

    def test_main_writes_both_figures(self):
        with tempfile.TemporaryDirectory() as d:
            fixture(d)
            plot.main([d])
            for png in ("fig10_frames.png", "fig10_secondary_motion.png"):
                self.assertGreater(os.path.getsize(os.path.join(d, png)), 1000)


if __name__ == "__main__":
    unittest.main()
