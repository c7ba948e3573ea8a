"""plot_outside_rigs counts the outcomes per configuration and places every run in its cell."""
import os
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
import physik_plot  # noqa: E402
import plot_outside_rigs  # noqa: E402

HEADER = ("rig,bones,points,configuration,preset,outcome,steps_to_converge,steps_run,"
          "residual_over_size,damping,wall_s\n")
RUNS = HEADER + """arm,2,1,default,original,diverged,-1,2,0.2,3,0.001
arm,2,1,implicit,original,converged,40,49,1e-6,0.5,0.001
arm,2,2,default,original,converged,300,309,1e-4,3,0.001
arm,2,2,implicit,original,not_converged,-1,500,0.1,0.5,0.002
box,437,1,default,original,diverged,-1,1,0.3,3,0.4
box,437,1,implicit,,refused,-1,0,,,0.01
"""


def write(folder, text):
    with open(os.path.join(folder, "runs.csv"), "w") as f:
        f.write(text)
    return physik_plot.read_table(os.path.join(folder, "runs.csv"))


class OutsideRigsPlotTest(unittest.TestCase):
    def test_counts_per_configuration(self):
        with tempfile.TemporaryDirectory() as d:
            counts = plot_outside_rigs.outcome_counts(write(d, RUNS))
            self.assertEqual(list(counts), ["default", "implicit"])
            self.assertEqual(counts["default"],
                             {"converged": 1, "not_converged": 0, "diverged": 2, "refused": 0})
            self.assertEqual(counts["implicit"],
                             {"converged": 1, "not_converged": 1, "diverged": 0, "refused": 1})

    def test_every_run_has_its_cell(self):
        with tempfile.TemporaryDirectory() as d:
            scenes, configs, cells = plot_outside_rigs.outcome_grid(write(d, RUNS))
            self.assertEqual(scenes, ["arm, 1 pt", "arm, 2 pt", "box, 1 pt"])
            self.assertEqual(configs, ["default", "implicit"])
            self.assertEqual(len(cells), 6)
            self.assertEqual(cells[("arm, 1 pt", "implicit")], ("converged", 40))
            self.assertEqual(cells[("arm, 2 pt", "default")], ("converged", 300))
            self.assertEqual(cells[("box, 1 pt", "implicit")], ("refused", -1))
            plot_outside_rigs.main([d])
            self.assertGreater(os.path.getsize(os.path.join(d, "outside_rigs.png")), 1000)

    def test_empty_table_and_unknown_outcome_are_errors(self):
        with tempfile.TemporaryDirectory() as d:
            write(d, HEADER)
            with self.assertRaises(ValueError):
                plot_outside_rigs.main([d])
            bad = write(d, HEADER + "arm,2,1,default,original,exploded,-1,2,0.2,3,0.001\n")
            with self.assertRaises(ValueError):
                plot_outside_rigs.outcome_counts(bad)


if __name__ == "__main__":
    unittest.main()
