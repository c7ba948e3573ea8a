#include "physik/engine/linear_modes_dense.h"

#include <cmath>

#include <Eigen/Eigenvalues>

#include "physik/engine/forces.h"

namespace physik {

namespace {

using MatX = Eigen::MatrixXd;

// the first rotational coordinate of a joint: after a free root's three translations
int rot_dof(const Rig& rig, int bone) {
  return rig.bone_dofadr[bone] + (rig.bone_joint_type[bone] == JointType::kFree ? 3 : 0);
}

// the rotation Jacobian of body b and the velocity Jacobian of a point p on it: each DOF turns
// about its axis through its pivot (a free root: its centre of mass, which also translates; a
// ball, a pinned root's too: the head); a weld has none
void body_jacobians(const Rig& rig, const SimState& s, int b, const Vec3& p, MatX& Jw, MatX& Jp) {
  Jw.setZero(3, rig.nv);
  Jp.setZero(3, rig.nv);
  if (rig.bone_joint_type[0] == JointType::kFree) Jp.leftCols<3>().setIdentity();
  for (int j = b; j >= 0; j = rig.bone_joint_parent[j]) {
    const JointType type = rig.bone_joint_type[j];
    if (type == JointType::kWeld) continue;
    const Vec3 pivot = type == JointType::kFree ? s.com_world[0] : s.frames.head_world[j];
    for (int k = 0; k < 3; ++k) {
      const Vec3 axis = s.frames.orient_world[j] * Vec3::Unit(k);
      Jw.col(rot_dof(rig, j) + k) = axis;
      Jp.col(rot_dof(rig, j) + k) = axis.cross(p - pivot);
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
  const int nv = rig.nv;
  DenseModeMatrices out{MatX::Zero(nv, nv), MatX::Zero(nv, nv), MatX::Zero(nv, nv),
                        MatX::Zero(nv, nv)};
  MatX &M = out.M, &K = out.K, &D1 = out.D1, &Dr = out.Dr;
  MatX Jw, Jp, Jwp, Jdummy;
  const double rot = (1.0 - prm.angular_velocity_factor) / prm.dt;
  for (int b = 0; b < rig.nbone; ++b) {
    const Mat3 I = inertia_of(rig, s, b);
    body_jacobians(rig, s, b, s.com_world[b], Jw, Jp);
    M += Jw.transpose() * I * Jw + rig.bone_mass[b] * Jp.transpose() * Jp;
    Dr += Jw.transpose() * (rot * I) * Jw;
    for (const Vec3* p : {&s.frames.head_world[b], &s.frames.tail_world[b]}) {
      body_jacobians(rig, s, b, *p, Jw, Jp);
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
    body_jacobians(rig, s, e.bone, e.point_world, Jw, Jp);
    K += Jp.transpose() * e.stiffness * Jp;
  }
  for (const ModeStiffness::Couple& e : stiffness.couples) {
    body_jacobians(rig, s, e.bone, s.com_world[e.bone], Jw, Jdummy);
    K += Jw.transpose() * e.stiffness * Jw;
  }
  for (const ModeStiffness::Block& e : stiffness.blocks) {
    body_jacobians(rig, s, e.bone, s.com_world[e.bone], Jw, Jdummy);
    const int parent = rig.bone_parent[e.bone];
    if (parent >= 0) {
      body_jacobians(rig, s, parent, s.com_world[e.bone], Jwp, Jdummy);
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
