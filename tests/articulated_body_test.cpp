// The articulated-body algorithm (physik/engine/articulated_body.h) against a dense solve
// M(q) qdd = tau - C(q, qdot) assembled independently (tests/dense_dynamics.h): M = sum_b J_b^T
// diag(I_b, m_b) J_b from body Jacobians, C from a classical (not spatial) Newton-Euler recursion
// of the velocity- product accelerations; on random trees with random shapes, masses, inertias,
// poses, velocities and forces. Also: the world view rebuilt from the joint state equals forward
// kinematics and J qdot, and the extension points (extra body inertia, joint blocks) add J^T X J
// and R^T K R to M.
#include "physik/engine/articulated_body.h"

#include <random>

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include "physik/engine/integrate_joint_space.h"
#include "physik/engine/state.h"
#include "tests/dense_dynamics.h"
#include "tests/test_util.h"

namespace physik {
namespace {

// the dense reference (body Jacobians, M(q), tau - C): tests/dense_dynamics.h, shared with the
// implicit step's tests
using namespace dense;

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
    articulated_accelerations(t.rig, body_motion(t.s), t.s.joint_space.articulated);
    const MatX M = mass_matrix(t.rig, t.s);
    const VecX expected = M.ldlt().solve(generalised_force(t.rig, t.s));
    const VecX got = aba_qacc(t.rig, t.s.joint_space.articulated);
    const double err =
        (got - expected).cwiseAbs().maxCoeff() / std::max(1.0, expected.cwiseAbs().maxCoeff());
    worst = std::max(worst, err);
    EXPECT_LT(err, 1e-10) << "bones " << n << " trial " << trial;
  }
  RecordProperty("worst_relative_error", std::to_string(worst));
}

// rig.h "Locked axes": hinges, universal joints (two hinges in sequence) and welds by locks, with
// locks at zero and away from it, in the recursion (the P of articulated_body.h) and in the dense
// reference (their axes' columns, the universal's first axis turning with the parent)
TEST(ArticulatedBody, HingesAndUniversalJointsEqualADenseSolveOnRandomTrees) {
  std::mt19937 rng(23);
  double worst = 0.0;
  int hinges = 0, universals = 0, welds = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const int n = 2 + trial % 12;
    RandomTree t = random_tree(rng, n, true, true);
    for (int i = 1; i < n; ++i) {
      hinges += t.rig.bone_joint_type[i] == JointType::kHinge;
      universals += t.rig.bone_joint_type[i] == JointType::kUniversal;
      welds += t.rig.bone_joint_type[i] == JointType::kWeld;
    }
    t.s.joint_space.articulated.torque_per_omega = trial % 3 == 0 ? -5.0 : 0.0;
    articulated_accelerations(t.rig, body_motion(t.s), t.s.joint_space.articulated);
    const MatX M = mass_matrix(t.rig, t.s);
    const VecX expected = M.ldlt().solve(generalised_force(t.rig, t.s));
    const VecX got = aba_qacc(t.rig, t.s.joint_space.articulated);
    const double err =
        (got - expected).cwiseAbs().maxCoeff() / std::max(1.0, expected.cwiseAbs().maxCoeff());
    worst = std::max(worst, err);
    EXPECT_LT(err, 1e-10) << "bones " << n << " trial " << trial;
  }
  EXPECT_GT(hinges, 50);
  EXPECT_GT(universals, 50);
  EXPECT_GT(welds, 50);
  RecordProperty("worst_relative_error", std::to_string(worst));
}

TEST(ArticulatedBody, HingedWorldViewEqualsForwardKinematicsAndJacobianVelocities) {
  std::mt19937 rng(29);
  for (int trial = 0; trial < 20; ++trial) {
    RandomTree t = random_tree(rng, 2 + trial % 9, true, true);
    const Rig& rig = t.rig;
    const SimState& s = t.s;
    Pose pose = s.pose;
    pose.root_head_world = s.frames.head_world[0];
    const BoneFrames fk = forward_kinematics(rig, pose);
    const VecX qd = qvel(rig, s);
    MatX Jw, Jv;
    for (int i = 0; i < rig.nbone; ++i) {
      EXPECT_TRUE(test::near(s.frames.tail_world[i], fk.tail_world[i], 1e-12));
      EXPECT_LT(test::angle_between(s.frames.orient_world[i], fk.orient_world[i]), 1e-12);
      jacobians(rig, s, i, Jw, Jv);
      EXPECT_TRUE(test::near(s.omega_world[i], Jw * qd, 1e-12));
      EXPECT_TRUE(test::near(s.vel_world[i], Jv * qd, 1e-12));
    }
  }
}

// a joint block K (world, on the relative rate) adds S^T K S to a hinge's own coordinates
TEST(ArticulatedBody, JointBlocksOnHingesAddTheirProjection) {
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    RandomTree t = random_tree(rng, 3 + trial % 8, false, true);
    const Rig& rig = t.rig;
    ArticulatedBodyData& d = t.s.joint_space.articulated;
    articulated_velocity_pass(rig, body_motion(t.s), d);
    MatX M = mass_matrix(rig, t.s);
    for (int b = 1; b < rig.nbone; ++b) {
      Mat3 B = Mat3::Random();
      Mat3 K = B * B.transpose() + 0.1 * Mat3::Identity();
      if (trial % 2) K += skew(Vec3(u(rng), u(rng), u(rng)));
      d.joint_block[b] = K;
      d.joint_blocks = true;
      const int k = coordinates(rig, b);
      const MatX S = joint_axes(rig, t.s, b).leftCols(k);
      M.block(dof(rig, b), dof(rig, b), k, k) += S.transpose() * K * S;
    }
    articulated_backward_pass(rig, d);
    articulated_forward_pass(rig, body_motion(t.s), d);
    const VecX expected = M.partialPivLu().solve(generalised_force(rig, t.s));
    const VecX got = aba_qacc(rig, d);
    EXPECT_LT((got - expected).cwiseAbs().maxCoeff(),
              1e-10 * std::max(1.0, expected.cwiseAbs().maxCoeff()))
        << "trial " << trial;
  }
}

