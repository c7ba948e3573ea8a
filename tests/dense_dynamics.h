// Dense joint-space dynamics for the tests, assembled independently of the articulated-body
// recursion: random trees, body and point Jacobians (MuJoCo's qvel layout of the rig's joint
// model, rig.h "Locked axes": root v_com world, root w local, ball u local, a hinge's or
// universal's angle rates about their world axes, a weld none), M = sum_b J_b^T diag(I_b, m_b)
// J_b, and tau - C from a classical Newton-Euler recursion of the velocity-product accelerations.
// (The helpers of tests/articulated_body_test.cpp, shared with tests/implicit_step_test.cpp.)
#pragma once

#include <random>

#include <Eigen/Dense>

#include "physik/engine/integrate_joint_space.h"
#include "physik/engine/state.h"
#include "physik/model/joint_coordinates.h"

namespace physik::dense {

using MatX = Eigen::MatrixXd;
using VecX = Eigen::VectorXd;

struct RandomTree {
  Rig rig;
  SimState s;
};

inline Vec3 random_unit(std::mt19937& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  return Vec3(g(rng), g(rng), g(rng)).normalized();
}

// a random tree of n bones, each child's head at a random earlier bone's tail
inline Rig random_rig(std::mt19937& rng, int n) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<BoneSpec> specs(n);
  for (int i = 0; i < n; ++i) {
    BoneSpec& b = specs[i];
    b.name = "b" + std::to_string(i);
    if (i == 0) {
      b.head_world = Vec3(u(rng), u(rng), u(rng));
    } else {
      const int p = std::uniform_int_distribution<int>(0, i - 1)(rng);
      b.parent = specs[p].name;
      b.head_world = specs[p].tail_world;
    }
    b.tail_world = b.head_world + (0.3 + 1.7 * u(rng)) * random_unit(rng);
    b.rest_frame_world = rest_frame_from_roll(b.head_world, b.tail_world, 6.0 * u(rng));
    b.mass = 0.2 + 2.8 * u(rng);
    // principal moments that satisfy the triangle inequality: sums of two of three positives
    const Vec3 a(0.02 + u(rng), 0.02 + u(rng), 0.02 + u(rng));
    b.inertia_local = Vec3(a.y() + a.z(), a.x() + a.z(), a.x() + a.y()) * b.mass * 0.3;
  }
  return build_rig(specs, "<random>", "random");
}

// random_rig with limits on some axes of every joint but the root's (narrow enough that random
// poses violate them: engaged torsion springs)
inline Rig random_limited_rig(std::mt19937& rng, int n) {
  Rig rig = random_rig(rng, n);
  for (int i = 1; i < n; ++i) {
    for (int a = 0; a < 3; ++a) {
      if ((i + a) % 3 == 0) rig.bone_limit[i][a] = {true, -0.2, 0.1 + 0.1 * a};
    }
  }
  return rig;
}

// random_rig with locked axes: bone i > 0 a ball, a hinge, a universal joint or a weld by locks
// (i % 4), its free axes and lock values (0 or not) random
inline Rig random_hinged_rig(std::mt19937& rng, int n) {
  Rig rig = random_rig(rng, n);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_int_distribution<int> axis(0, 2);
  for (int i = 1; i < n; ++i) {
    const int locks = i % 4, first = axis(rng);
    for (int k = 0; k < locks; ++k) {
      const double v = (i + k) % 2 == 0 ? 0.0 : 0.6 * u(rng);
      rig.bone_limit[i][(first + k) % 3] = AxisLimit{true, v, v};
    }
  }
  refresh_joint_model(rig);
  return rig;
}

