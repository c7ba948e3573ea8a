#include "physik/engine/mode_operators.h"

#include <algorithm>

#include <Eigen/Eigenvalues>

#include "physik/engine/forces.h"
#include "physik/engine/implicit_elements.h"
#include "physik/engine/state.h"
#include "physik/engine/torsion_springs.h"
#include "physik/model/joint_coordinates.h"

namespace physik {

namespace {

// a joint with rotational coordinates of its own, about its head: a ball (3), a universal (2) or
// a hinge (1), a pinned root's too
inline bool turns(JointType type) {
  return type == JointType::kBall || type == JointType::kHinge || type == JointType::kUniversal;
}

// the world axes of a turning joint's coordinates as the columns of `axes`, their count: a ball's
// the world axes x, y, z; a hinge's s0, a universal's s0, s1 (joint_coordinates.h)
inline int joint_axes(JointType type, const ArticulatedBodyData& d, int i, Mat3& axes) {
  if (type == JointType::kBall) {
    axes.setIdentity();
    return 3;
  }
  axes.col(0) = d.axis0_world[i];
  axes.col(1) = d.axis1_world[i];
  axes.col(2).setZero();
  return type == JointType::kHinge ? 1 : 2;
}

// adds the wrench about o of a point element K at offset r moving with V = (w; v at o)
inline void add_point_wrench(const Mat3& K, const Vec3& r, const Vec6& V, Vec6& W) {
  const Vec3 f = K * (V.tail<3>() + V.head<3>().cross(r));
  W.head<3>() += r.cross(f);
  W.tail<3>() += f;
}

}  // namespace

ModeOperators::ModeOperators(const Scene& scene, const SimState& s,
                             const std::vector<Vec3>& targets, ModeWorkspace& ws)
    : rig_(scene.rig), state_(s), ws_(ws), locked_(scene.params.locked_axes()) {
  const Rig& rig = scene.rig;
  const EngineParams& prm = scene.params;
  const int n = rig.nbone;
  nv_ = rig.velocity_count(locked_);
  ArticulatedBodyData& d = ws.articulated;
  if (static_cast<int>(d.inertia_art.size()) != n) resize_articulated_data(n, d);
  d.locked_axes = locked_;
  if (static_cast<int>(ws.velocity.size()) != n) {
    ws.velocity.assign(n, Vec6::Zero());
    ws.wrench.assign(n, Vec6::Zero());
    ws.second_moment.assign(n, Mat3::Zero());
    ws.first_moment.assign(n, Vec3::Zero());
    ws.ends.assign(n, 0.0);
  }
  // the recursion's inputs at zero velocity: points, inertias, no bias acceleration
  for (int i = 0; i < n; ++i) {
    const Mat3 R = s.frames.orient_world[i].toRotationMatrix();
    d.inertia_com_world[i] = R * rig.bone_inertia_local[i].asDiagonal() * R.transpose();
    const JointType type = rig.joint_type(i, locked_);
    d.point_world[i] = type == JointType::kFree ? s.com_world[i] : s.frames.head_world[i];
    d.bias_accel[i].setZero();
    if (type == JointType::kHinge || type == JointType::kUniversal) {
      const int p = rig.bone_parent[i];
      hinge_axes_world(rig, i, p < 0 ? Quat::Identity() : s.frames.orient_world[p],
                       s.frames.orient_world[i], d.axis0_world[i], d.axis1_world[i]);
    }
  }
  factor_damper_ = (1.0 - prm.angular_velocity_factor) / prm.dt;
  // K's elements, every force's (forces.h): points on bodies, couples on them, blocks on balls
  physik::mode_stiffness(scene, s, targets, ws.stiffness);
  ws.couples.clear();
  for (const ModeStiffness::Couple& c : ws.stiffness.couples)
    ws.couples.emplace_back(c.bone, c.stiffness);
  ws.torsion.clear();
  for (const ModeStiffness::Block& b : ws.stiffness.blocks)
    ws.torsion.emplace_back(b.bone, b.stiffness);
  ws.springs.clear();
  for (const ModeStiffness::Point& p : ws.stiffness.points) {
    ws.springs.push_back({p.bone, p.point_world - d.point_world[p.bone], p.stiffness});
  }
  compute_end_damper_scale();
}

void ModeOperators::element_wrenches(Matrix which) {
  const ArticulatedBodyData& d = ws_.articulated;
  const int n = rig_.nbone;
  for (int i = 0; i < n; ++i) {
    const Vec6& V = ws_.velocity[i];
    Vec6& W = ws_.wrench[i];
    W.setZero();
    switch (which) {
      case Matrix::kMass: {
        const Vec3 e = state_.com_world[i] - d.point_world[i];
        const Vec3 f = rig_.bone_mass[i] * (V.tail<3>() + V.head<3>().cross(e));
        W << d.inertia_com_world[i] * V.head<3>() + e.cross(f), f;
        break;
      }
      case Matrix::kEndDampers:
        add_point_wrench(Mat3::Identity(), state_.frames.head_world[i] - d.point_world[i], V, W);
        add_point_wrench(Mat3::Identity(), state_.frames.tail_world[i] - d.point_world[i], V, W);
        break;
      case Matrix::kFactorDamper:
        W.head<3>() = factor_damper_ * (d.inertia_com_world[i] * V.head<3>());
        break;
      case Matrix::kStiffness:
        break;
    }
  }
  if (which != Matrix::kStiffness) return;
  for (const ModePointElement& e : ws_.springs) {
    add_point_wrench(e.stiffness, e.offset, ws_.velocity[e.bone], ws_.wrench[e.bone]);
  }
  for (const auto& [b, K] : ws_.couples) {
    ws_.wrench[b].head<3>() += K * ws_.velocity[b].head<3>();
  }
}

void ModeOperators::multiply(Matrix which, const VecX& x, VecX& y) {
  const int n = rig_.nbone;
  const ArticulatedBodyData& d = ws_.articulated;
  std::vector<Vec6>& V = ws_.velocity;
  std::vector<Vec6>& W = ws_.wrench;
  y.resize(nv_);
  // velocities outward: V = (w; v at o); a pinned root turns about its fixed head
  if (rig_.joint_type(0, locked_) == JointType::kFree) {
    V[0] << x.segment<3>(3), x.head<3>();
  } else {
    V[0] << rate(0, x), Vec3::Zero();
  }
  for (int i = 1; i < n; ++i) {
    const int p = rig_.bone_joint_parent[i];
    const Vec3 r = d.point_world[i] - d.point_world[p];
    V[i].head<3>() = V[p].head<3>() + rate(i, x);
    V[i].tail<3>() = V[p].tail<3>() - r.cross(Vec3(V[p].head<3>()));
  }
  element_wrenches(which);
  // wrenches inward; each joint's coordinates take its subtree's torque about the joint
  for (int i = n - 1; i > 0; --i) {
    const int p = rig_.bone_joint_parent[i];
    const Vec3 r = d.point_world[i] - d.point_world[p];
    put_torque(i, W[i].head<3>(), false, y);
    W[p].head<3>() += W[i].head<3>() + r.cross(Vec3(W[i].tail<3>()));
    W[p].tail<3>() += W[i].tail<3>();
  }
  if (rig_.joint_type(0, locked_) == JointType::kFree) {
    y.head<3>() = W[0].tail<3>();
    y.segment<3>(3) = W[0].head<3>();
  } else {
    put_torque(0, W[0].head<3>(), false, y);
  }
  if (which != Matrix::kStiffness) return;
  // the torsion blocks (world, on the relative rate): S^T K S on the joint's coordinates
  for (const auto& [b, K] : ws_.torsion) put_torque(b, K * rate(b, x), true, y);
}

Vec3 ModeOperators::rate(int i, const VecX& x) const {
  Mat3 axes;
  const JointType type = rig_.joint_type(i, locked_);
  if (!turns(type)) return Vec3::Zero();
  const int k = joint_axes(type, ws_.articulated, i, axes);
  const int a = rig_.dofadr(i, locked_);
  if (k == 3) return x.segment<3>(a);
  Vec3 w = axes.col(0) * x[a];
  if (k == 2) w += axes.col(1) * x[a + 1];
  return w;
}

void ModeOperators::put_torque(int i, const Vec3& torque, bool add, VecX& y) const {
  Mat3 axes;
  const JointType type = rig_.joint_type(i, locked_);
  if (!turns(type)) return;
  const int k = joint_axes(type, ws_.articulated, i, axes);
  const int a = rig_.dofadr(i, locked_);
  if (k == 3) {
    if (add) {
      y.segment<3>(a) += torque;
    } else {
      y.segment<3>(a) = torque;
    }
    return;
  }
  for (int c = 0; c < k; ++c) {
    const double v = axes.col(c).dot(torque);
    y[a + c] = add ? y[a + c] + v : v;
  }
}

void ModeOperators::set_shift(double s) {
  shift_ = s;
  ArticulatedBodyData& d = ws_.articulated;
  for (Mat3& J : d.joint_block) J.setZero();
  for (const auto& [b, K] : ws_.torsion) d.joint_block[b] = K / s;
  d.joint_blocks = !ws_.torsion.empty();
}

// the recursion's inertias of M + K / s: the rigid inertias plus K's point elements over s (the
// balls' blocks are set by set_shift); every bias force 0
void ModeOperators::load_inertias() {
  ArticulatedBodyData& d = ws_.articulated;
  for (int i = 0; i < rig_.nbone; ++i) {
    d.inertia_art[i] = spatial_inertia(rig_.bone_mass[i], d.inertia_com_world[i],
                                       state_.com_world[i] - d.point_world[i]);
    d.bias_force[i].setZero();
  }
  for (const ModePointElement& e : ws_.springs) {
    add_point_inertia(e.stiffness / shift_, e.offset, d.inertia_art[e.bone]);
  }
  for (const auto& [b, K] : ws_.couples) d.inertia_art[b].A += K / shift_;
}

// the negative eigenvalues of a joint's pivot from its (symmetric) inverse: a ball's 3x3; a
// hinge's or universal's on its axes, S^T P S = (S^T D S)^-1 (1x1 or 2x2: P's eigenvalues of the
// locked directions are zeros, which round-off would put on either side)
int ModeOperators::negative_pivots(JointType type, int i, const Mat3& inverse) const {
  if (type == JointType::kBall) {
    Eigen::SelfAdjointEigenSolver<Mat3> eig3;
    eig3.compute(inverse, Eigen::EigenvaluesOnly);
    return static_cast<int>((eig3.eigenvalues().array() < 0.0).count());
  }
  const Vec3& s0 = ws_.articulated.axis0_world[i];
  const Vec3& s1 = ws_.articulated.axis1_world[i];
  const double a = s0.dot(inverse * s0);
  if (type == JointType::kHinge) return a < 0.0 ? 1 : 0;
  const double b = s0.dot(inverse * s1), c = s1.dot(inverse * s1);
  // a symmetric 2x2's eigenvalues: both negative (det > 0, trace < 0), one (det < 0), or none
  const double det = a * c - b * b;
  return det < 0.0 ? 1 : (a + c < 0.0 ? 2 : 0);
}

// H = M - K / sigma (the shift -sigma) is -(K - sigma M) / sigma, so the modes below sigma are
// H's positive eigenvalues: nv minus the negative eigenvalues of H's pivots (Sylvester; the
// pivots of the backward pass, whose congruence H = L diag(pivots) L^T the header cites)
int ModeOperators::count_below(double sigma) {
  const double saved = shift_;
  set_shift(-sigma);
  load_inertias();
  ArticulatedBodyData& d = ws_.articulated;
  articulated_backward_pass(rig_, d);
  int negative = 0;
  for (int i = 1; i < rig_.nbone; ++i) {
    const JointType type = rig_.joint_type(i, locked_);
    if (!turns(type)) continue;  // a weld has no pivot
    // D^-1 has D's signs; K is symmetric, so D is up to round-off
    negative += negative_pivots(type, i, 0.5 * (d.D_inv[i] + d.D_inv[i].transpose()));
  }
  // the root's pivot: a free root's 6x6, a pinned root's ball block (its projector), none for a
  // fixed root
  const JointType root = rig_.joint_type(0, locked_);
  if (root == JointType::kFree) {
    Mat6 root6 = d.inertia_art[0].matrix();
    if (d.joint_blocks) root6.bottomLeftCorner<3, 3>() = d.inertia_lower[0];
    const Eigen::SelfAdjointEigenSolver<Mat6> eig6(0.5 * (root6 + root6.transpose()),
                                                   Eigen::EigenvaluesOnly);
    negative += static_cast<int>((eig6.eigenvalues().array() < 0.0).count());
  } else if (turns(root)) {
    Mat3 D0 = d.inertia_art[0].A + (d.joint_blocks ? d.joint_block[0] : Mat3::Zero());
    if (root != JointType::kBall) {
      D0 = axis_projector(D0, d.axis0_world[0], d.axis1_world[0], root == JointType::kHinge);
    }
    negative += negative_pivots(root, 0, 0.5 * (D0 + D0.transpose()));
  }
  set_shift(saved);
  return nv_ - negative;
}

void ModeOperators::solve(const VecX& b, VecX& x) {
  const int n = rig_.nbone;
  ArticulatedBodyData& d = ws_.articulated;
  // b as external torques: b_i on bone i, -b_i on its parent (bias force = -external wrench)
  load_inertias();
  const bool free_root = rig_.joint_type(0, locked_) == JointType::kFree;
  if (free_root) {
    d.bias_force[0] << -b.segment<3>(3), -b.head<3>();
  } else {
    d.bias_force[0].head<3>() -= rate(0, b);
  }
  for (int i = 1; i < n; ++i) {
    const Vec3 torque = rate(i, b);  // S b: zero for a weld
    d.bias_force[i].head<3>() -= torque;
    d.bias_force[rig_.bone_joint_parent[i]].head<3>() += torque;
  }
  // (M + K / s) a = b, so x = a / s
  articulated_backward_pass(rig_, d);
  articulated_forward_pass(rig_, body_motion(state_), d);
  const double inv = 1.0 / shift_;
  x.resize(nv_);
  if (free_root) {
    x.head<3>() = inv * d.accel_spatial[0].tail<3>();
    x.segment<3>(3) = inv * d.accel_spatial[0].head<3>();
  } else {
    put_torque(0, inv * d.accel_spatial[0].head<3>(), false, x);
  }
  for (int i = 1; i < n; ++i) {
    const Vec3 alpha_rel =
        d.accel_spatial[i].head<3>() - d.accel_spatial[rig_.bone_joint_parent[i]].head<3>();
    put_torque(i, inv * alpha_rel, false, x);  // S^T of the relative acceleration
  }
}

// D1's diagonal in the dense path's coordinates: the root's translations 2 n (every head and
// tail), and per rotational axis a about its pivot o, sum over the ends p it moves of
// |a x (p - o)|^2 = tr(Q) - a^T Q a, Q = sum (p - o)(p - o)^T over the joint's subtree
// (moments shifted from child to parent: d = o_child - o, Q += Q_c + S_c d^T + d S_c^T
// + N_c d d^T, S += S_c + N_c d)
void ModeOperators::compute_end_damper_scale() {
  const int n = rig_.nbone;
  const BoneFrames& f = state_.frames;
  std::vector<Mat3>& Q = ws_.second_moment;
  std::vector<Vec3>& S = ws_.first_moment;
  std::vector<double>& N = ws_.ends;
  for (int i = 0; i < n; ++i) {
    S[i] = f.tail_world[i] - f.head_world[i];  // the head adds 0 about itself
    Q[i] = S[i] * S[i].transpose();
    N[i] = 2.0;
  }
  const JointType root = rig_.joint_type(0, locked_);
  double scale = root == JointType::kFree ? 2.0 * n : 0.0;
  const auto shift = [&](int c, const Vec3& dv, Mat3& Qo, Vec3& So) {
    Qo += Q[c] + S[c] * dv.transpose() + dv * S[c].transpose() + N[c] * dv * dv.transpose();
    So += S[c] + N[c] * dv;
  };
  // a ball's axes are its bone's local axes (the dense coordinates), a hinge's its own
  const auto axes_max = [&](const Mat3& Qj, int bone) {
    Mat3 axes;
    const JointType type = rig_.joint_type(bone, locked_);
    const int count = type == JointType::kBall || type == JointType::kFree
                          ? 3
                          : joint_axes(type, ws_.articulated, bone, axes);
    for (int k = 0; k < count; ++k) {
      const Vec3 a = count == 3 ? Vec3(f.orient_world[bone] * Vec3::Unit(k)) : Vec3(axes.col(k));
      scale = std::max(scale, Qj.trace() - a.dot(Qj * a));
    }
  };
  // a weld's ends move with its joint parent: they join that joint's moments
  for (int i = n - 1; i > 0; --i) {
    if (turns(rig_.joint_type(i, locked_))) axes_max(Q[i], i);
    const int p = rig_.bone_joint_parent[i];
    shift(i, f.head_world[i] - f.head_world[p], Q[p], S[p]);
    N[p] += N[i];
  }
  if (root == JointType::kFree) {
    // the free root turns about its centre of mass
    Mat3 Q0 = Mat3::Zero();
    Vec3 S0 = Vec3::Zero();
    shift(0, f.head_world[0] - state_.com_world[0], Q0, S0);
    axes_max(Q0, 0);
  } else if (turns(root)) {
    axes_max(Q[0], 0);  // a pinned root turns about its head
  }
  end_damper_scale_ = scale;
}

}  // namespace physik