TEST(ArticulatedBody, BallPassKeepsTheInertiasExactlySymmetric) {
  // without joint blocks the pass builds A, C, D^-1 (and the rigid R diag(I) R^T) as symmetric
  // matrices, upper triangle mirrored: every articulated inertia's A and C, every pivot's
  // inverse, equal their transposes bit for bit, on trees whose inertias are general
  std::mt19937 rng(17);
  for (int trial = 0; trial < 20; ++trial) {
    RandomTree t = random_tree(rng, 2 + trial % 10, true);
    ArticulatedBodyData& d = t.s.joint_space.articulated;
    articulated_accelerations(t.rig, body_motion(t.s), d);
    for (int i = 0; i < t.rig.nbone; ++i) {
      EXPECT_EQ(d.inertia_com_world[i], d.inertia_com_world[i].transpose()) << i;
      EXPECT_EQ(d.inertia_art[i].A, d.inertia_art[i].A.transpose()) << i;
      EXPECT_EQ(d.inertia_art[i].C, d.inertia_art[i].C.transpose()) << i;
      if (i > 0 && t.rig.bone_joint_type[i] == JointType::kBall) {
        EXPECT_EQ(d.D_inv[i], d.D_inv[i].transpose()) << i;
        EXPECT_LT((d.D_inv[i] * d.inertia_art[i].A - Mat3::Identity()).norm(), 1e-12) << i;
      }
    }
  }
}

TEST(ArticulatedBody, RotationalDamperAndGyroscopicCancellationMatchTheDenseSolve) {
  // the factor f's torque I (f - 1) w / dt and the gyroscopic-off switch as external torques
  std::mt19937 rng(13);
  for (int trial = 0; trial < 20; ++trial) {
    RandomTree t = random_tree(rng, 1 + trial % 9, true);
    t.s.joint_space.articulated.torque_per_omega = -10.0;
    t.s.joint_space.articulated.cancel_gyroscopic = trial % 2 == 0;
    articulated_accelerations(t.rig, body_motion(t.s), t.s.joint_space.articulated);
    const VecX expected = mass_matrix(t.rig, t.s).ldlt().solve(generalised_force(t.rig, t.s));
    const VecX got = aba_qacc(t.rig, t.s.joint_space.articulated);
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
    articulated_accelerations(t.rig, body_motion(t.s), t.s.joint_space.articulated);
    const VecX expected = mass_matrix(t.rig, t.s).ldlt().solve(generalised_force(t.rig, t.s));
    const VecX got = aba_qacc(t.rig, t.s.joint_space.articulated);
    ASSERT_GT(expected.norm(), 1e-3);  // the velocities really act
    EXPECT_LT((got - expected).cwiseAbs().maxCoeff(), 1e-10 * std::max(1.0, expected.norm()));
  }
}

TEST(ArticulatedBody, ExtraBodyInertiaAndJointBlocksAddToTheMassMatrix) {
  // at rest: (M + sum_b Js_b^T X_b Js_b + blockdiag(R_i^T K_i R_i)) qdd = tau, where Js_b maps
  // qdot to body b's spatial velocity about its point o_b and K_i is joint i's block (world axes);
  // on odd trials K_i has an antisymmetric part as large as its symmetric one (the paper's torsion
  // torque's tangent), so the articulated inertias are general 6x6 matrices
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    const bool unsymmetric = trial % 2 == 1;
    RandomTree t = random_tree(rng, 2 + trial % 8, false);
    const Rig& rig = t.rig;
    ArticulatedBodyData& d = t.s.joint_space.articulated;
    articulated_velocity_pass(rig, body_motion(t.s), d);
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
      Mat3 K = B * B.transpose() + 0.1 * Mat3::Identity();
      if (unsymmetric) K += skew(Vec3(u(rng), u(rng), u(rng)));
      d.joint_block[b] = K;
      d.joint_blocks = true;
      const Mat3 R = t.s.frames.orient_world[b].toRotationMatrix();
      M.block<3, 3>(dof(rig, b), dof(rig, b)) += R.transpose() * K * R;
    }
    articulated_backward_pass(rig, d);
    articulated_forward_pass(rig, body_motion(t.s), d);
    ASSERT_EQ((M - M.transpose()).norm() > 1e-3, unsymmetric && rig.nbone > 1) << "trial " << trial;
    const VecX expected = M.partialPivLu().solve(generalised_force(rig, t.s));
    const VecX got = aba_qacc(rig, d);
    EXPECT_LT((got - expected).cwiseAbs().maxCoeff(),
              1e-10 * std::max(1.0, expected.cwiseAbs().maxCoeff()))
        << "trial " << trial << (unsymmetric ? " (unsymmetric blocks)" : "");
  }
}

}  // namespace
}  // namespace physik