// random joint state (poses, velocities) and forces; the world view from the joint state
inline RandomTree random_tree(std::mt19937& rng, int n, bool moving, bool hinged = false) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  RandomTree t;
  t.rig = hinged ? random_hinged_rig(rng, n) : random_rig(rng, n);
  SimState& s = t.s;
  s.pose = rest_pose(t.rig);
  forward_kinematics(t.rig, s.pose, s.frames);
  s.com_world.assign(n, Vec3::Zero());
  s.vel_world.assign(n, Vec3::Zero());
  s.omega_world.assign(n, Vec3::Zero());
  s.force_world.assign(n, Vec3::Zero());
  s.torque_world.assign(n, Vec3::Zero());
  size_joint_space(t.rig, s.joint_space);
  init_joint_space(t.rig, s);
  const double speed = moving ? 2.0 : 0.0;
  for (int i = 1; i < n; ++i) {
    const JointType type = t.rig.bone_joint_type[i];
    if (type == JointType::kBall) {
      s.pose.bone_local_rotation[i] = Quat(Eigen::AngleAxisd(3.0 * u(rng), random_unit(rng)));
    } else {
      Vec2& angle = s.joint_space.hinge_angle[i];
      angle = type == JointType::kWeld ? Vec2::Zero() : Vec2(3.0 * u(rng), 1.4 * u(rng));
      if (type == JointType::kHinge) angle[1] = 0.0;
      s.pose.bone_local_rotation[i] = hinge_rotation(t.rig, i, angle);
    }
  }
  s.joint_space.root_com_world = 3.0 * Vec3(u(rng), u(rng), u(rng));
  s.joint_space.root_orient_world = Quat(Eigen::AngleAxisd(3.0 * u(rng), random_unit(rng)));
  s.joint_space.root_vel_world = speed * Vec3(u(rng), u(rng), u(rng));
  for (int i = 0; i < n; ++i) {
    const int k = rotational_coordinates(t.rig.bone_joint_type[i]);
    for (int c = 0; c < 3; ++c) s.joint_space.joint_vel_local[i][c] = c < k ? speed * u(rng) : 0.0;
  }
  world_from_joint_space(t.rig, s);
  for (int i = 0; i < n; ++i) {
    s.force_world[i] = 5.0 * Vec3(u(rng), u(rng), u(rng));
    s.torque_world[i] = 5.0 * Vec3(u(rng), u(rng), u(rng));
  }
  return t;
}

inline int nv(const Rig& rig) {
  return rig.nv;  // the random trees' roots are free: 6 + each joint's coordinates
}
// the first rotational coordinate of a bone's joint (after the free root's translation)
inline int dof(const Rig& rig, int bone) {
  return rig.bone_dofadr[bone] + (bone == 0 ? 3 : 0);
}
inline int coordinates(const Rig& rig, int bone) {
  return rotational_coordinates(rig.bone_joint_type[bone]);
}

// the world axes of bone j's rotational coordinates (columns): a ball's (the root's) local axes,
// a hinge's or universal's s0, s1 (joint_coordinates.h: s0 fixed in the parent, s1 in the bone)
inline Mat3 joint_axes(const Rig& rig, const SimState& s, int j) {
  if (coordinates(rig, j) == 3) return s.frames.orient_world[j].toRotationMatrix();
  const int p = rig.bone_parent[j];
  Vec3 s0, s1;
  hinge_axes_world(rig, j, p < 0 ? Quat::Identity() : s.frames.orient_world[p],
                   s.frames.orient_world[j], s0, s1);
  Mat3 out;
  out << s0, s1, Vec3::Zero();
  return out;
}

inline bool in_subtree(const Rig& rig, int bone, int root) {
  for (int b = bone; b >= 0; b = rig.bone_parent[b]) {
    if (b == root) return true;
  }
  return false;
}

// body b's Jacobians: w_b = Jw qdot, v_com_b = Jv qdot (MuJoCo's qvel: root v world, root w
// local, ball u local); each column is the motion of a unit rate about that dof's axis and point
inline void jacobians(const Rig& rig, const SimState& s, int b, MatX& Jw, MatX& Jv) {
  Jw.setZero(3, nv(rig));
  Jv.setZero(3, nv(rig));
  Jv.leftCols<3>().setIdentity();
  for (int j = 0; j < rig.nbone; ++j) {
    if (!in_subtree(rig, b, j)) continue;
    const Vec3 pivot = j == 0 ? s.com_world[0] : s.frames.head_world[j];
    const Mat3 axes = joint_axes(rig, s, j);
    for (int k = 0; k < coordinates(rig, j); ++k) {
      const Vec3 axis = axes.col(k);
      Jw.col(dof(rig, j) + k) = axis;
      Jv.col(dof(rig, j) + k) = axis.cross(s.com_world[b] - pivot);
    }
  }
}

// per-bone joint vectors (joint_vel_local, joint_accel_local: a joint's first `coordinates`
// entries) after the root's translation entries
inline void gather(const Rig& rig, const std::vector<Vec3>& per_bone, VecX& q) {
  for (int i = 0; i < rig.nbone; ++i) {
    for (int k = 0; k < coordinates(rig, i); ++k) q[dof(rig, i) + k] = per_bone[i][k];
  }
}

