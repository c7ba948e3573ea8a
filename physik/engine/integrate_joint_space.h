// The exact explicit step (docs/engine.md "The exact scheme"):
// PhysIK's forces into the articulated-body algorithm (articulated_body.h), then MuJoCo 2.2.2's
// Euler step in joint space, so the run equals MuJoCo's same-forces run
// (reference/mujoco_runner.h) to round-off.
//
// Forces. The force stages' force_world/torque_world (about each centre of mass, world axes) go in
// unchanged, plus, per body, exactly as the MuJoCo reference applies them:
//   the angular-velocity factor f as the torque  I_world (f - 1) w / dt
//   (gyroscopic off) +w x I w, cancelling the exact dynamics' own gyroscopic term.
// Every other velocity product (gyroscopic, Coriolis, centripetal) is the exact dynamics' own.
//
// Integration (MuJoCo 2.2.2, engine_forward.c mj_Euler -> mj_advance; engine_support.c
// mj_integratePos; engine_util_spatial.c mju_quatIntegrate), with h = dt:
//   qvel <- qvel + h qacc                                 (no dof damping in the model)
//   root:  com <- com + h v_com                           (the new velocity)
//          q_root <- normalize(q_root * exp(h w_local))  (quaternion turned by its LOCAL w)
//   ball:  q_i <- normalize(q_i * exp(h u_i))
// where exp(h w) = (cos(h|w|/2), sin(h|w|/2) w/|w|) (identity when h|w| = 0).
// Then the world view is rebuilt from the joint state (as mj_kinematics and mj_comVel do):
//   R_0 = q_root,  R_i = R_p R_rest_in_parent_i q_i,  head_i = head_p + R_p h_i,
//   com_i = head_i + R_i (0, L/2, 0),  w_0 = R_0 u_0,  w_i = w_p + R_i u_i,
//   v_com_i = v_com_p + w_p x (head_i - com_p) + w_i x (com_i - head_i)
// and the Pose (s.pose) IS the ball state: it is not recomputed from the frames.
// Units: s, rig units, rad.
#pragma once

#include "physik/engine/joint_forces.h"
#include "physik/engine/state.h"
#include "physik/model/params.h"
#include "physik/model/rig.h"

namespace physik {

// Take the joint-space state from the world view (frames, com, vel, omega): root from bone 0,
// u_i = R_i^T (w_i - w_parent). The balls are s.pose's rotations. The buffers are sized by
// size_state (state.h).
void init_joint_space(const Rig& rig, SimState& state);

// The exact joint solve: the external wrench (force stages + the factor torque) into the
// articulated-body algorithm; state.joint_space.articulated then holds the joint accelerations.
// Also fills joint_force_world/joint_torque_world with the inter-joint forces this implies
// (m a - F, I alpha + w x I w - tau). force_world/torque_world are left as the force stages made
// them.
JointSolveStats solve_articulated(const Rig& rig, const EngineParams& params, SimState& state);

// joint_force_world/joint_torque_world from state.joint_space.articulated's accelerations: m a - F
// and I alpha + w x I w - tau (the implicit step's element forces of the step count among them)
void articulated_joint_forces(const Rig& rig, SimState& state);

// MuJoCo's Euler step of length h (s) of the joint state with state.joint_space.articulated's
// accelerations, then the world view (frames, com, vel, omega, the root's pose entry).
void integrate_joint_space(const Rig& rig, double h, SimState& state);

// The world view from the joint state alone.
void world_from_joint_space(const Rig& rig, SimState& state);

// mju_quatIntegrate: q <- normalize(q * exp(h w_local)).
void quat_integrate(Quat& q, const Vec3& omega_local, double h);

}  // namespace physik
