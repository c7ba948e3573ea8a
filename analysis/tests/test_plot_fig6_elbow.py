"""Fig 6's plot: the drawn limit is the forearm turned exactly 90 deg from the upper arm, on the
side the forearm bends to, and the figure draws from a summary with the targets."""
import json
import math
import os
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
import plot_fig6_elbow  # noqa: E402


def elbow(bend_deg, sign=1):
    """The elbow rig posed: upper arm up +Z from the origin, forearm bent by bend_deg about x."""
    a = math.radians(bend_deg) * sign
    return [{"bone": "upper_arm", "parent": "", "head": (0, 0, 0), "tail": (0, 0, 2)},
            {"bone": "forearm", "parent": "upper_arm", "head": (0, 0, 2),
             "tail": (0, 2 * math.sin(a), 2 + 2 * math.cos(a))}]


class Fig6PlotTest(unittest.TestCase):
    def test_limit_ray_is_the_forearm_at_ninety_degrees_on_its_side(self):
        for sign in (1, -1):
            (hy, hz), (ty, tz) = plot_fig6_elbow.limit_ray(elbow(120, sign))
            self.assertEqual((hy, hz), (0, 2))
            self.assertAlmostEqual(ty, 2 * sign)  # 90 deg from +Z, toward the bend
            self.assertAlmostEqual(tz, 2)
            at_limit = elbow(90, sign)[1]["tail"]
            self.assertAlmostEqual(ty, at_limit[1])

    def test_draws_targets_from_the_summary(self):
        with tempfile.TemporaryDirectory() as d:
            with open(os.path.join(d, "f.csv"), "w") as f:
                f.write("bone,parent,head_x,head_y,head_z,tail_x,tail_y,tail_z\n")
                for b in elbow(115):
                    f.write("%s,%s,%s\n" % (b["bone"], b["parent"],
                                            ",".join(str(v) for v in b["head"] + b["tail"])))
            case = {"case": "near_linear", "final_frame": "f.csv", "final_overbend_deg": 25.0,
                    "peak_overbend_deg": 27.0, "targets_world": [[0, 0, 0], [0, 0, 2], [0, 1.6, 1]]}
            with open(os.path.join(d, "summary.json"), "w") as f:
                json.dump({"cases": [case, dict(case, targets_world=[])]}, f)
            png = plot_fig6_elbow.plot(d)
            self.assertGreater(os.path.getsize(png), 1000)


if __name__ == "__main__":
    unittest.main()
