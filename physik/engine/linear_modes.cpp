#include "physik/engine/linear_modes.h"

#include <cmath>
#include <string>

#include <Eigen/Eigenvalues>

#include "physik/engine/control_springs.h"
#include "physik/engine/torsion_springs.h"
#include "physik/model/errors.h"

namespace physik {

namespace {

using MatX = Eigen::MatrixXd;

int nv_of(const Rig& rig) { return 6 + 3 * (rig.nbone - 1); }
int rot_dof(int bone) { return bone == 0 ? 3 : 3 + 3 * bone; }

// the rotation Jacobian of body b and the velocity Jacobian of a point p on it: each DOF turns
// about its axis through its pivot (root: its centre of mass, ball: the head); the root also
// translates
void body_jacobians(const Rig& rig, const SimState& s, int b, const Vec3& p, MatX& Jw, MatX& Jp) {
  Jw.setZero(3, nv_of(rig));
  Jp.setZero(3, nv_of(rig));
  Jp.leftCols<3>().setIdentity();
  for (int j = b; j >= 0; j = rig.bone_parent[j]) {
    const Vec3 pivot = j == 0 ? s.com_world[0] : s.frames.head_world[j];
    for (int k = 0; k < 3; ++k) {
      const Vec3 axis = s.frames.orient_world[j] * Vec3::Unit(k);
      Jw.col(rot_dof(j) + k) = axis;
      Jp.col(rot_dof(j) + k) = axis.cross(p - pivot);
    }
  }
}

Mat3 inertia_of(const Rig& rig, const SimState& s, int b) {
  const Mat3 R = s.frames.orient_world[b].toRotationMatrix();
  return R * rig.bone_inertia_local[b].asDiagonal() * R.transpose();
}

}  // namespace

LinearModes linear_modes(const Scene& scene, const SimState& s, const std::vector<Vec3>& targets) {
  const Rig& rig = scene.rig;
  const EngineParams& prm = scene.params;
  if (rig.nbone > kMaxModeBones) {
    throw_input_error(scene.file, "params", "damping_auto",
                      "the dense linear modes support rigs up to " + std::to_string(kMaxModeBones) +
                          " bones (this one has " + std::to_string(rig.nbone) + ")");
  }
  const int nv = nv_of(rig);
  MatX M = MatX::Zero(nv, nv), K = MatX::Zero(nv, nv), D1 = MatX::Zero(nv, nv), Dr = MatX::Zero(nv, nv);
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
    if (b == 0 || prm.torsion_k == 0.0) continue;
    const Vec3 theta = rotation_vector(s.pose.bone_local_rotation[b]);
    const Vec3 k = torsion_stiffness_local(rig.bone_limit[b], theta, prm);
    if (k.isZero(0.0)) continue;
    const Mat3 T = torsion_torque_frame(rig, prm, s.frames.orient_world[rig.bone_parent[b]], b, theta);
    body_jacobians(rig, s, rig.bone_parent[b], s.com_world[b], Jwp, Jdummy);
    const MatX Jrel = Jw - Jwp;
    K += Jrel.transpose() * (T * k.asDiagonal() * T.transpose()) * Jrel;
  }
  for (std::size_t c = 0; c < scene.control_points.size(); ++c) {
    const ControlPoint& cp = scene.control_points[c];
    const Vec3 a = point_on_bone(s.frames, cp.bone, cp.alpha);
    body_jacobians(rig, s, cp.bone, a, Jw, Jp);
    K += Jp.transpose() * spring_tangent(cp.spring_in(prm), cp.k_in(prm), cp.cap_in(prm),
                                          targets[c] - a) * Jp;
  }

  LinearModes out;
  const Eigen::GeneralizedSelfAdjointEigenSolver<MatX> eig(K, M);
  const Eigen::VectorXd w2 = eig.eigenvalues();
  out.omega.resize(nv);
  for (int i = 0; i < nv; ++i) out.omega[i] = std::sqrt(std::max(w2[i], 0.0));
  const double tiny = 1e-9 * std::max(w2.maxCoeff(), 0.0);
  const double d1_scale = D1.diagonal().maxCoeff();
  for (int i = 0; i < nv && tiny > 0.0; ++i) {
    if (w2[i] <= tiny) continue;
    if (out.first_constrained < 0) out.first_constrained = i;
    const Eigen::VectorXd phi = eig.eigenvectors().col(i);
    const double d1 = phi.dot(D1 * phi);
    if (d1 <= 1e-12 * d1_scale) continue;  // the end dampers do not reach this mode
    const double dr = phi.dot(Dr * phi);
    const double c = (2.0 * out.omega[i] - dr) / d1;
    if (c <= 0.0) continue;  // the angular-velocity factor alone damps it critically or more
    out.slowest = i;
    out.slowest_d1 = d1;
    out.slowest_dr = dr;
    out.critical_damping = c;
    break;
  }
  return out;
}

void update_auto_damping(const Scene& scene, SimState& s) {
  // the springs' stiffness of the settling approach: d = 0, so capped springs count with k 1
  // (beyond the cap they have none along the pull, and the whole-body translation would be a
  // zero mode at the start pose of a far target)
  std::vector<Vec3> at_target(scene.control_points.size());
  for (std::size_t c = 0; c < at_target.size(); ++c) {
    const ControlPoint& cp = scene.control_points[c];
    at_target[c] = point_on_bone(s.frames, cp.bone, cp.alpha);
  }
  s.damping_auto_value = linear_modes(scene, s, at_target).critical_damping;
  s.damping_auto_updates += 1;
}

}  // namespace physik
