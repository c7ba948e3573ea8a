"""The data the fixed figures draw, taken from their CSV as the plot scripts take it: Fig 7's
control-point path and one box for every panel, the damping sweep's three outcomes (a run that
neither converged nor diverged is kept, not dropped), and the MuJoCo gap's lines per scene."""
import os
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
import physik_plot  # noqa: E402
import plot_damping_sweep  # noqa: E402
import plot_fig7_cannon  # noqa: E402
import plot_mujoco_gap  # noqa: E402


def table(text):
    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, "t.csv")
        with open(path, "w") as f:
            f.write(text)
        return physik_plot.read_table(path)


class FigureDataTest(unittest.TestCase):
    def test_fig7_path_is_the_control_point_up_to_the_frame(self):
        t = table("step,torso.head_x,torso.head_y,torso.head_z,torso.tail_x,torso.tail_y,torso.tail_z\n"
                  "0,0,0,1,0,0,2\n5,0,-1,1,0,-1,2\n10,0,-3,1,0,-3,2\n")
        path = plot_fig7_cannon.control_path(t, "torso", 0.5, 5)
        self.assertEqual(path, [(0, 0, 1.5), (0, -1, 1.5)])
        lo, hi = plot_fig7_cannon.bounds(path + [(0, -12, 1.13)], margin=0)
        self.assertEqual((lo[1], hi[1]), (-12, 0))  # the target's 12 units are inside every panel

    def test_damping_sweep_keeps_every_outcome(self):
        t = table("scene,damping,converged,steps_to_converge,diverged\n"
                  "fig5_running,2.5,1,194,0\nfig5_running,3,0,-1,0\nfig5_running,5,0,-1,1\n"
                  "pinhead,3,1,90,0\n")
        o = plot_damping_sweep.outcomes(t)
        self.assertEqual(o["fig5_running"], {"converged": [(2.5, 194)], "not_converged": [3],
                                             "diverged": [5]})
        self.assertEqual(o["pinhead"]["converged"], [(3, 90)])

    def test_mujoco_gap_gives_each_scene_its_own_lines(self):
        t = table("scene,mode,step,gap,exact_gap\n"
                  "a,same-forces,1,0.1,1e-15\na,exact-constraints,1,0.2,\nb,same-forces,1,0.3,2e-15\n")
        s = plot_mujoco_gap.gap_series(t)
        self.assertEqual(sorted(s), ["a", "b"])
        self.assertEqual([(m, k) for m, k, _, _ in s["a"]],
                         [("exact-constraints", "gauss-seidel"), ("same-forces", "gauss-seidel"),
                          ("same-forces", "exact")])
        self.assertEqual(len(s["b"]), 2)


if __name__ == "__main__":
    unittest.main()
