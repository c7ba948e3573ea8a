// The articulated-body algorithm (physik/engine/articulated_body.h) against a dense solve
// M(q) qdd = tau - C(q, qdot) assembled here independently: M = sum_b J_b^T diag(I_b, m_b) J_b
// from body Jacobians, C from a classical (not spatial) Newton-Euler recursion of the velocity-
// product accelerations; on random trees with random shapes, masses, inertias, poses, velocities
// and forces. Also: the world view rebuilt from the joint state equals forward kinematics and
// J qdot, and the extension points (extra body inertia, joint blocks) add J^T X J and R^T K R to M.
#include "physik/engine/articulated_body.h"

#include <random>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "physik/engine/integrate_joint_space.h"
#include "physik/engine/state.h"
#include "tests/test_util.h"

namespace physik {
namespace {

using MatX = Eigen::MatrixXd;
using VecX = Eigen::VectorXd;

struct RandomTree {
  Rig rig;
  SimState s;
};

Vec3 random_unit(std::mt19937& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  return Vec3(g(rng), g(rng), g(rng)).normalized();
}

// a random tree of n bones, each child's head at a random earlier bone's tail
Rig random_rig(std::mt19937& rng, int n) {
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

// random joint state (poses, velocities) and forces; the world view from the joint state
RandomTree random_tree(std::mt19937& rng, int n, bool moving) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  RandomTree t;
  t.rig = random_rig(rng, n);
  SimState& s = t.s;
  s.pose = rest_pose(t.rig);
  forward_kinematics(t.rig, s.pose, s.frames);
  s.com_world.assign(n, Vec3::Zero());
  s.vel_world.assign(n, Vec3::Zero());
  s.omega_world.assign(n, Vec3::Zero());
  s.force_world.assign(n, Vec3::Zero());
  s.torque_world.assign(n, Vec3::Zero());
  init_joint_space(t.rig, s);
  for (int i = 1; i < n; ++i) {
    s.pose.bone_local_rotation[i] = Quat(Eigen::AngleAxisd(3.0 * u(rng), random_unit(rng)));
  }
  s.root_com_world = 3.0 * Vec3(u(rng), u(rng), u(rng));
  s.root_orient_world = Quat(Eigen::AngleAxisd(3.0 * u(rng), random_unit(rng)));
  const double speed = moving ? 2.0 : 0.0;
  s.root_vel_world = speed * Vec3(u(rng), u(rng), u(rng));
  for (int i = 0; i < n; ++i) s.joint_vel_local[i] = speed * Vec3(u(rng), u(rng), u(rng));
  world_from_joint_space(t.rig, s);
  for (int i = 0; i < n; ++i) {
    s.force_world[i] = 5.0 * Vec3(u(rng), u(rng), u(rng));
    s.torque_world[i] = 5.0 * Vec3(u(rng), u(rng), u(rng));
  }
  return t;
}

int nv(const Rig& rig) { return 6 + 3 * (rig.nbone - 1); }
int dof(int bone) { return bone == 0 ? 3 : 3 + 3 * bone; }  // first rotational dof of a bone

bool in_subtree(const Rig& rig, int bone, int root) {
  for (int b = bone; b >= 0; b = rig.bone_parent[b]) {
    if (b == root) return true;
  }
  return false;
}

// body b's Jacobians: w_b = Jw qdot, v_com_b = Jv qdot (MuJoCo's qvel: root v world, root w
// local, ball u local); each column is the motion of a unit rate about that dof's axis and point
void jacobians(const Rig& rig, const SimState& s, int b, MatX& Jw, MatX& Jv) {
  Jw.setZero(3, nv(rig));
  Jv.setZero(3, nv(rig));
  Jv.leftCols<3>().setIdentity();
  for (int j = 0; j < rig.nbone; ++j) {
    if (!in_subtree(rig, b, j)) continue;
    const Vec3 pivot = j == 0 ? s.com_world[0] : s.frames.head_world[j];
    for (int k = 0; k < 3; ++k) {
      const Vec3 axis = s.frames.orient_world[j] * Vec3::Unit(k);
      Jw.col(dof(j) + k) = axis;
      Jv.col(dof(j) + k) = axis.cross(s.com_world[b] - pivot);
    }
  }
}

VecX qvel(const Rig& rig, const SimState& s) {
  VecX q(nv(rig));
  q.head<3>() = s.root_vel_world;
  for (int i = 0; i < rig.nbone; ++i) q.segment<3>(dof(i)) = s.joint_vel_local[i];
  return q;
}

Mat3 inertia(const Rig& rig, const SimState& s, int i) {
  const Mat3 R = s.frames.orient_world[i].toRotationMatrix();
  return R * rig.bone_inertia_local[i].asDiagonal() * R.transpose();
}

// M = sum_b Jw^T I Jw + Jv^T m Jv
MatX mass_matrix(const Rig& rig, const SimState& s) {
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
//   alpha_i = alpha_p + w_i x w_rel,   a_head = a_p + alpha_p x d + w_p x (w_p x d),
//   a_i = a_head + alpha_i x e + w_i x (w_i x e)        d = head_i - com_p,  e = com_i - head_i
VecX generalised_force(const Rig& rig, const SimState& s) {
  const int n = rig.nbone;
  std::vector<Vec3> alpha(n, Vec3::Zero()), acc(n, Vec3::Zero());
  for (int i = 1; i < n; ++i) {
    const int p = rig.bone_parent[i];
    const Vec3 w_rel = s.omega_world[i] - s.omega_world[p];
    alpha[i] = alpha[p] + s.omega_world[i].cross(w_rel);
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
    Vec3 T = s.torque_world[b] + s.articulated.torque_per_omega * (I * w) - I * alpha[b] -
             w.cross(I * w);
    if (s.articulated.cancel_gyroscopic) T += w.cross(I * w);
    Q += Jv.transpose() * F + Jw.transpose() * T;
  }
  return Q;
}

VecX aba_qacc(const Rig& rig, const ArticulatedBodyData& d) {
  VecX q(nv(rig));
  q.head<3>() = d.root_accel_world;
  for (int i = 0; i < rig.nbone; ++i) q.segment<3>(dof(i)) = d.joint_accel_local[i];
  return q;
}

TEST(ArticulatedBody, WorldViewEqualsForwardKinematicsAndJacobianVelocities) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 20; ++trial) {
    RandomTree t = random_tree(rng, 1 + trial % 9, true);
    const Rig& rig = t.rig;
    const SimState& s = t.s;
    Pose pose = s.pose;  // FK of the same joint state from the root's head
    pose.root_head_world = s.frames.head_world[0];
    const BoneFrames fk = forward_kinematics(rig, pose);
    const VecX qd = qvel(rig, s);
    MatX Jw, Jv;
    for (int i = 0; i < rig.nbone; ++i) {
      EXPECT_TRUE(test::near(s.frames.head_world[i], fk.head_world[i], 1e-12));
      EXPECT_TRUE(test::near(s.frames.tail_world[i], fk.tail_world[i], 1e-12));
      EXPECT_LT(test::angle_between(s.frames.orient_world[i], fk.orient_world[i]), 1e-12);
      EXPECT_TRUE(test::near(s.com_world[i], 0.5 * (fk.head_world[i] + fk.tail_world[i]), 1e-12));
      jacobians(rig, s, i, Jw, Jv);
      EXPECT_TRUE(test::near(s.omega_world[i], Jw * qd, 1e-12));
      EXPECT_TRUE(test::near(s.vel_world[i], Jv * qd, 1e-12));
    }
  }
}

TEST(ArticulatedBody, AccelerationsEqualADenseSolveOnRandomTrees) {
  std::mt19937 rng(5);
  double worst = 0.0;
  for (int trial = 0; trial < 60; ++trial) {
    const int n = 1 + trial % 12;
    RandomTree t = random_tree(rng, n, true);
    articulated_accelerations(t.rig, t.s, t.s.articulated);
    const MatX M = mass_matrix(t.rig, t.s);
    const VecX expected = M.ldlt().solve(generalised_force(t.rig, t.s));
    const VecX got = aba_qacc(t.rig, t.s.articulated);
    const double err = (got - expected).cwiseAbs().maxCoeff() /
                       std::max(1.0, expected.cwiseAbs().maxCoeff());
    worst = std::max(worst, err);
    EXPECT_LT(err, 1e-10) << "bones " << n << " trial " << trial;
  }
  RecordProperty("worst_relative_error", std::to_string(worst));
}

TEST(ArticulatedBody, RotationalDamperAndGyroscopicCancellationMatchTheDenseSolve) {
  // the factor f's torque I (f - 1) w / dt and the gyroscopic-off switch as external torques
  std::mt19937 rng(13);
  for (int trial = 0; trial < 20; ++trial) {
    RandomTree t = random_tree(rng, 1 + trial % 9, true);
    t.s.articulated.torque_per_omega = -10.0;
    t.s.articulated.cancel_gyroscopic = trial % 2 == 0;
    articulated_accelerations(t.rig, t.s, t.s.articulated);
    const VecX expected = mass_matrix(t.rig, t.s).ldlt().solve(generalised_force(t.rig, t.s));
    const VecX got = aba_qacc(t.rig, t.s.articulated);
    EXPECT_LT((got - expected).cwiseAbs().maxCoeff(),
              1e-10 * std::max(1.0, expected.cwiseAbs().maxCoeff()));
  }
}

TEST(ArticulatedBody, VelocityProductsAloneMatchTheDenseSolve) {
  // no external forces: qdd = -M^-1 C, all from the velocity products
  std::mt19937 rng(9);
  for (int trial = 0; trial < 20; ++trial) {
    RandomTree t = random_tree(rng, 2 + trial % 8, true);
    for (int i = 0; i < t.rig.nbone; ++i) {
      t.s.force_world[i].setZero();
      t.s.torque_world[i].setZero();
    }
    articulated_accelerations(t.rig, t.s, t.s.articulated);
    const VecX expected = mass_matrix(t.rig, t.s).ldlt().solve(generalised_force(t.rig, t.s));
    const VecX got = aba_qacc(t.rig, t.s.articulated);
    ASSERT_GT(expected.norm(), 1e-3);  // the velocities really act
    EXPECT_LT((got - expected).cwiseAbs().maxCoeff(), 1e-10 * std::max(1.0, expected.norm()));
  }
}

TEST(ArticulatedBody, ExtraBodyInertiaAndJointBlocksAddToTheMassMatrix) {
  // at rest: (M + sum_b Js_b^T X_b Js_b + blockdiag(R_i^T K_i R_i)) qdd = tau, where Js_b maps
  // qdot to body b's spatial velocity about its point o_b and K_i is joint i's block (world axes)
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    RandomTree t = random_tree(rng, 2 + trial % 8, false);
    const Rig& rig = t.rig;
    ArticulatedBodyData& d = t.s.articulated;
    articulated_velocity_pass(rig, t.s, d);
    MatX M = mass_matrix(rig, t.s);
    MatX Jw, Jv;
    for (int b = 0; b < rig.nbone; ++b) {
      Eigen::Matrix<double, 6, 6> A = Eigen::Matrix<double, 6, 6>::Random();
      const Mat6 X = A * A.transpose() * 0.3;  // symmetric positive semi-definite
      d.inertia_art[b].add(X);
      jacobians(rig, t.s, b, Jw, Jv);  // at the centre of mass; move the linear part to o_b
      MatX Js(6, nv(rig));
      Js.topRows<3>() = Jw;
      for (int c = 0; c < nv(rig); ++c) {
        const Vec3 w = Jw.col(c);
        Js.col(c).tail<3>() = Vec3(Jv.col(c)) - w.cross(t.s.com_world[b] - d.point_world[b]);
      }
      M += Js.transpose() * X * Js;
      if (b == 0) continue;
      Mat3 B = Mat3::Random();
      const Mat3 K = B * B.transpose() + 0.1 * Mat3::Identity();
      d.joint_block[b] = K;
      d.joint_blocks = true;
      const Mat3 R = t.s.frames.orient_world[b].toRotationMatrix();
      M.block<3, 3>(dof(b), dof(b)) += R.transpose() * K * R;
    }
    articulated_backward_pass(rig, d);
    articulated_forward_pass(rig, t.s, d);
    const VecX expected = M.ldlt().solve(generalised_force(rig, t.s));
    const VecX got = aba_qacc(rig, d);
    EXPECT_LT((got - expected).cwiseAbs().maxCoeff(),
              1e-10 * std::max(1.0, expected.cwiseAbs().maxCoeff()));
  }
}

TEST(ArticulatedBody, ShiftInertiaIsTheCongruenceOfATranslation) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Mat6 I = spatial_inertia(1.7, Vec3(0.3, 0.5, 0.4).asDiagonal(), Vec3(0.2, -0.4, 0.9)).matrix();
  const Vec3 r(u(rng), u(rng), u(rng));
  Mat6 X = Mat6::Identity();  // motion transform parent point -> child point: v - r x w
  X.bottomLeftCorner<3, 3>() = -skew(r);
  SpatialInertia Is;
  Is.add(I);
  EXPECT_LT((shift_inertia(Is, r).matrix() - X.transpose() * I * X).cwiseAbs().maxCoeff(), 1e-14);
  // a rigid body's inertia moved from its point o to o - r is its inertia about the new point
  EXPECT_LT((shift_inertia(Is, r).matrix() -
             spatial_inertia(1.7, Vec3(0.3, 0.5, 0.4).asDiagonal(), Vec3(0.2, -0.4, 0.9) + r)
                 .matrix())
                .cwiseAbs()
                .maxCoeff(),
            1e-14);
}

}  // namespace
}  // namespace physik
