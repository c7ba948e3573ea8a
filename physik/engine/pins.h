// Pins (scene.h Pin): a point a = head + alpha (tail - head) of a bone held at a world point p by
// a stiff linear spring, F = k (p - a), in every scheme; F in N, k in N/m, distances in rig
// units. A pin is a spring and not a constraint: the paper's scheme and the exact scheme's
// recursion hold joints only (a pin would close a loop through the world, which the articulated
// body recursion does not solve), and a spring is one law in every scheme, the MuJoCo reference
// included. It holds a bone within |F_other| / k of p under the other forces F_other; the
// implicit scheme takes it at any dt (its step stiffness h^2 k enters the recursion), the
// explicit schemes for dt below 2 sqrt(m / k) (m the pinned body's mass), as any spring.
//
// Potential U = k |p - a|^2 / 2, J. Implicit step (implicit_step.h): a point element at a,
// A = h^2 k 1, and -h k v_a on the right-hand side (the control springs' linear law,
// control_springs.h). Damping auto's modes: a point element k 1 at a. MuJoCo's reference applies
// the same force. The pose-terms step (implicit_linearisation full, implicit_pose_terms.h): the
// force at a, held in the world.
#pragma once

#include <vector>

#include "physik/engine/force_stages.h"
#include "physik/engine/state.h"
#include "physik/model/scene.h"

namespace physik {

// The force stage: every pin's force at its point (state.force_world, state.torque_world).
void apply_pins(const Scene& scene, SimState& state);
// U of the state's pins, J.
double pins_potential(const Scene& scene, const SimState& state);
// The implicit step: -h k v_a at each point (rate); h^2 k 1 into the bone's articulated inertia
// (augment).
void pins_rate(const Scene& scene, const ImplicitStage& stage, SimState& state);
void pins_augment(const Scene& scene, const ImplicitStage& stage, SimState& state);
// Damping auto: a point element k 1 at each pin's point.
void pins_mode_stiffness(const Scene& scene, const SimState& state,
                         const std::vector<Vec3>& targets, ModeStiffness& out);
// The pose-terms step: each pin's force at its point.
void pins_pose_forces(const Scene& scene, const SimState& state, PoseForces& out);

}  // namespace physik
