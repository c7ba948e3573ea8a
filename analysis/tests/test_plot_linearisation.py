"""plot_linearisation takes medians per rig and variant and draws them."""
import os
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
import physik_plot  # noqa: E402
import plot_linearisation  # noqa: E402

RUNS = """rig,target,variant,converged,diverged,steps,substeps,residual
chain10,0,shipped,1,0,20,30,1e-5
chain10,1,shipped,1,0,30,50,1e-5
chain10,0,newton,1,0,10,12,1e-5
chain10,1,newton,1,0,14,14,1e-5
chain50,0,shipped,1,0,300,700,1e-5
"""


class LinearisationPlotTest(unittest.TestCase):
    def test_medians_per_rig_and_variant(self):
        with tempfile.TemporaryDirectory() as d:
            with open(os.path.join(d, "runs.csv"), "w") as f:
                f.write(RUNS)
            m = plot_linearisation.medians(physik_plot.read_table(os.path.join(d, "runs.csv")))
            self.assertEqual(list(m), ["chain10", "chain50"])
            self.assertEqual(m["chain10"]["shipped"], (25.0, 40.0))
            self.assertEqual(m["chain10"]["newton"], (12.0, 13.0))
            plot_linearisation.main([d])
            self.assertGreater(os.path.getsize(os.path.join(d, "linearisation.png")), 1000)

    def test_empty_table_is_an_error(self):
        with tempfile.TemporaryDirectory() as d:
            with open(os.path.join(d, "runs.csv"), "w") as f:
                f.write(RUNS.splitlines()[0] + "\n")
            with self.assertRaises(ValueError):
                plot_linearisation.main([d])


if __name__ == "__main__":
    unittest.main()
