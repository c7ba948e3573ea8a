// The joint-space state of the exact and implicit schemes (integrate_joint_space.h,
// implicit_step.h), owned by the state (SimState::joint_space): MuJoCo's qpos/qvel of the
// rig's joint model (rig.h "Locked axes"), the root's free joint and per bone its joint's
// velocity coordinates, with the articulated-body algorithm's workspace. Every ball's quaternion
// is the state's pose.bone_local_rotation[i]; a hinge's or universal's angles are hinge_angle[i]
// and its pose entry is derived from them (joint_coordinates.h); the world view (frames, com,
// vel, omega) is derived from these after every step. Units: rig units, s, rad.
#pragma once

#include <vector>

#include "physik/engine/articulated_body.h"
#include "physik/model/rig.h"

namespace physik {

struct JointSpaceState {
  Vec3 root_com_world = Vec3::Zero();         // rig units
  Vec3 root_vel_world = Vec3::Zero();         // rig units/s, of the root's centre of mass
  Quat root_orient_world = Quat::Identity();  // world<-root bone
  std::vector<Vec3> joint_vel_local;          // (nbone) rad/s; [0] the root's w in its own frame,
                                              //   [i] R_i^T (w_i - w_parent), in bone i's frame;
                                              //   a hinge's or universal's (t0', t1', 0) (a
                                              //   pinned root's too), a weld's 0
  std::vector<Vec2> hinge_angle;              // (nbone) rad; a hinge's or universal's (t0, t1),
                                              //   MuJoCo's hinge qpos; 0 for other joints
  ArticulatedBodyData articulated;            // the articulated-body algorithm's workspace
};

// Size every buffer for a rig, zeroed, the root at rest at the origin (size_state, state.h).
void size_joint_space(const Rig& rig, JointSpaceState& js);

}  // namespace physik
