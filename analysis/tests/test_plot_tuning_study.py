"""The tuning-study plot writes a non-empty PNG from a small fixture; an empty sweep is an error."""
import json
import os
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
import plot_tuning_study  # noqa: E402

SWEEP = """variant,scale,density,damping,steps_to_converge,diverged
1x / 1 kg/unit,1,1,0.1,-1,0
1x / 1 kg/unit,1,1,1,60,0
1x / 1 kg/unit,1,1,3,65,0
1x / 1 kg/unit,1,1,10,-1,1
10x / 1 kg/unit,10,1,1,900,0
10x / 1 kg/unit,10,1,10,300,0
10x / 1 kg/unit,10,1,100,-1,1
"""
ROWS = {"rows": [{"variant": "1x / 1 kg/unit", "c_tuned": 0.8, "c_rule": 1.5},
                 {"variant": "10x / 1 kg/unit", "c_tuned": 6.0, "c_rule": 5.0}]}


class TuningStudyPlotTest(unittest.TestCase):
    def test_writes_png(self):
        with tempfile.TemporaryDirectory() as d:
            with open(os.path.join(d, "sweep.csv"), "w") as f:
                f.write(SWEEP)
            with open(os.path.join(d, "summary.json"), "w") as f:
                json.dump(ROWS, f)
            plot_tuning_study.main([d])
            self.assertGreater(os.path.getsize(os.path.join(d, "tuning_study.png")), 1000)

    def test_diverged_band_covers_only_diverged_runs(self):
        # a low c that diverges and high ones, with settling runs between: two bands, and no
        # settling c inside either (the band once ran from the first diverged c to the grid's end)
        pts = [(1e-3, None, True), (1e-2, None, True), (0.2, 679, False), (3.2, 91, False),
               (10.0, None, True), (100.0, None, True), (1e3, None, True)]
        spans = plot_tuning_study.diverged_spans(pts)
        self.assertEqual(len(spans), 2)
        self.assertEqual(spans[0][0], 1e-3)
        self.assertEqual(spans[1][1], 1e3)
        for c, steps, diverged in pts:
            inside = any(lo <= c <= hi for lo, hi in spans)
            self.assertEqual(inside, diverged, c)
        self.assertEqual(plot_tuning_study.diverged_spans(pts[2:4]), [])

    def test_empty_sweep_is_an_error(self):
        with tempfile.TemporaryDirectory() as d:
            with open(os.path.join(d, "sweep.csv"), "w") as f:
                f.write(SWEEP.splitlines()[0] + "\n")
            with self.assertRaises(ValueError):
                plot_tuning_study.read_sweep(os.path.join(d, "sweep.csv"))


if __name__ == "__main__":
    unittest.main()
