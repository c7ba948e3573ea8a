#include "physik/engine/torsion_springs.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>

#include "physik/engine/potential.h"

namespace physik {

Vec3 torsion_torque_local(const std::array<AxisLimit, 3>& limits, const Vec3& theta,
                          const EngineParams& params) {
  Vec3 tau = Vec3::Zero();
  for (int k = 0; k < 3; ++k) {
    const AxisLimit& l = limits[k];
    if (!l.limited) continue;
    // the dead zone of potential.h: tau = -dU/dtheta
    double d = torsion_excess(l, params.torsion_tolerance, theta[k]);
    if (d == 0.0) continue;
    if (params.torsion_spring == SpringLaw::kCapped) {
      d = std::copysign(std::min(std::abs(d), params.torsion_cap), d);
    }
    tau[k] = params.torsion_k * d;
  }
  return tau;
}

namespace {

// per axis: k on an engaged axis within the cap; beyond the cap 0 (tangent) or k c / |d| (secant)
Vec3 axis_stiffness(const std::array<AxisLimit, 3>& limits, const Vec3& theta,
                    const EngineParams& params, bool secant_beyond_cap) {
  Vec3 k = Vec3::Zero();
  for (int a = 0; a < 3; ++a) {
    const AxisLimit& l = limits[a];
    if (!l.limited) continue;
    const double d = torsion_excess(l, params.torsion_tolerance, theta[a]);
    if (d == 0.0) continue;
    k[a] = params.torsion_k;
    if (params.torsion_spring == SpringLaw::kCapped && std::abs(d) > params.torsion_cap) {
      k[a] = secant_beyond_cap ? params.torsion_k * params.torsion_cap / std::abs(d) : 0.0;
    }
  }
  return k;
}

}  // namespace

Vec3 torsion_stiffness_local(const std::array<AxisLimit, 3>& limits, const Vec3& theta,
                             const EngineParams& params) {
  return axis_stiffness(limits, theta, params, false);
}

Vec3 torsion_step_stiffness_local(const std::array<AxisLimit, 3>& limits, const Vec3& theta,
                                  const EngineParams& params) {
  return axis_stiffness(limits, theta, params, true);
}

Mat3 left_jacobian_inverse_transpose(const Vec3& theta) {
  const double t2 = theta.squaredNorm(), t = std::sqrt(t2);
  // b = 1/t^2 - cot(t/2) / (2 t), its series near 0 (the two terms cancel there)
  const double b = t < 1e-3 ? 1.0 / 12.0 + t2 / 720.0 : 1.0 / t2 - 0.5 / (t * std::tan(0.5 * t));
  const Mat3 W = skew(theta);
  return Mat3::Identity() + 0.5 * W + b * (W * W);
}

Mat3 torsion_torque_frame(const Rig& rig, const EngineParams& params,
                          const Quat& parent_orient_world, int bone, const Vec3& theta) {
  const Mat3 R = (parent_orient_world * rig.bone_rest_orient_parent[bone]).toRotationMatrix();
  return params.torsion_torque == TorsionTorque::kGradient
             ? R * left_jacobian_inverse_transpose(theta)
             : R;
}

Mat3 torsion_step_block_local(const Vec3& k, const Vec3& theta, TorsionTorque torque) {
  const Mat3 Jt = left_jacobian_inverse_transpose(theta);  // J_l^-T
  const Mat3 tangent = k.asDiagonal() * Jt.transpose();    // diag(k) J_l^-1
  if (torque == TorsionTorque::kGradient) return Jt * tangent;
  // the symmetric part's negative eigenvalues clipped; the antisymmetric part kept
  const Mat3 sym = 0.5 * (tangent + tangent.transpose());
  Eigen::SelfAdjointEigenSolver<Mat3> eig;
  eig.computeDirect(sym);
  if (eig.eigenvalues().minCoeff() >= 0.0) return tangent;
  const Vec3 clipped = eig.eigenvalues().cwiseMax(0.0);
  return eig.eigenvectors() * clipped.asDiagonal() * eig.eigenvectors().transpose() +
         0.5 * (tangent - tangent.transpose());
}

void apply_torsion_springs(const Rig& rig, const EngineParams& params, SimState& s) {
  if (params.torsion_k == 0.0) return;
  const bool gradient = params.torsion_torque == TorsionTorque::kGradient;
  for (int i = 0; i < rig.nbone; ++i) {
    if (!has_torsion_spring(rig, i)) continue;
    const auto& limits = rig.bone_limit[i];
    const Vec3 theta = rotation_vector(s.pose.bone_local_rotation[i]);
    Vec3 tau_local = torsion_torque_local(limits, theta, params);
    if (tau_local.isZero(0.0)) continue;
    if (gradient) tau_local = left_jacobian_inverse_transpose(theta) * tau_local;  // tau_pr
    const int p = rig.bone_parent[i];
    const Vec3 tau_world =
        torsion_parent_orient(rig, s.frames, i) * (rig.bone_rest_orient_parent[i] * tau_local);
    s.torque_world[i] += tau_world;
    if (p >= 0) s.torque_world[p] -= tau_world;
  }
}

}  // namespace physik
