// Torsion springs that enforce joint limits (paper Sec. 3.4; original fwik.py).
//
// For bone i with parent p, q_i is its rotation relative to its rest orientation in the parent's
// frame, and theta = log(q_i) its rotation vector; theta_k is the angle about local axis k
// (k = x, y, z of the rest frame carried by the parent, R_p R_rest_in_parent). For a limited axis
// with range [min, max], the spring engages `tolerance` x (max - min) inside each limit:
//   lo = min + tol (max - min),  hi = max - tol (max - min)
//   d  = lo - theta_k  if theta_k < lo;   d = hi - theta_k  if theta_k > hi;   else 0
//   linear  tau_k = k d              capped  tau_k = k min(|d|, c) sign(d)
// A locked axis (min == max) always pulls toward its value. The torque, turned to world axes
// (tau_world = R_p R_rest_in_parent tau_local), acts on the bone; its opposite acts on the parent.
// k in N m/rad, c in rad. The root has no parent and no limits.
#pragma once

#include "physik/model/params.h"
#include "physik/model/rig.h"
#include "physik/engine/state.h"

namespace physik {

// The local torque (N m, per rest axis) for joint angles theta of bone i.
Vec3 torsion_torque_local(const std::array<AxisLimit, 3>& limits, const Vec3& theta,
                          const EngineParams& params);

// Its stiffness per axis, -d tau_k / d theta_k (N m/rad): k on an engaged axis (linear, or capped
// within the cap), 0 outside the band or beyond the cap. For the implicit step and the modes.
Vec3 torsion_stiffness_local(const std::array<AxisLimit, 3>& limits, const Vec3& theta,
                             const EngineParams& params);

// The stiffness the implicit step uses: the same, but beyond the cap of a capped spring the
// secant k c / |d| instead of 0, a majoriser of the potential as for the capped control spring
// (spring_step_stiffness, control_springs.h).
Vec3 torsion_step_stiffness_local(const std::array<AxisLimit, 3>& limits, const Vec3& theta,
                                  const EngineParams& params);

// Requires state.pose to hold the current local rotations.
void apply_torsion_springs(const Rig& rig, const EngineParams& params, SimState& state);

}  // namespace physik
