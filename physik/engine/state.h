// The simulation state (the data half of the model/data split): everything a step reads and
// writes, allocated once for a rig. Arrays are per bone (nbone) in DFS order, world frame.
#pragma once

#include <vector>

#include "physik/engine/articulated_body.h"
#include "physik/engine/contact_data.h"
#include "physik/engine/mode_workspace.h"
#include "physik/model/kinematics.h"
#include "physik/model/scene.h"

namespace physik {

// The joint-space state at the start of an implicit (sub)step, to undo it (implicit_advance.h).
struct JointStateSnapshot {
  Vec3 root_com_world = Vec3::Zero();
  Vec3 root_vel_world = Vec3::Zero();
  Quat root_orient_world = Quat::Identity();
  std::vector<Vec3> joint_vel_local;      // (nbone)
  std::vector<Quat> bone_local_rotation;  // (nbone)
  std::vector<FrictionAnchor>
      friction_anchors;  // the contacts' static friction (ground_contacts.h)
};

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

  // --- the gauss-seidel scheme's rigid bodies where bones are welded (rig.h "Welds"; sized only
  // for a rig with welds): per body, at its first bone's index; a body of one bone copies it ---
  std::vector<double> body_mass;             // (nbone) kg
  std::vector<Vec3> body_com_world;          // (nbone) rig units
  std::vector<Vec3> body_force_world;        // (nbone) N, at the body's centre of mass
  std::vector<Vec3> body_torque_world;       // (nbone) N m, about it
  std::vector<Mat3> body_inertia_inv_world;  // (nbone) 1/(kg m^2)
  std::vector<Vec3> body_gyro_world;         // (nbone) w x I w, N m
  std::vector<Vec3> body_vel_world;          // (nbone) free rods: its centre's new velocity

  // --- joint solve workspace, per joint member (Rig::joint_member_bone, ...) ---
  std::vector<Vec3> member_r_world;      // (nmember) joint point minus centre of mass
  std::vector<Mat3> member_Minv;         // (nmember) inverse of M_i = m^-1 I + [r]x^T I^-1 [r]x
  std::vector<Mat3> joint_Sinv;          // (njoint) (sum_i M_i^-1)^-1
  std::vector<Vec3> member_accel;        // (nmember) scratch: joint-point accelerations
  std::vector<Vec3> member_force_world;  // (nmember) inter-joint force on that bone at the
                                         //           joint this step, N (sums to 0 per joint)

  // --- joint-space state (scheme exact): MuJoCo's qpos/qvel of the ball-joint model ---
  // the root's free joint, and per bone the ball's relative angular velocity; every ball's
  // quaternion is pose.bone_local_rotation[i]. frames, com, vel and omega are derived from these
  // after every step (integrate_joint_space.h).
  Vec3 root_com_world = Vec3::Zero();         // rig units
  Vec3 root_vel_world = Vec3::Zero();         // rig units/s, of the root's centre of mass
  Quat root_orient_world = Quat::Identity();  // world<-root bone
  std::vector<Vec3> joint_vel_local;          // (nbone) rad/s; [0] the root's w in its own frame,
                                              //   [i] R_i^T (w_i - w_parent), in bone i's frame
  ArticulatedBodyData articulated;            // the articulated-body algorithm's workspace

  // --- implicit step workspace (scheme implicit, implicit_step.h) ---
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
  std::vector<JointStateSnapshot>
      implicit_snapshots;               // (implicit_max_splits + 1) the energy guard's
  int implicit_gauss_newton_steps = 0;  // full steps taken as gauss-newton (implicit_step.h)
  int implicit_split_steps = 0;         // steps the energy guard split (implicit_advance.h)
  int implicit_max_substeps = 0;        // the most substeps one step took
  int implicit_retaken_steps = 0;       // (sub)steps retaken with the contacts they reached
  int implicit_unresolved_steps = 0;    // (sub)steps kept where halving did not lower the energy
  int implicit_deepest_steps = 0;       // steps split to implicit_max_splits (taken unchecked)

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

// Size every buffer for a rig and `ncontrol` control points, zeroed, at step 0. init_state
// (engine.h) then puts the scene's initial pose, velocities and targets in.
void size_state(const Rig& rig, std::size_t ncontrol, SimState& state);

}  // namespace physik
