#include "physik/engine/linear_modes_dense.h"

#include <cmath>

#include <Eigen/Eigenvalues>

#include "physik/engine/forces.h"
#include "physik/model/joint_coordinates.h"

namespace physik {

namespace {

using MatX = Eigen::MatrixXd;

// the first rotational coordinate of a joint: after a free root's three translations
int rot_dof(const Rig& rig, LockedAxes locked, int bone) {
  return rig.dofadr(bone, locked) + (rig.joint_type(bone, locked) == JointType::kFree ? 3 : 0);
}

// the world axes of joint j's rotational coordinates as the columns of `axes`, their count: a
// ball's (a free root's) its bone's local axes, a hinge's or universal's s0, s1
// (joint_coordinates.h); a weld has none
int rotation_axes(const Rig& rig, LockedAxes locked, const SimState& s, int j, Mat3& axes) {
  const JointType type = rig.joint_type(j, locked);
  if (type == JointType::kWeld) return 0;
  if (type == JointType::kFree || type == JointType::kBall) {
    axes = s.frames.orient_world[j].toRotationMatrix();
    return 3;
  }
  const int p = rig.bone_parent[j];
  Vec3 s0, s1;
  hinge_axes_world(rig, j, p < 0 ? Quat::Identity() : s.frames.orient_world[p],
                   s.frames.orient_world[j], s0, s1);
  axes << s0, s1, Vec3::Zero();
  return type == JointType::kHinge ? 1 : 2;
}

// the rotation Jacobian of body b and the velocity Jacobian of a point p on it: each DOF turns
// about its axis through its pivot (a free root: its centre of mass, which also translates; a
// ball, a hinge, a pinned root's too: the head); a weld has none
void body_jacobians(const Rig& rig, LockedAxes locked, const SimState& s, int b, const Vec3& p,
                    MatX& Jw, MatX& Jp) {
  const int nv = rig.velocity_count(locked);
  Jw.setZero(3, nv);
  Jp.setZero(3, nv);
  if (rig.joint_type(0, locked) == JointType::kFree) Jp.leftCols<3>().setIdentity();
  Mat3 axes;
  for (int j = b; j >= 0; j = rig.bone_joint_parent[j]) {
    const int count = rotation_axes(rig, locked, s, j, axes);
    const Vec3 pivot =
        rig.joint_type(j, locked) == JointType::kFree ? s.com_world[0] : s.frames.head_world[j];
    for (int k = 0; k < count; ++k) {
      const Vec3 axis = axes.col(k);
      Jw.col(rot_dof(rig, locked, j) + k) = axis;
      Jp.col(rot_dof(rig, locked, j) + k) = axis.cross(p - pivot);
    }
  }
}

Mat3 inertia_of(const Rig& rig, const SimState& s, int b) {
  const Mat3 R = s.frames.orient_world[b].toRotationMatrix();
  return R * rig.bone_inertia_local[b].asDiagonal() * R.transpose();
}

}  // namespace

DenseModeMatrices dense_mode_matrices(const Scene& scene, const SimState& s,
                                      const std::vector<Vec3>& targets) {
  const Rig& rig = scene.rig;
  const EngineParams& prm = scene.params;
  const LockedAxes locked = prm.locked_axes();
  const int nv = rig.velocity_count(locked);
  DenseModeMatrices out{MatX::Zero(nv, nv), MatX::Zero(nv, nv), MatX::Zero(nv, nv),
                        MatX::Zero(nv, nv)};
  MatX &M = out.M, &K = out.K, &D1 = out.D1, &Dr = out.Dr;
  MatX Jw, Jp, Jwp, Jdummy;
  const double rot = (1.0 - prm.angular_velocity_factor) / prm.dt;
  for (int b = 0; b < rig.nbone; ++b) {
    const Mat3 I = inertia_of(rig, s, b);
    body_jacobians(rig, locked, s, b, s.com_world[b], Jw, Jp);
    M += Jw.transpose() * I * Jw + rig.bone_mass[b] * Jp.transpose() * Jp;
    Dr += Jw.transpose() * (rot * I) * Jw;
    for (const Vec3* p : {&s.frames.head_world[b], &s.frames.tail_world[b]}) {
      body_jacobians(rig, locked, s, b, *p, Jw, Jp);
      D1 += Jp.transpose() * Jp;
    }
  }
  // K: every force element's stiffness at the pose (forces.h mode_stiffness), as the O(n)
  // operators see it: a point element through its point's velocity Jacobian, a couple through
  // its body's angular velocity Jacobian, a joint block
  // through the relative turn of its bone and its parent (a pinned root's: the world)
  ModeStiffness stiffness;
  mode_stiffness(scene, s, targets, stiffness);
  for (const ModeStiffness::Point& e : stiffness.points) {
    body_jacobians(rig, locked, s, e.bone, e.point_world, Jw, Jp);
    K += Jp.transpose() * e.stiffness * Jp;
  }
  for (const ModeStiffness::Couple& e : stiffness.couples) {
    body_jacobians(rig, locked, s, e.bone, s.com_world[e.bone], Jw, Jdummy);
    K += Jw.transpose() * e.stiffness * Jw;
  }
  for (const ModeStiffness::Block& e : stiffness.blocks) {
    body_jacobians(rig, locked, s, e.bone, s.com_world[e.bone], Jw, Jdummy);
    const int parent = rig.bone_parent[e.bone];
    if (parent >= 0) {
      body_jacobians(rig, locked, s, parent, s.com_world[e.bone], Jwp, Jdummy);
    } else {
      Jwp.setZero(3, nv);
    }
    const MatX Jrel = Jw - Jwp;
    K += Jrel.transpose() * e.stiffness * Jrel;
  }
  return out;
}

DenseLinearModes linear_modes_dense(const Scene& scene, const SimState& s,
                                    const std::vector<Vec3>& targets) {
  const DenseModeMatrices mat = dense_mode_matrices(scene, s, targets);
  const MatX &M = mat.M, &K = mat.K, &D1 = mat.D1, &Dr = mat.Dr;
  const int nv = static_cast<int>(M.rows());
  DenseLinearModes out;
  LinearModes& m = out.modes;
  const Eigen::GeneralizedSelfAdjointEigenSolver<MatX> eig(K, M);
  const Eigen::VectorXd w2 = eig.eigenvalues();
  out.omega.resize(nv);
  for (int i = 0; i < nv; ++i) out.omega[i] = std::sqrt(std::max(w2[i], 0.0));
  m.omega2_max = std::max(w2.maxCoeff(), 0.0);
  const double tiny = 1e-9 * m.omega2_max;
  const double d1_scale = D1.diagonal().maxCoeff();
  for (int i = 0; i < nv && tiny > 0.0; ++i) {
    if (w2[i] <= tiny) continue;
    if (out.first_constrained < 0) {
      out.first_constrained = i;
      m.first_constrained_omega = out.omega[i];
    }
    const Eigen::VectorXd phi = eig.eigenvectors().col(i);
    const double d1 = phi.dot(D1 * phi);
    const double dr = phi.dot(Dr * phi);
    const double c = (2.0 * out.omega[i] - dr) / d1;
    // the end dampers do not reach this mode, or the angular-velocity factor alone damps it
    // critically or more
    if (d1 <= 1e-12 * d1_scale || c <= 0.0) {
      ++m.skipped;
      continue;
    }
    out.slowest = i;
    m.found = true;
    m.slowest_omega = out.omega[i];
    m.slowest_d1 = d1;
    m.slowest_dr = dr;
    m.critical_damping = c;
    break;
  }
  return out;
}

}  // namespace physik
