// Aim (look-at) targets (scene.h AimTarget): a bone's axis u = R u_bone turned toward a point p
// from the bone's head a. With d = (p - a) / L, L = |p - a|, the angle theta = angle(u, d) and
// n = u x d / |u x d|, the law is the control springs' (control_springs.h) on the turn theta n
// that lays u onto d:
//   linear         tau = k theta n
//   capped-linear  tau = k min(theta, c) n           (|tau| <= k c)
// a couple on the bone, and with it a force at the head, F = -(|tau| / L) w, w = (u - (u.d) d)
// / sin(theta) (the unit vector across d toward u): the aim's pull as the head moves. tau in N m,
// F in N, k in N m/rad, c in rad, L in rig units.
//
// Potential U(theta): linear k theta^2 / 2; capped k theta^2 / 2 (theta <= c), k c (theta - c/2)
// (theta > c). Turning the bone by dr (world axes) turns u by dr x u, so d theta = -n . dr; moving
// the head by da turns d by -(1 - d d^T) da / L, so d theta = w . da / L: tau and F are minus U's
// gradient, and the aim conserves energy as the other springs do. At theta = 0 both vanish; at
// theta = pi (u opposite d) n is any unit vector across u: the one across u nearest the world's x.
//
// Implicit step (implicit_step.h): a couple K_r = k (1 - u u^T) (the secant k c / theta beyond
// the cap) and a point element at the head K_a = (k / L^2) (1 - d d^T), the two diagonal blocks of
// U's Hessian in (turn, head) at theta = 0 without their coupling. The turn's block bounds its
// Hessian above (curvature 1 along n, theta cot theta across u and n, 0 about u). Damping auto's
// modes: the same couple and point. MuJoCo's reference applies the same couple and force. The
// pose-terms step (implicit_linearisation full, implicit_pose_terms.h): the couple and the head's
// force, held in the world; under full the step stiffness is U's whole Hessian in (turn, head),
// its tangent, coupling included (aim_springs.cpp), where it exists (the linear law or within the
// cap, u not within 2.6 degrees of opposite d; elsewhere the bound above).
#pragma once

#include <vector>

#include "physik/engine/force_stages.h"
#include "physik/engine/state.h"
#include "physik/model/scene.h"

namespace physik {

// One aim at the state's pose: its turn (theta n, rad, world axes), the bone's axis u and the
// unit direction d from the head to the point (world), and the head's distance L (rig units).
struct AimTurn {
  Vec3 turn = Vec3::Zero();
  Vec3 axis_world = Vec3::UnitY();
  Vec3 direction_world = Vec3::UnitY();
  double distance = 0.0;
};
AimTurn aim_turn(const BoneFrames& frames, const AimTarget& target);

// The force stage: every aim's couple and head force (state.force_world, state.torque_world).
void apply_aim_springs(const Scene& scene, SimState& state);
// U of the state's aims, J.
double aim_springs_potential(const Scene& scene, const SimState& state);
// The implicit step: -h K v of the couple and of the head's point (rate); h^2 K into the bone's
// articulated inertia (augment).
void aim_springs_rate(const Scene& scene, const ImplicitStage& stage, SimState& state);
void aim_springs_augment(const Scene& scene, const ImplicitStage& stage, SimState& state);
// Damping auto: the couple and the head's point element at the state's pose.
void aim_springs_mode_stiffness(const Scene& scene, const SimState& state,
                                const std::vector<Vec3>& targets, ModeStiffness& out);
// The pose-terms step: each aim's couple and its head's force.
void aim_springs_pose_forces(const Scene& scene, const SimState& state, PoseForces& out);

}  // namespace physik
