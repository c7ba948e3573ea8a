#include "physik/engine/integrate_joint_space.h"

#include <cmath>

#include "physik/model/joint_coordinates.h"

namespace physik {

void quat_integrate(Quat& q, const Vec3& w, double h) {
  constexpr double kMinVal = 1e-15;  // MuJoCo's mjMINVAL
  const double norm = w.norm();
  const Vec3 axis = norm < kMinVal ? Vec3(1, 0, 0) : Vec3(w * (1.0 / norm));
  const double angle = h * norm;
  Quat rot = Quat::Identity();
  if (angle != 0.0) {
    const double s = std::sin(0.5 * angle);
    rot = Quat(std::cos(0.5 * angle), axis.x() * s, axis.y() * s, axis.z() * s);
  }
  Quat out = q * rot;
  const double n = out.norm();
  q = n < kMinVal ? Quat::Identity() : Quat(out.coeffs() * (1.0 / n));
}

namespace {

inline bool hinged(JointType type) {
  return type == JointType::kHinge || type == JointType::kUniversal;
}

inline Quat parent_orient(const Rig& rig, const BoneFrames& f, int i) {
  const int p = rig.bone_parent[i];
  return p < 0 ? Quat::Identity() : f.orient_world[p];
}

// w_i - w_parent of a hinge or universal, world: s0 t0' + s1 t1' (joint_coordinates.h)
inline Vec3 hinge_rate_world(const Rig& rig, int i, const Quat& parent_orient_world,
                             const Quat& orient_world, const Vec3& rate) {
  Vec3 s0, s1;
  hinge_axes_world(rig, i, parent_orient_world, orient_world, s0, s1);
  return s0 * rate[0] + s1 * rate[1];
}

// a joint with locked axes removed (rig.h "Locked axes"): its coordinates from the pose's rotation
// and the world view's relative turn, and the pose's rotation put on the joint's set (a weld by
// locks at L)
void project_joint(const Rig& rig, SimState& s, int i) {
  JointSpaceState& js = s.joint_space;
  Quat& q = s.pose.bone_local_rotation[i];
  js.joint_vel_local[i].setZero();
  js.hinge_angle[i].setZero();
  if (rig.bone_joint_type[i] == JointType::kWeld) {
    q = hinge_rotation(rig, i, Vec2::Zero());
  } else {
    const int p = rig.bone_parent[i];
    const Vec3 w_rel = s.omega_world[i] - (p < 0 ? Vec3::Zero() : s.omega_world[p]);
    Vec3 s0, s1;
    hinge_axes_world(rig, i, parent_orient(rig, s.frames, i), s.frames.orient_world[i], s0, s1);
    js.joint_vel_local[i] << s0.dot(w_rel), s1.dot(w_rel), 0.0;
    js.hinge_angle[i] = hinge_coordinates(rig, i, q);
    q = hinge_rotation(rig, i, js.hinge_angle[i]);
  }
  if (i == 0) js.root_orient_world = (rig.bone_rest_orient_parent[0] * q).normalized();
}

// a joint whose locked axes are removed and that is not welded by the rig (a weld to a bone, a
// fixed root): a hinge, a universal joint or a weld by locks
inline bool locks_removed(const Rig& rig, int i) {
  const JointType t = rig.bone_joint_type[i];
  if (hinged(t)) return true;
  return t == JointType::kWeld && rig.bone_weld[i] < 0 &&
         !(i == 0 && rig.root_joint == RootJoint::kFixed);
}

}  // namespace

void init_joint_space(const Rig& rig, SimState& s) {
  const int n = rig.nbone;
  JointSpaceState& js = s.joint_space;
  if (n == 0) return;
  js.root_com_world = s.com_world[0];
  js.root_vel_world = s.vel_world[0];
  js.root_orient_world = s.frames.orient_world[0];
  const bool locked = rig.has_locked_joints();
  for (int i = 0; i < n; ++i) {
    if (locked && locks_removed(rig, i)) {
      project_joint(rig, s, i);
      continue;
    }
    if (rig.bone_joint_type[i] == JointType::kWeld) {  // no joint velocity
      js.joint_vel_local[i].setZero();
      continue;
    }
    const int p = rig.bone_joint_parent[i];
    const Vec3 w_rel = s.omega_world[i] - (p < 0 ? Vec3::Zero() : s.omega_world[p]);
    js.joint_vel_local[i] = s.frames.orient_world[i].conjugate() * w_rel;
  }
  // the pose was put on the joints' sets: the world view follows it
  if (locked) world_from_joint_space(rig, s);
}

void articulated_joint_forces(const Rig& rig, SimState& s) {
  const ArticulatedBodyData& d = s.joint_space.articulated;
  // what the bodies feel beyond the external wrench
  for (int i = 0; i < rig.nbone; ++i) {
    const Vec3 e = s.com_world[i] - d.point_world[i];
    const Vec3 alpha = d.accel_spatial[i].head<3>();
    const Vec3& w = s.omega_world[i];
    const Vec3 a_com = d.accel_spatial[i].tail<3>() + alpha.cross(e) + w.cross(s.vel_world[i]);
    const Mat3& I = d.inertia_com_world[i];
    s.joint_force_world[i] = rig.bone_mass[i] * a_com - s.force_world[i];
    s.joint_torque_world[i] = I * alpha + w.cross(I * w) - d.torque_ext_world[i];
  }
}

JointSolveStats solve_articulated(const Rig& rig, const EngineParams& params, SimState& s) {
  ArticulatedBodyData& d = s.joint_space.articulated;
  d.torque_per_omega = (params.angular_velocity_factor - 1.0) / params.dt;
  d.cancel_gyroscopic = !params.gyroscopic;
  articulated_accelerations(rig, body_motion(s), d);

  articulated_joint_forces(rig, s);
  JointSolveStats stats;
  stats.passes = 1;  // one sweep of the recursion, no iteration
  stats.mismatch = 0.0;
  return stats;
}

namespace {

// bone i's world view from its joint state and its parent's (already derived) world view
inline void derive_body(const Rig& rig, SimState& s, int i) {
  JointSpaceState& js = s.joint_space;
  BoneFrames& f = s.frames;
  const int p = rig.bone_parent[i];
  const double half_length = 0.5 * rig.bone_length[i];
  if (p < 0) {
    f.orient_world[i] = js.root_orient_world.normalized();
    const Mat3 R = f.orient_world[i].toRotationMatrix();
    const Vec3 half = half_length * R.col(1);  // R (0, L/2, 0)
    s.omega_world[i] =
        hinged(rig.bone_joint_type[i])
            ? hinge_rate_world(rig, i, Quat::Identity(), f.orient_world[i], js.joint_vel_local[i])
            : Vec3(R * js.joint_vel_local[i]);
    if (rig.root_anchored()) {
      // the head stays at its rest position; the centre turns about it
      f.head_world[i] = rig.bone_rest_head_world[i];
      js.root_com_world = f.head_world[i] + half;
      js.root_vel_world = s.omega_world[i].cross(half);
    } else {
      f.head_world[i] = js.root_com_world - half;
    }
    s.com_world[i] = js.root_com_world;
    f.tail_world[i] = js.root_com_world + half;
    s.vel_world[i] = js.root_vel_world;
    return;
  }
  // as mj_kinematics: the ball's quaternion normalised, the products not
  const Quat& q_parent = f.orient_world[p];
  const int w = rig.bone_weld[i];
  if (w >= 0) {
    // a weld turns with the bone it is welded to
    f.orient_world[i] = f.orient_world[w] * rig.bone_rest_orient_weld[i];
    s.omega_world[i] = s.omega_world[w];
  } else {
    f.orient_world[i] =
        q_parent * rig.bone_rest_orient_parent[i] * s.pose.bone_local_rotation[i].normalized();
  }
  const Mat3 R = f.orient_world[i].toRotationMatrix();
  f.head_world[i] = f.head_world[p] + q_parent * rig.bone_head_in_parent[i];
  const Vec3 half = half_length * R.col(1);
  s.com_world[i] = f.head_world[i] + half;
  f.tail_world[i] = s.com_world[i] + half;
  if (w < 0) {
    s.omega_world[i] =
        s.omega_world[p] +
        (hinged(rig.bone_joint_type[i])
             ? hinge_rate_world(rig, i, q_parent, f.orient_world[i], js.joint_vel_local[i])
             : Vec3(R * js.joint_vel_local[i]));
  }
  s.vel_world[i] = s.vel_world[p] + s.omega_world[p].cross(f.head_world[i] - s.com_world[p]) +
                   s.omega_world[i].cross(half);
}

// the pose's local rotations follow the world view: the root's (R_0 = R_rest q_0), and a welded
// bone's, which the step does not integrate
void pose_from_derived(const Rig& rig, SimState& s) {
  s.pose.root_head_world = s.frames.head_world[0];
  s.pose.bone_local_rotation[0] =
      (rig.bone_rest_orient_parent[0].conjugate() * s.frames.orient_world[0]).normalized();
  welded_local_rotations(rig, s.frames, s.pose);
}

// a hinge's or universal's angles as MuJoCo's hinge qpos (mj_advance, mj_integratePos): the
// rates first, then the angles with the new rates; the pose's rotation q(t) (joint_coordinates.h)
inline void integrate_hinge(const Rig& rig, double h, SimState& s, int i) {
  JointSpaceState& js = s.joint_space;
  js.joint_vel_local[i].head<2>() += h * js.articulated.joint_accel_local[i].head<2>();
  js.hinge_angle[i] += h * js.joint_vel_local[i].head<2>();
  s.pose.bone_local_rotation[i] = hinge_rotation(rig, i, js.hinge_angle[i]);
}

}  // namespace

void integrate_joint_space(const Rig& rig, double h, SimState& s) {
  JointSpaceState& js = s.joint_space;
  const ArticulatedBodyData& d = js.articulated;
  if (rig.nbone == 0) return;
  // per joint: velocity first (mj_advance), then position with the new velocity
  // (mj_integratePos); joints are independent, so one pass, parents first, also rebuilds the
  // world view. An anchored root's centre follows its turn (derive_body); a fixed one's and a
  // weld's coordinates stay zero.
  switch (rig.bone_joint_type[0]) {
    case JointType::kFree:
      js.root_vel_world += h * d.root_accel_world;
      js.joint_vel_local[0] += h * d.joint_accel_local[0];
      js.root_com_world += h * js.root_vel_world;
      quat_integrate(js.root_orient_world, js.joint_vel_local[0], h);
      break;
    case JointType::kBall:
      js.joint_vel_local[0] += h * d.joint_accel_local[0];
      quat_integrate(js.root_orient_world, js.joint_vel_local[0], h);
      break;
    case JointType::kHinge:
    case JointType::kUniversal:
      integrate_hinge(rig, h, s, 0);
      js.root_orient_world = rig.bone_rest_orient_parent[0] * s.pose.bone_local_rotation[0];
      break;
    case JointType::kWeld:
      break;
  }
  derive_body(rig, s, 0);
  for (int i = 1; i < rig.nbone; ++i) {
    const JointType type = rig.bone_joint_type[i];
    if (type == JointType::kBall) {
      js.joint_vel_local[i] += h * d.joint_accel_local[i];
      quat_integrate(s.pose.bone_local_rotation[i], js.joint_vel_local[i], h);
    } else if (hinged(type)) {
      integrate_hinge(rig, h, s, i);
    }
    derive_body(rig, s, i);
  }
  pose_from_derived(rig, s);
}

void world_from_joint_space(const Rig& rig, SimState& s) {
  for (int i = 0; i < rig.nbone; ++i) derive_body(rig, s, i);
  if (rig.nbone > 0) pose_from_derived(rig, s);
}

}  // namespace physik
