// Control-point springs (paper Sec. 3.3; original fwik.py): a zero-rest-length spring from the
// attachment point a = head + alpha (tail - head) to the effective target t:
//   linear         F = k (t - a)
//   capped-linear  F = k min(|t - a|, c) (t - a) / |t - a|      (|F| <= k c)
// F in N, k in N/m, c and distances in rig units. The force acts at a on the bone.
//
// Potential, d = |a - t|: linear U = k d^2 / 2; capped U = k d^2 / 2 (d <= c),
// k c (d - c/2) (d > c); F is minus its gradient in a. Energies in J.
//
// Implicit step (implicit_step.h): a point element at a, A = h^2 K_c with K_c = the step
// stiffness below (the tangent, and beyond the cap the secant), and the force -h K_c v_a on the
// right-hand side. Damping auto's modes (linear_modes.h): a point element K = the tangent toward
// the given targets. The pose-terms step reads the stage's forces (state.control_force_world).
// MuJoCo's reference applies the same force.
#pragma once

#include <vector>

#include "physik/engine/force_stages.h"
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
// step along the pull meets no stiffness and overshoots (tests/implicit_step_test.cpp: long
// steps on a chain pulled far beyond its cap).
Mat3 spring_step_stiffness(SpringLaw law, double k, double cap, const Vec3& d);

// U of one spring at distance d (rig units), J; the equilibrium's residuals (tune/equilibrium.h)
// are its square roots.
double control_spring_potential(SpringLaw law, double k, double cap, double distance);

// The force stage: every spring's force toward its effective target (state.control_force_world).
void apply_control_springs(const Scene& scene, SimState& state);
// U of the state's springs toward their effective targets, J.
double control_springs_potential(const Scene& scene, const SimState& state);
// The implicit step: the step stiffness of every spring (state.implicit.control_stiffness:
// tangents), then -h K_c v at each point (rate); h^2 K_c into the bone's articulated inertia
// (augment).
void control_springs_tangents(const Scene& scene, SimState& state);
void control_springs_rate(const Scene& scene, const ImplicitStage& stage, SimState& state);
void control_springs_augment(const Scene& scene, const ImplicitStage& stage, SimState& state);
// Damping auto: the tangent toward `targets` at each point.
void control_springs_mode_stiffness(const Scene& scene, const SimState& state,
                                    const std::vector<Vec3>& targets, ModeStiffness& out);
// The pose-terms step (implicit_pose_terms.h): each spring's force at its point, as the force
// stage left it (state.control_force_world).
void control_springs_pose_forces(const Scene& scene, const SimState& state, PoseForces& out);

}  // namespace physik
