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

    def test_empty_sweep_is_an_error(self):
        with tempfile.TemporaryDirectory() as d:
            with open(os.path.join(d, "sweep.csv"), "w") as f:
                f.write(SWEEP.splitlines()[0] + "\n")
            with self.assertRaises(ValueError):
                plot_tuning_study.read_sweep(os.path.join(d, "sweep.csv"))


if __name__ == "__main__":
    unittest.main()