inline VecX qvel(const Rig& rig, const SimState& s) {
  VecX q(nv(rig));
  q.head<3>() = s.joint_space.root_vel_world;
  gather(rig, s.joint_space.joint_vel_local, q);
  return q;
}

inline Mat3 inertia(const Rig& rig, const SimState& s, int i) {
  const Mat3 R = s.frames.orient_world[i].toRotationMatrix();
  return R * rig.bone_inertia_local[i].asDiagonal() * R.transpose();
}

// M = sum_b Jw^T I Jw + Jv^T m Jv
inline MatX mass_matrix(const Rig& rig, const SimState& s) {
  MatX M = MatX::Zero(nv(rig), nv(rig));
  MatX Jw, Jv;
  for (int b = 0; b < rig.nbone; ++b) {
    jacobians(rig, s, b, Jw, Jv);
    M += Jw.transpose() * inertia(rig, s, b) * Jw + rig.bone_mass[b] * Jv.transpose() * Jv;
  }
  return M;
}

// tau - C: the external wrench minus the velocity products, as generalised forces. The
// accelerations with qdd = 0 come from a classical recursion (world axes, centres of mass):
//   alpha_i = alpha_p + d/dt (w_i - w_p) at qdd = 0: a ball's axes turn with the bone,
//             w_i x w_rel; a hinge's or universal's s0 with the parent, s1 with the bone:
//             w_p x s0 t0' + w_i x s1 t1'
//   a_head = a_p + alpha_p x d + w_p x (w_p x d),
//   a_i = a_head + alpha_i x e + w_i x (w_i x e)        d = head_i - com_p,  e = com_i - head_i
inline VecX generalised_force(const Rig& rig, const SimState& s) {
  const int n = rig.nbone;
  std::vector<Vec3> alpha(n, Vec3::Zero()), acc(n, Vec3::Zero());
  for (int i = 1; i < n; ++i) {
    const int p = rig.bone_parent[i];
    const Vec3 w_rel = s.omega_world[i] - s.omega_world[p];
    const int k = coordinates(rig, i);
    if (k == 3) {
      alpha[i] = alpha[p] + s.omega_world[i].cross(w_rel);
    } else {
      const Mat3 axes = joint_axes(rig, s, i);
      const Vec3& rate = s.joint_space.joint_vel_local[i];
      alpha[i] = alpha[p] + s.omega_world[p].cross(Vec3(axes.col(0))) * rate[0] +
                 s.omega_world[i].cross(Vec3(axes.col(1))) * rate[1];
    }
    const Vec3 d = s.frames.head_world[i] - s.com_world[p];
    const Vec3 e = s.com_world[i] - s.frames.head_world[i];
    const Vec3& wp = s.omega_world[p];
    const Vec3& w = s.omega_world[i];
    acc[i] = acc[p] + alpha[p].cross(d) + wp.cross(wp.cross(d)) + alpha[i].cross(e) +
             w.cross(w.cross(e));
  }
  VecX Q = VecX::Zero(nv(rig));
  MatX Jw, Jv;
  for (int b = 0; b < n; ++b) {
    jacobians(rig, s, b, Jw, Jv);
    const Mat3 I = inertia(rig, s, b);
    const Vec3& w = s.omega_world[b];
    const Vec3 F = s.force_world[b] - rig.bone_mass[b] * acc[b];
    // the external torque with the data's rotational damper and gyroscopic cancellation
    Vec3 T = s.torque_world[b] + s.joint_space.articulated.torque_per_omega * (I * w) -
             I * alpha[b] - w.cross(I * w);
    if (s.joint_space.articulated.cancel_gyroscopic) T += w.cross(I * w);
    Q += Jv.transpose() * F + Jw.transpose() * T;
  }
  return Q;
}

inline VecX aba_qacc(const Rig& rig, const ArticulatedBodyData& d) {
  VecX q(nv(rig));
  q.head<3>() = d.root_accel_world;
  gather(rig, d.joint_accel_local, q);
  return q;
}

// the velocity Jacobian of a world point p moving with body b: v_p = Jp qdot
inline MatX point_jacobian(const Rig& rig, const SimState& s, int b, const Vec3& p) {
  MatX Jw, Jv;
  jacobians(rig, s, b, Jw, Jv);
  MatX Jp = Jv;
  for (int c = 0; c < Jp.cols(); ++c) Jp.col(c) += Vec3(Jw.col(c)).cross(p - s.com_world[b]);
  return Jp;
}

}  // namespace physik::dense
