// The simulation state (the data half of the model/data split): everything a step reads and
// writes, allocated once for a rig. Arrays are per bone (nbone) in DFS order, world frame.
#pragma once

#include <vector>

#include "physik/engine/articulated_body.h"
#include "physik/engine/contact_data.h"
#include "physik/engine/gauss_seidel_workspace.h"
#include "physik/engine/implicit_workspace.h"
#include "physik/engine/joint_space_state.h"
#include "physik/engine/mode_workspace.h"
#include "physik/model/kinematics.h"
#include "physik/model/scene.h"

namespace physik {

struct SimState {
  // --- configuration and velocity (integrated) ---
  BoneFrames frames;              // head/tail/orientation, world, rig units
  std::vector<Vec3> com_world;    // (nbone) centre of mass = midpoint, rig units
  std::vector<Vec3> vel_world;    // (nbone) centre-of-mass velocity, rig units/s
  std::vector<Vec3> omega_world;  // (nbone) angular velocity, rad/s

  // --- per-step accumulators ---
  std::vector<Vec3> force_world;         // (nbone) net force, N
  std::vector<Vec3> torque_world;        // (nbone) net torque about the centre of mass, N m
  std::vector<Vec3> joint_force_world;   // (nbone) inter-joint forces only (for checks)
  std::vector<Vec3> joint_torque_world;  // (nbone) their torque about the centre of mass

  // --- per-step geometry caches (fixed during the joint passes) ---
  std::vector<Mat3> inertia_inv_world;  // (nbone) I^-1 in world axes, 1/(kg m^2)
  std::vector<Vec3> gyro_world;         // (nbone) w x I w, N m (0 when gyroscopic is off)

  // --- each scheme's workspace, sized by size_state ---
  GaussSeidelWorkspace gauss_seidel;  // joint solve and welded bodies (gauss_seidel_workspace.h)
  JointSpaceState joint_space;        // exact and implicit: qpos/qvel, the recursion's buffers
                                      //   (joint_space_state.h)
  ImplicitWorkspace implicit;         // tangents, pose terms, energy guard (implicit_workspace.h)

  // --- contacts: what the force stage found and carries (contact_data.h) ---
  ContactData contact;

  // --- damping_auto (linear_modes.h) ---
  double damping_auto_value = 0.0;  // N s/m, the damping chosen at the last target change
  int damping_auto_updates = 0;     // how many times it was chosen this run
  ModeWorkspace modes;              // the linear modes' buffers, sized at the first update

  // --- control points ---
  std::vector<Vec3> target_effective_world;  // (ncontrol) the target the spring pulls toward now
  std::vector<Vec3> target_goal_world;       // (ncontrol) where the target is heading
  std::vector<int> interp_steps_left;        // (ncontrol) steps of interpolation remaining
  std::vector<Vec3> control_force_world;     // (ncontrol) last spring force, N

  // --- bookkeeping ---
  int step = 0;       // steps taken
  double time = 0.0;  // s
  Pose pose;          // local rotations of `frames` (torsion, limits, output); init_state
                      // and step() keep it in sync: code that edits frames must refresh it
                      // (local_rotations_from_world)
};

// The recursion's view of a state (articulated_body.h).
inline BodyMotion body_motion(const SimState& s) {
  return {s.frames, s.com_world, s.vel_world, s.omega_world, s.force_world, s.torque_world};
}

// Size every buffer for a scene (its rig, control points, contacts and scheme), zeroed, at
// step 0: the state's own, the contact data (prepare_contact_data) and each workspace through
// its one sizing function. init_state (engine.h) then puts the scene's initial pose, velocities
// and targets in.
void size_state(const Scene& scene, SimState& state);

}  // namespace physik
