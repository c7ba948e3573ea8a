"""plot_beyond_the_paper.py writes a non-empty PNG from a small fixture."""
import os
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
import plot_beyond_the_paper  # noqa: E402


def write(folder, name, text):
    with open(os.path.join(folder, name), "w") as f:
        f.write(text)


class PlotBeyondThePaper(unittest.TestCase):
    def test_plot(self):
        with tempfile.TemporaryDirectory() as d:
            write(d, "stability_map.csv", "scheme,dt,damping,outcome,steps_to_converge,steps_run,peak_kinetic_energy\n"
                  "explicit,0.05,1,settled,60,70,1\nexplicit,1,1000,diverged,-1,3,1e9\n"
                  "implicit,0.05,1,settled,60,70,1\nimplicit,1,1000,neither,-1,200,0.1\n")
            write(d, "insensitivity.csv", "scene,scheme,damping,outcome,converged,diverged,steps_to_converge,"
                  "steps_run,max_final_residual\ns,explicit,1,settled,1,0,60,70,0.1\ns,explicit,20,diverged,0,1,-1,5,9\n"
                  "s,implicit,1,settled,1,0,70,80,0.1\ns,implicit,20,settled,1,0,200,210,0.1\n")
            write(d, "large_steps.csv", "torsion_torque,dt,step,distance_to_equilibrium\naxes,1,1,0.1\naxes,1,2,1e-9\n"
                  "axes,0.05,1,0.5\naxes,0.05,2,0.4\ngradient,1,1,0.1\ngradient,1,2,1e-10\n")
            png = plot_beyond_the_paper.plot(d)
            self.assertTrue(os.path.getsize(png) > 1000)


if __name__ == "__main__":
    unittest.main()
