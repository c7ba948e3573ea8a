#include "physik/engine/torsion_springs.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>

#include "physik/model/joint_coordinates.h"

namespace physik {

double torsion_spring_potential(SpringLaw law, double k, double cap, double excess) {
  const double d = std::abs(excess);
  if (law == SpringLaw::kLinear || d <= cap) return 0.5 * k * d * d;
  return k * cap * (d - 0.5 * cap);
}

Vec3 torsion_excess(const std::array<AxisLimit, 3>& limits, double tolerance, const Quat& q) {
  Vec3 e = Vec3::Zero();
  if (!limits[0].limited && !limits[1].limited && !limits[2].limited) return e;
  const Vec3 theta = rotation_vector(q);
  for (int k = 0; k < 3; ++k) {
    if (limits[k].limited) e[k] = torsion_excess(limits[k], tolerance, theta[k]);
  }
  return e;
}

TorsionKind torsion_kind(const Rig& rig, LockedAxes locked, int i) {
  if (!has_torsion_spring(rig, i)) return TorsionKind::kNone;
  switch (rig.joint_type(i, locked)) {
    case JointType::kBall:
      return TorsionKind::kRotationVector;
    case JointType::kHinge:
    case JointType::kUniversal: {
      const auto& l = rig.bone_limit[i];
      const auto& axes = rig.bone_joint_axes[i];
      const bool limited = l[axes[0]].limited || (axes[1] >= 0 && l[axes[1]].limited);
      return limited ? TorsionKind::kHingeAngles : TorsionKind::kNone;
    }
    case JointType::kFree:
    case JointType::kWeld:
      break;
  }
  return TorsionKind::kNone;
}

Vec3 torsion_angles(const Rig& rig, TorsionKind kind, int i, const Quat& q) {
  if (kind != TorsionKind::kHingeAngles) return rotation_vector(q);
  Vec3 theta;
  for (int k = 0; k < 3; ++k)
    theta[k] = rig.bone_limit[i][k].locked() ? rig.bone_limit[i][k].min : 0.0;
  const Vec2 t = hinge_coordinates(rig, i, q);
  const auto& axes = rig.bone_joint_axes[i];
  theta[axes[0]] = t[0];
  if (axes[1] >= 0) theta[axes[1]] = t[1];
  return theta;
}

double torsion_potential(const Rig& rig, const EngineParams& params, const Pose& pose) {
  if (params.torsion_k == 0.0) return 0.0;
  double u = 0.0;
  const LockedAxes locked = params.locked_axes();
  for (int i = 0; i < rig.nbone; ++i) {
    const TorsionKind kind = torsion_kind(rig, locked, i);
    if (kind == TorsionKind::kNone) continue;
    const Vec3 theta = torsion_angles(rig, kind, i, pose.bone_local_rotation[i]);
    Vec3 e = Vec3::Zero();
    for (int k = 0; k < 3; ++k) {
      const AxisLimit& l = rig.bone_limit[i][k];
      if (l.limited) e[k] = torsion_excess(l, params.torsion_tolerance, theta[k]);
    }
    for (int k = 0; k < 3; ++k) {
      if (e[k] != 0.0) {
        u += torsion_spring_potential(params.torsion_spring, params.torsion_k, params.torsion_cap,
                                      e[k]);
      }
    }
  }
  return u;
}

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

namespace {

// a hinge's or universal's world axes at the state's frames (joint_coordinates.h)
void axes_world(const Rig& rig, const BoneFrames& f, int i, Vec3& s0, Vec3& s1) {
  hinge_axes_world(rig, i, torsion_parent_orient(rig, f, i), f.orient_world[i], s0, s1);
}

// a local per-axis vector v (torque or stiffness) on a hinge's or universal's angles, the axes
// s0, s1 carrying its free axes' entries: S diag(v) S^T or S v
Mat3 hinge_block(const Rig& rig, int i, const Vec3& v, const Vec3& s0, const Vec3& s1) {
  const auto& axes = rig.bone_joint_axes[i];
  Mat3 out = v[axes[0]] * (s0 * s0.transpose());
  if (axes[1] >= 0) out += v[axes[1]] * (s1 * s1.transpose());
  return out;
}

Vec3 hinge_torque(const Rig& rig, int i, const Vec3& tau_local, const Vec3& s0, const Vec3& s1) {
  const auto& axes = rig.bone_joint_axes[i];
  return tau_local[axes[0]] * s0 + (axes[1] >= 0 ? tau_local[axes[1]] : 0.0) * s1;
}

}  // namespace

void apply_torsion_springs(const Rig& rig, const EngineParams& params, SimState& s) {
  if (params.torsion_k == 0.0) return;
  const bool gradient = params.torsion_torque == TorsionTorque::kGradient;
  const LockedAxes locked = params.locked_axes();
  for (int i = 0; i < rig.nbone; ++i) {
    const TorsionKind kind = torsion_kind(rig, locked, i);
    if (kind == TorsionKind::kNone) continue;
    const auto& limits = rig.bone_limit[i];
    const Vec3 theta = torsion_angles(rig, kind, i, s.pose.bone_local_rotation[i]);
    Vec3 tau_local = torsion_torque_local(limits, theta, params);
    if (tau_local.isZero(0.0)) continue;
    const int p = rig.bone_parent[i];
    Vec3 tau_world;
    if (kind == TorsionKind::kHingeAngles) {  // generalised forces on the angles
      Vec3 s0, s1;
      axes_world(rig, s.frames, i, s0, s1);
      tau_world = hinge_torque(rig, i, tau_local, s0, s1);
    } else {
      if (gradient) tau_local = left_jacobian_inverse_transpose(theta) * tau_local;  // tau_pr
      tau_world =
          torsion_parent_orient(rig, s.frames, i) * (rig.bone_rest_orient_parent[i] * tau_local);
    }
    s.torque_world[i] += tau_world;
    if (p >= 0) s.torque_world[p] -= tau_world;
  }
}

double torsion_springs_potential(const Scene& scene, const SimState& s) {
  return torsion_potential(scene.rig, scene.params, s.pose);
}

void torsion_springs_tangents(const Scene& scene, const ImplicitStage& stage, SimState& s) {
  ImplicitWorkspace& im = s.implicit;
  const bool full = stage.full;
  const EngineParams& p = scene.params;
  const Rig& rig = scene.rig;
  const LockedAxes locked = p.locked_axes();
  for (int i = 0; i < rig.nbone; ++i) {
    const auto& limits = rig.bone_limit[i];
    im.torsion_torque_world[i].setZero();
    const TorsionKind kind = torsion_kind(rig, locked, i);
    if (kind == TorsionKind::kNone || p.torsion_k == 0.0) {
      im.torsion_stiffness[i].setZero();
      im.torsion_block_world[i].setZero();  // torsion_block_world() reads it without the stiffness
      continue;
    }
    const Vec3 theta = torsion_angles(rig, kind, i, s.pose.bone_local_rotation[i]);
    im.torsion_stiffness[i] = torsion_step_stiffness_local(limits, theta, p);
    if (kind == TorsionKind::kHingeAngles) {
      // diag(k) on the angles: S diag(k) S^T on the relative rate; the generalised force Q(t)
      // is the angles' own, so no pose term (the torque S Q turns with the axes it acts on)
      Vec3 s0, s1;
      axes_world(rig, s.frames, i, s0, s1);
      im.torsion_block_world[i] = hinge_block(rig, i, im.torsion_stiffness[i], s0, s1);
      if (full) {
        im.torsion_torque_world[i] =
            hinge_torque(rig, i, torsion_torque_local(limits, theta, p), s0, s1);
      }
      continue;
    }
    const Mat3 R = (torsion_parent_orient(rig, s.frames, i) * rig.bone_rest_orient_parent[i])
                       .toRotationMatrix();  // R_pr
    im.torsion_block_world[i] =
        R * torsion_step_block_local(im.torsion_stiffness[i], theta, p.torsion_torque) *
        R.transpose();
    if (full && !im.torsion_stiffness[i].isZero(0.0)) {
      // the torque the force stage applied, and its pose terms (implicit_pose_terms.h (5))
      const Vec3 tau_local = torsion_torque_local(limits, theta, p);
      const Vec3 tau_pr = p.torsion_torque == TorsionTorque::kGradient
                              ? Vec3(left_jacobian_inverse_transpose(theta) * tau_local)
                              : tau_local;
      im.torsion_torque_world[i] = R * tau_pr;
      const PoseTermSelection& use = stage.terms;
      if (use.forces) {
        im.torsion_block_world[i] +=
            torsion_pose_block(R, theta, tau_local, p.torsion_torque, im.torsion_torque_world[i]);
      }
      // torsion_pose_block's frame term, -[tau]x, taken back when not selected
      if (use.forces != use.torque_frame) {
        im.torsion_block_world[i] += (use.forces ? 1.0 : -1.0) * skew(im.torsion_torque_world[i]);
      }
    }
  }
}

void torsion_springs_rate(const Scene& scene, const ImplicitStage& stage, SimState& s) {
  torsion_springs_tangents(scene, stage, s);
  const Rig& rig = scene.rig;
  for (int i = 0; i < rig.nbone; ++i) {
    if (s.implicit.torsion_stiffness[i].isZero(0.0)) continue;
    const int p = rig.bone_parent[i];
    const Vec3 w_rel = p < 0 ? s.omega_world[i] : Vec3(s.omega_world[i] - s.omega_world[p]);
    const Vec3 tau = -stage.h * (s.implicit.torsion_block_world[i] * w_rel);
    s.torque_world[i] += tau;
    if (p >= 0) s.torque_world[p] -= tau;
  }
}

void torsion_springs_augment(const Scene& scene, const ImplicitStage& stage, SimState& s) {
  ArticulatedBodyData& d = s.joint_space.articulated;
  d.joint_blocks = false;
  for (int i = 0; i < scene.rig.nbone; ++i) {
    if (s.implicit.torsion_stiffness[i].isZero(0.0)) {
      d.joint_block[i].setZero();
      continue;
    }
    d.joint_block[i] = stage.h * stage.h * s.implicit.torsion_block_world[i];
    d.joint_blocks = true;
  }
}

void torsion_springs_mode_stiffness(const Scene& scene, const SimState& s,
                                    const std::vector<Vec3>& /*targets*/, ModeStiffness& out) {
  const EngineParams& p = scene.params;
  const Rig& rig = scene.rig;
  const LockedAxes locked = p.locked_axes();
  for (int b = 0; b < rig.nbone && p.torsion_k != 0.0; ++b) {
    const TorsionKind kind = torsion_kind(rig, locked, b);
    if (kind == TorsionKind::kNone) continue;
    const Vec3 theta = torsion_angles(rig, kind, b, s.pose.bone_local_rotation[b]);
    const Vec3 k = torsion_stiffness_local(rig.bone_limit[b], theta, p);
    if (k.isZero(0.0)) continue;
    if (kind == TorsionKind::kHingeAngles) {
      Vec3 s0, s1;
      axes_world(rig, s.frames, b, s0, s1);
      out.blocks.push_back({b, hinge_block(rig, b, k, s0, s1)});
      continue;
    }
    const Mat3 T = torsion_torque_frame(rig, p, torsion_parent_orient(rig, s.frames, b), b, theta);
    out.blocks.push_back({b, T * k.asDiagonal() * T.transpose()});
  }
}

Mat3 left_jacobian_inverse_transpose_derivative(const Vec3& theta, const Vec3& tau) {
  // J_l^-T = 1 + W/2 + b W^2, W = [theta]x, b(t) = 1/t^2 - cot(t/2) / (2 t):
  //   d(W tau / 2) = -[tau]x dtheta / 2
  //   d(b W^2 tau) = (b'(t) / t) (W^2 tau) theta^T dtheta - b ([theta x tau]x + W [tau]x) dtheta
  // b'(t) / t = -2/t^4 + cot(t/2) / (2 t^3) + 1 / (4 t^2 sin^2(t/2)), its series near 0 (the
  // terms cancel there): 1/360 + t^2/7560 + t^4/201600
  const double t2 = theta.squaredNorm(), t = std::sqrt(t2);
  double b, db_over_t;
  if (t < 0.1) {
    b = 1.0 / 12.0 + t2 / 720.0 + t2 * t2 / 30240.0 + t2 * t2 * t2 / 1209600.0;
    db_over_t = 1.0 / 360.0 + t2 / 7560.0 + t2 * t2 / 201600.0;
  } else {
    const double cot = 1.0 / std::tan(0.5 * t), sn = std::sin(0.5 * t);
    b = 1.0 / t2 - 0.5 * cot / t;
    db_over_t = -2.0 / (t2 * t2) + 0.5 * cot / (t2 * t) + 0.25 / (t2 * sn * sn);
  }
  const Mat3 W = skew(theta);
  const Vec3 W2tau = theta.cross(theta.cross(tau));
  return -0.5 * skew(tau) + db_over_t * W2tau * theta.transpose() -
         b * (skew(theta.cross(tau)) + W * skew(tau));
}

Mat3 torsion_pose_block(const Mat3& R_pr, const Vec3& theta, const Vec3& tau_local,
                        TorsionTorque torque, const Vec3& tau_world) {
  Mat3 out = -skew(tau_world);
  if (torque == TorsionTorque::kGradient) {
    const Mat3 Jl_inv = left_jacobian_inverse_transpose(theta).transpose();
    out -= R_pr * left_jacobian_inverse_transpose_derivative(theta, tau_local) * Jl_inv *
           R_pr.transpose();
  }
  return out;
}

void torsion_springs_pose_forces(const Scene& scene, const SimState& s, PoseForces& out) {
  for (int i = 1; i < scene.rig.nbone; ++i) out.joint(i, s.implicit.torsion_torque_world[i]);
}

}  // namespace physik
