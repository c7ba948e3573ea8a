// Every force of a PhysIK step, in one place: the engine's step() and the MuJoCo reference
// (reference/mujoco_runner.cpp) both call apply_forces(), so a new force lands in both.
//
// Stages, in order, on the state as it stands (positions, velocities and state.pose in sync):
//   prepare_bodies        clear force/torque accumulators, refresh I^-1 (world), w x I w
//   newton_euler.h apply_damping         -c v at head and tail of every bone damping.h
//   apply_control_springs linear or capped springs toward the effective targets control_springs.h
//   apply_torsion_springs joint-limit springs, +tau on the bone, -tau on its parent
//                         (torsion_springs.h)
//   apply_gravity         m g at every centre of mass (nothing when gravity is zero)  contacts.h
//   apply_contacts        the ground's and self-collision's penalty springs, dampers and
//                         friction at the contacts found at this state                 contacts.h
// Result: state.force_world (N, at the centre of mass) and state.torque_world (N m, about it),
// world axes, per bone. The inter-joint forces are not among them: they are the joint solve's.
#pragma once

#include "physik/engine/state.h"
#include "physik/model/scene.h"

namespace physik {

struct ForceSelection {
  bool torsion_springs = true;  // false where joint limits are enforced otherwise (MuJoCo's own
                                // limits in the exact-constraints reference mode)
  bool gravity = true;          // false where gravity is applied otherwise (MuJoCo's own)
  bool contacts = true;         // false where contacts are resolved otherwise (MuJoCo's own)
  double step = 0.0;            // s, the step the forces are taken over (0: params.dt); it caps a
                                // self-contact's damper and friction (contacts.h)
};

void apply_forces(const Scene& scene, SimState& state, const ForceSelection& selection = {});

}  // namespace physik
