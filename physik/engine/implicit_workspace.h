// The implicit scheme's workspace (implicit_step.h, implicit_pose_terms.h, implicit_advance.h),
// owned by the state (SimState::implicit): this step's element tangents, the pose terms' buffers,
// the energy guard's snapshots and what a run counts of them. The tangents are also read by
// damping auto (mode_operators.h), whatever the scheme. Arrays per bone in DFS order, world axes
// unless named otherwise. Units: N, N m, rig units, s, rad.
#pragma once

#include <cstddef>
#include <vector>

#include "physik/engine/articulated_body.h"
#include "physik/engine/contact_data.h"
#include "physik/model/scene.h"

namespace physik {

// The joint-space state at the start of an implicit (sub)step, to undo it (implicit_advance.h).
struct JointStateSnapshot {
  Vec3 root_com_world = Vec3::Zero();
  Vec3 root_vel_world = Vec3::Zero();
  Quat root_orient_world = Quat::Identity();
  std::vector<Vec3> joint_vel_local;      // (nbone)
  std::vector<Vec2> hinge_angle;          // (nbone)
  std::vector<Quat> bone_local_rotation;  // (nbone)
  std::vector<FrictionAnchor>
      friction_anchors;  // the contacts' static friction (ground_contacts.h)
};

struct ImplicitWorkspace {
  // --- the step's linearisation (implicit_step.h) ---
  std::vector<Vec6> accel_bias;           // (nbone) velocity-product spatial accelerations a0_i
                                          //   (qacc = 0) about o_i, (rad/s^2; rig units/s^2)
  std::vector<Mat3> control_stiffness;    // (ncontrol) K_c this step (spring_step_stiffness), N/m
  std::vector<Vec3> torsion_stiffness;    // (nbone) per rest axis this step
                                          //   (torsion_step_stiffness_local), N m/rad
  std::vector<Mat3> torsion_block_world;  // (nbone) the torsion block K_j this step, world axes,
                                          //   N m/rad (implicit_step.h torsion_block_world)
  // implicit_linearisation full (implicit_pose_terms.h): the rest solve, the rest wrench per
  // body about its point o_i, then the subtree's transmitted wrench (N m; N), the torsion
  // torques (world, N m) and the pose terms' rate z(v)
  ArticulatedBodyData articulated_rest;
  std::vector<Vec6> rest_wrench;                          // (nbone)
  std::vector<Vec3> torsion_torque_world;                 // (nbone)
  std::vector<Vec6> pose_rate;                            // (nbone)
  std::vector<Vec3> step_force_world, step_torque_world;  // (nbone) the forces, kept for a
                                                          //   Gauss-Newton retake, N; N m

  // --- the energy guard (implicit_advance.h) ---
  std::vector<JointStateSnapshot> snapshots;  // (implicit_max_splits + 1) one per halving depth;
                                              //   none unless the scheme is implicit
  int gauss_newton_steps = 0;                 // full steps taken as gauss-newton (implicit_step.h)
  int split_steps = 0;                        // steps the energy guard split (implicit_advance.h)
  int max_substeps = 0;                       // the most substeps one step took
  int retaken_steps = 0;                      // (sub)steps retaken with the contacts they reached
  int unresolved_steps = 0;  // (sub)steps kept where halving did not help (implicit_advance.h)
  int deepest_steps = 0;     // steps with substeps taken unchecked (max depth or max checks)
};

// A snapshot sized for `nbone` bones, with room for `anchor_capacity` friction anchors.
void size_joint_snapshot(int nbone, std::size_t anchor_capacity, JointStateSnapshot& snapshot);

// Size every buffer for a scene, zeroed, the counts at 0 (size_state, state.h): the snapshots
// only for scheme implicit, each with room for `anchor_capacity` friction anchors (the contact
// data's, contact_data.h prepare_contact_data), so that a step allocates nothing.
void size_implicit(const Scene& scene, std::size_t anchor_capacity, ImplicitWorkspace& ws);

}  // namespace physik
