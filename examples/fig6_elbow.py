"""Paper Fig 6: an elbow limited to 90..180 deg pulled past its limit by linear and by capped
control springs (models/scenes/fig6_elbow_*.json; experiments/fig6_elbow.cpp, "near" target).
Prints the forearm's over-bend past 90 deg at rest and at its peak during the run, in degrees.
Run: PYTHONPATH=build/python /usr/bin/python3 examples/fig6_elbow.py"""
import os
import numpy as np
import physik

def overbend_deg(q):  # q: the forearm's rest-relative rotation (x, y, z, w); it bends about -x
    q = -q if q[3] < 0 else q
    s = np.linalg.norm(q[:3])
    rotvec_x = q[0] * (2 * np.arctan2(s, q[3]) / s if s >= 1e-12 else 2.0)
    return max(0.0, -np.degrees(rotvec_x) - 90.0)

scenes = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "models", "scenes")
print("law final_overbend_deg peak_overbend_deg")
for law in ("linear", "capped"):
    sim = physik.Simulation(physik.Scene.load(os.path.join(scenes, "fig6_elbow_%s.json" % law)))
    forearm = sim.pose.local_rotations[sim.scene.rig.find_bone("forearm")]  # a view: follows the run
    peak = 0.0
    for _ in range(sim.scene.steps):
        sim.step()
        peak = max(peak, overbend_deg(forearm))
    print("%-7s %.10f %.10f" % (law, overbend_deg(forearm), peak))
