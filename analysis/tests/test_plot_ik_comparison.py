"""plot_ik_comparison draws every figure and the table from a small summary fixture."""
import json
import os
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
import plot_ik_comparison  # noqa: E402


def row(rig, solver, success):
    return {"rig": rig, "solver": solver, "reachable": 10, "unreachable": 2, "success_rate": success,
            "median_residual_over_reach": 1e-5,
            "median_iterations": 12.0, "p95_iterations": 40.0, "mean_time_ms": 0.05,
            "max_limit_violation_deg": 0.0, "mean_total_rotation_rad": 1.5, "mean_offpath_motion": 0.0,
            "unreachable_not_converged": 1.0, "unreachable_excess_over_reach": 0.001,
            "continuity_median_ratio": 2.0, "continuity_p95_ratio": 8.0, "continuity_jumps_over_10": 0.0}


class IkComparisonPlotTest(unittest.TestCase):
    def test_every_figure_and_the_table_are_written(self):
        with tempfile.TemporaryDirectory() as d:
            rows = [row("chain3", "dls", 1.0), row("chain3", "ccd", 0.9), row("pinhead", "dls", 0.8)]
            with open(os.path.join(d, "summary.json"), "w") as f:
                json.dump({"table": rows}, f)
            plot_ik_comparison.main([d])
            for name in ("ik_success.png", "ik_time.png", "ik_continuity.png"):
                self.assertGreater(os.path.getsize(os.path.join(d, name)), 1000)
            table = open(os.path.join(d, "ik_comparison_table.md")).read()
            self.assertIn("| chain3 | ccd | 10+2 | 90.0% |", table)

    def test_empty_table_is_an_error(self):
        with tempfile.TemporaryDirectory() as d:
            with self.assertRaises(ValueError):
                plot_ik_comparison.grouped_bars([], "success_rate", "y", os.path.join(d, "x.png"))


if __name__ == "__main__":
    unittest.main()
