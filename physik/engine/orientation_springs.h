// Orientation targets (scene.h OrientationTarget): a rotational spring from a bone's frame R to
// its target frame R_t, both world<-bone. With phi = log(R_t R^T) the turn that takes the bone
// onto its target (world axes, |phi| <= pi), the law is the control springs' (control_springs.h)
// on phi:
//   linear         tau = k phi
//   capped-linear  tau = k min(|phi|, c) phi / |phi|     (|tau| <= k c)
// a couple on the bone (it moves no point), tau in N m, k in N m/rad, c in rad.
//
// Potential, theta = |phi|: linear U = k theta^2 / 2; capped U = k theta^2 / 2 (theta <= c),
// k c (theta - c/2) (theta > c). tau is minus its gradient in the bone's turn: turning the bone
// by dr (world axes) changes phi by -J_r^-1(phi) dr, and phi^T J_r^-1(phi) = phi^T, so
// dU = -tau . dr (J_r the right Jacobian of SO(3): J. Sola, J. Deray, D. Atchuthan, "A micro
// Lie theory for state estimation in robotics", arXiv:1812.01537, 2018).
//
// Implicit step (implicit_step.h): a couple element (implicit_elements.h) with the control
// springs' step stiffness on phi, K = k 1 (the secant k c / theta 1 beyond the cap): the Hessian
// of U in the turn is k (sym J_r^-1) = k (1 along phi, (theta/2) cot(theta/2) <= 1 across), so
// k 1 bounds it above and the quadratic model majorises U as the control springs' does. Damping
// auto's modes: a couple K = the control springs' tangent on phi (k 1 within the cap).
// MuJoCo's reference applies the same torque. The pose-terms step (implicit_linearisation full,
// implicit_pose_terms.h): the couple, held in the world, and under full within the cap the
// couple's tangent k J_l^-T(phi) as its step stiffness instead of k 1 (their Newton step).
#pragma once

#include <vector>

#include "physik/engine/force_stages.h"
#include "physik/engine/state.h"
#include "physik/model/scene.h"

namespace physik {

// phi = log(target q^-1): the turn (world axes, rad, |phi| <= pi) from q to target.
Vec3 orientation_error(const Quat& q, const Quat& target);

// The force stage: every orientation target's torque on its bone (state.torque_world).
void apply_orientation_springs(const Scene& scene, SimState& state);
// U of the state's orientation springs, J.
double orientation_springs_potential(const Scene& scene, const SimState& state);
// The implicit step: -h K w into the bone's torque (rate); h^2 K into its articulated inertia's
// angular block (augment).
void orientation_springs_rate(const Scene& scene, const ImplicitStage& stage, SimState& state);
void orientation_springs_augment(const Scene& scene, const ImplicitStage& stage, SimState& state);
// Damping auto: a couple per target, the tangent at the state's pose.
void orientation_springs_mode_stiffness(const Scene& scene, const SimState& state,
                                        const std::vector<Vec3>& targets, ModeStiffness& out);
// The pose-terms step: each target's couple.
void orientation_springs_pose_forces(const Scene& scene, const SimState& state, PoseForces& out);

}  // namespace physik
