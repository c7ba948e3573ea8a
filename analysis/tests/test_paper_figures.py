"""The lead's figure scripts (Fig 5-8, timing, damping sweep): each writes non-empty PNGs from a
small fixture made here."""
import json
import os
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
import plot_contacts_cost  # noqa: E402
import plot_damping_sweep  # noqa: E402
import plot_fig5_running  # noqa: E402
import plot_fig6_elbow  # noqa: E402
import plot_fig7_cannon  # noqa: E402
import plot_fig8_wobble  # noqa: E402
import plot_mujoco_gap  # noqa: E402
import plot_timing  # noqa: E402
import plot_tracking  # noqa: E402

BONES = """bone,parent,head_x,head_y,head_z,tail_x,tail_y,tail_z
a,,0,0,0,0,0,1
b,a,0,0,1,0.5,0.2,1.5
"""


def write(folder, name, text):
    with open(os.path.join(folder, name), "w") as f:
        f.write(text if isinstance(text, str) else json.dumps(text))


def trajectory(n=5, ncontrol=2):
    cols = ["step", "time", "kinetic_energy", "passes", "joint_mismatch", "joint_separation"]
    cols += ["residual_%d" % c for c in range(ncontrol)]
    cols += ["a.%s_%s" % (e, x) for e in ("head", "tail") for x in "xyz"]
    rows = [",".join(cols)]
    for k in range(1, n + 1):
        rows.append(",".join(str(v) for v in [k, 0.05 * k, 1.0 / k, 3, 1e-4, 0] + [0.1 / k] * ncontrol
                             + [0, 0, 0, 0, 0, 1]))
    return "\n".join(rows) + "\n"


class PaperFigureScripts(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.d = self.tmp.name
        write(self.d, "f0.csv", BONES)
        write(self.d, "f1.csv", BONES)

    def tearDown(self):
        self.tmp.cleanup()

    def assertPng(self, path):
        self.assertTrue(os.path.isfile(path), path)
        self.assertGreater(os.path.getsize(path), 1000)

    def test_fig5(self):
        write(self.d, "summary.json", {"control_points": [{"target": [0, 0, 1]}], "frames": ["f0.csv", "f1.csv"],
                                       "final_frame": "f1.csv", "summary": {"steps_run": 10}})
        self.assertPng(plot_fig5_running.plot(self.d))

    def test_fig6(self):
        write(self.d, "summary.json", {"cases": [
            {"case": "near_linear", "final_frame": "f1.csv", "final_overbend_deg": 3.0, "peak_overbend_deg": 4.0},
            {"case": "near_capped", "final_frame": "f0.csv", "final_overbend_deg": 1.0, "peak_overbend_deg": 2.0}]})
        self.assertPng(plot_fig6_elbow.plot(self.d))

    def test_fig7(self):
        write(self.d, "lin.csv", trajectory(ncontrol=1))
        law = {"frames": ["f0.csv", "f1.csv"], "frame_steps": [0, 5], "csv": "lin.csv",
               "control_bone": "a", "control_alpha": 0.5, "target_world": [0, -12, 1]}
        write(self.d, "summary.json", {"laws": {"linear": law, "capped": law}})
        for png in plot_fig7_cannon.plot(self.d):
            self.assertPng(png)

    def test_fig8(self):
        write(self.d, "trajectory.csv", trajectory(ncontrol=3))
        self.assertPng(plot_fig8_wobble.plot(self.d))

    def test_timing(self):
        write(self.d, "summary.json", {"rows": [
            {"scene": "s", "us_per_step": 10.0, "passes_per_step": 4.0, "passes_per_step_while_moving": 12.0}]})
        self.assertPng(plot_timing.plot(self.d))

    def test_contacts_cost(self):
        rows = [{"workload": "pinhead", "bones": 19, "contacts_us": 12.0, "no_contacts_us": 8.0,
                 "ratio": 1.5}]
        rows += [{"workload": w, "bones": n, "contacts_us": 0.1 * n, "no_contacts_us": 0.04 * n,
                  "ratio": 2.5} for w in ("flat_spiral", "flat_ring") for n in (125, 250)]
        write(self.d, "summary.json", {"rows": rows})
        self.assertPng(plot_contacts_cost.plot(self.d))
        for drop in ("pinhead", "flat_ring"):
            write(self.d, "summary.json", {"rows": [r for r in rows if r["workload"] != drop]})
            with self.assertRaisesRegex(ValueError, drop):
                plot_contacts_cost.plot(self.d)

    def test_tracking(self):
        write(self.d, "frames.csv", "solver,frame,cost_us,lag,jump_ratio\nphysik k=3,1,5.0,0.01,1.2\n"
                                    "physik k=3,2,5.0,0.0,1.1\ndls,1,9.0,1e-5,2.0\ndls,2,8.0,1e-5,1.5\n")
        self.assertPng(plot_tracking.plot(self.d))

    def test_mujoco_gap(self):
        write(self.d, "gap_over_time.csv", "scene,mode,step,gap,exact_gap\ns,same-forces,1,0.1,1e-15\n"
                                           "s,same-forces,6,0.05,0\ns,exact-constraints,1,0.2,0.1\n"
                                           "s,exact-constraints,6,0.3,\n")
        write(self.d, "summary.json", {"rows": [{"scene": "s", "mode": "same-forces",
                                                 "physik_csv": "f0.csv", "mujoco_csv": "f1.csv"}]})
        for png in plot_mujoco_gap.plot(self.d):
            self.assertPng(png)

    def test_damping_sweep(self):
        write(self.d, "sweep.csv",
              "scene,damping,converged,steps_to_converge,diverged,steps_run,peak_kinetic_energy,max_final_residual\n"
              "s,1,1,80,0,90,1.0,0.0\ns,3,1,60,0,70,1.0,0.0\ns,20,0,-1,1,8,1e9,5.0\n")
        self.assertPng(plot_damping_sweep.plot(self.d))


if __name__ == "__main__":
    unittest.main()
