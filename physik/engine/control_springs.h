// Control-point springs (paper Sec. 3.3; original fwik.py): a zero-rest-length spring from the
// attachment point a = head + alpha (tail - head) to the effective target t:
//   linear         F = k (t - a)
//   capped-linear  F = k min(|t - a|, c) (t - a) / |t - a|      (|F| <= k c)
// F in N, k in N/m, c and distances in rig units. The force acts at a on the bone.
#pragma once

#include "physik/model/scene.h"
#include "physik/engine/state.h"

namespace physik {

// The spring force for a displacement d = t - a.
Vec3 spring_force(SpringLaw law, double k, double cap, const Vec3& d);

// Its tangent stiffness K = dF/dd = -dF/da (N/m, symmetric positive semi-definite), for the
// implicit step and the linearised modes:
//   linear, or capped with |d| <= c:  K = k 1
//   capped beyond the cap:            K = (k c / |d|) (1 - d d^T / |d|^2)
// (beyond the cap the force keeps its size k c: only its direction stiffens, across d)
Mat3 spring_tangent(SpringLaw law, double k, double cap, const Vec3& d);

void apply_control_springs(const Scene& scene, SimState& state);

}  // namespace physik
