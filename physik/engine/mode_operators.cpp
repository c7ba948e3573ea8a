#include "physik/engine/mode_operators.h"

#include <algorithm>

#include <Eigen/Eigenvalues>

#include "physik/engine/forces.h"
#include "physik/engine/implicit_elements.h"
#include "physik/engine/state.h"
#include "physik/engine/torsion_springs.h"

namespace physik {

namespace {

// a joint with a ball's three coordinates: every bone's but a weld's, a pinned root's too
inline bool is_ball(const Rig& rig, int bone) {
  return rig.bone_joint_type[bone] == JointType::kBall;
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
    : rig_(scene.rig), state_(s), ws_(ws) {
  const Rig& rig = scene.rig;
  const EngineParams& prm = scene.params;
  const int n = rig.nbone;
  nv_ = rig.nv;
  ArticulatedBodyData& d = ws.articulated;
  if (static_cast<int>(d.inertia_art.size()) != n) resize_articulated_data(n, d);
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
    d.point_world[i] =
        rig.bone_joint_type[i] == JointType::kFree ? s.com_world[i] : s.frames.head_world[i];
    d.bias_accel[i].setZero();
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
  switch (rig_.bone_joint_type[0]) {
    case JointType::kFree:
      V[0] << x.segment<3>(3), x.head<3>();
      break;
    case JointType::kBall:
      V[0] << x.head<3>(), Vec3::Zero();
      break;
    case JointType::kWeld:
      V[0].setZero();
      break;
  }
  for (int i = 1; i < n; ++i) {
    const int p = rig_.bone_joint_parent[i];
    const Vec3 r = d.point_world[i] - d.point_world[p];
    V[i].head<3>() = V[p].head<3>();
    if (is_ball(rig_, i)) V[i].head<3>() += x.segment<3>(rig_.bone_dofadr[i]);
    V[i].tail<3>() = V[p].tail<3>() - r.cross(Vec3(V[p].head<3>()));
  }
  element_wrenches(which);
  // wrenches inward; each ball's coordinate takes its subtree's torque about the joint
  for (int i = n - 1; i > 0; --i) {
    const int p = rig_.bone_joint_parent[i];
    const Vec3 r = d.point_world[i] - d.point_world[p];
    if (is_ball(rig_, i)) y.segment<3>(rig_.bone_dofadr[i]) = W[i].head<3>();
    W[p].head<3>() += W[i].head<3>() + r.cross(Vec3(W[i].tail<3>()));
    W[p].tail<3>() += W[i].tail<3>();
  }
  switch (rig_.bone_joint_type[0]) {
    case JointType::kFree:
      y.head<3>() = W[0].tail<3>();
      y.segment<3>(3) = W[0].head<3>();
      break;
    case JointType::kBall:
      y.head<3>() = W[0].head<3>();
      break;
    case JointType::kWeld:
      break;
  }
  if (which != Matrix::kStiffness) return;
  for (const auto& [b, K] : ws_.torsion) {
    const int a = rig_.bone_dofadr[b];
    y.segment<3>(a) += K * x.segment<3>(a);
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
  Eigen::SelfAdjointEigenSolver<Mat3> eig3;
  for (int i = 1; i < rig_.nbone; ++i) {
    if (!is_ball(rig_, i)) continue;  // a weld has no pivot
    // D^-1 has D's signs; K is symmetric, so D is up to round-off
    eig3.compute(0.5 * (d.D_inv[i] + d.D_inv[i].transpose()), Eigen::EigenvaluesOnly);
    negative += static_cast<int>((eig3.eigenvalues().array() < 0.0).count());
  }
  // the root's pivot: a free root's 6x6, a pinned root's 3x3 ball block, none for a fixed root
  if (rig_.bone_joint_type[0] == JointType::kFree) {
    Mat6 root = d.inertia_art[0].matrix();
    if (d.joint_blocks) root.bottomLeftCorner<3, 3>() = d.inertia_lower[0];
    const Eigen::SelfAdjointEigenSolver<Mat6> eig6(0.5 * (root + root.transpose()),
                                                   Eigen::EigenvaluesOnly);
    negative += static_cast<int>((eig6.eigenvalues().array() < 0.0).count());
  } else if (rig_.bone_joint_type[0] == JointType::kBall) {
    const Mat3 D0 = d.inertia_art[0].A + (d.joint_blocks ? d.joint_block[0] : Mat3::Zero());
    eig3.compute(0.5 * (D0 + D0.transpose()), Eigen::EigenvaluesOnly);
    negative += static_cast<int>((eig3.eigenvalues().array() < 0.0).count());
  }
  set_shift(saved);
  return nv_ - negative;
}

void ModeOperators::solve(const VecX& b, VecX& x) {
  const int n = rig_.nbone;
  ArticulatedBodyData& d = ws_.articulated;
  // b as external torques: b_i on bone i, -b_i on its parent (bias force = -external wrench)
  load_inertias();
  switch (rig_.bone_joint_type[0]) {
    case JointType::kFree:
      d.bias_force[0] << -b.segment<3>(3), -b.head<3>();
      break;
    case JointType::kBall:
      d.bias_force[0].head<3>() -= b.head<3>();
      break;
    case JointType::kWeld:
      break;
  }
  for (int i = 1; i < n; ++i) {
    if (!is_ball(rig_, i)) continue;
    const int a = rig_.bone_dofadr[i];
    d.bias_force[i].head<3>() -= b.segment<3>(a);
    d.bias_force[rig_.bone_joint_parent[i]].head<3>() += b.segment<3>(a);
  }
  // (M + K / s) a = b, so x = a / s
  articulated_backward_pass(rig_, d);
  articulated_forward_pass(rig_, body_motion(state_), d);
  const double inv = 1.0 / shift_;
  x.resize(nv_);
  switch (rig_.bone_joint_type[0]) {
    case JointType::kFree:
      x.head<3>() = inv * d.accel_spatial[0].tail<3>();
      x.segment<3>(3) = inv * d.accel_spatial[0].head<3>();
      break;
    case JointType::kBall:
      x.head<3>() = inv * d.accel_spatial[0].head<3>();
      break;
    case JointType::kWeld:
      break;
  }
  for (int i = 1; i < n; ++i) {
    if (!is_ball(rig_, i)) continue;
    x.segment<3>(rig_.bone_dofadr[i]) =
        inv * (d.accel_spatial[i].head<3>() - d.accel_spatial[rig_.bone_joint_parent[i]].head<3>());
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
  const JointType root = rig_.bone_joint_type[0];
  double scale = root == JointType::kFree ? 2.0 * n : 0.0;
  const auto shift = [&](int c, const Vec3& dv, Mat3& Qo, Vec3& So) {
    Qo += Q[c] + S[c] * dv.transpose() + dv * S[c].transpose() + N[c] * dv * dv.transpose();
    So += S[c] + N[c] * dv;
  };
  const auto axes_max = [&](const Mat3& Qj, int bone) {
    for (int k = 0; k < 3; ++k) {
      const Vec3 a = f.orient_world[bone] * Vec3::Unit(k);
      scale = std::max(scale, Qj.trace() - a.dot(Qj * a));
    }
  };
  // a weld's ends move with its joint parent: they join that joint's moments
  for (int i = n - 1; i > 0; --i) {
    if (is_ball(rig_, i)) axes_max(Q[i], i);
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
  } else if (root == JointType::kBall) {
    axes_max(Q[0], 0);  // a pinned root turns about its head
  }
  end_damper_scale_ = scale;
}

}  // namespace physik
