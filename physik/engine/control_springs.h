// Control-point springs (paper Sec. 3.3; original fwik.py): a zero-rest-length spring from the
// attachment point a = head + alpha (tail - head) to the effective target t:
//   linear         F = k (t - a)
//   capped-linear  F = k min(|t - a|, c) (t - a) / |t - a|      (|F| <= k c)
// F in N, k in N/m, c and distances in rig units. The force acts at a on the bone.
#pragma once

#include "physik/engine/state.h"
#include "physik/model/scene.h"

namespace physik {

// The spring force for a displacement d = t - a.
Vec3 spring_force(SpringLaw law, double k, double cap, const Vec3& d);

// Its tangent stiffness K = dF/dd = -dF/da (N/m, symmetric positive semi-definite), for the
// implicit step and the linearised modes:
//   linear, or capped with |d| <= c:  K = k 1
//   capped beyond the cap:            K = (k c / |d|) (1 - d d^T / |d|^2)
// (beyond the cap the force keeps its size k c: only its direction stiffens, across d)
Mat3 spring_tangent(SpringLaw law, double k, double cap, const Vec3& d);

// The stiffness the implicit step uses (implicit_step.h), symmetric positive definite:
//   linear, or capped with |d| <= c:  K = k 1 (the tangent)
//   capped beyond the cap:            K = (k c / |d|) 1
// Across d it is the tangent; along d, where the tangent is 0, it is the secant k c / |d|. The
// quadratic model U(d) - F.(x - d) + (x - d)^T K (x - d) / 2 then lies above the capped
// potential everywhere (it exceeds it by k c (|x| - |d|)^2 / (2 |d|) beyond the cap, by at least
// that within it: a majoriser, as in iteratively reweighted least squares), so a step of any
// size moves the point at most onto its target, never past it. With the tangent alone a long
// step along the pull meets no stiffness and overshoots (measured: implicit steps of dt >= 1
// diverge on a chain pulled far beyond its cap; tests/implicit_step_test.cpp).
Mat3 spring_step_stiffness(SpringLaw law, double k, double cap, const Vec3& d);

void apply_control_springs(const Scene& scene, SimState& state);

}  // namespace physik
