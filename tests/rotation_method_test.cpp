// rotation_method.cpp: the solver contract (ik_test_util.h) and what is particular to this solver.
#include <cmath>

#include <gtest/gtest.h>

#include "physik/model/joint_angles.h"
#include "physik/model/rig_generators.h"
#include "tests/ik_test_util.h"

namespace physik {
namespace {

TEST(Rotation, MeetsTheSolverContract) {
  test::expect_solver_contract(IkMethod::kRotation);
}

}  // namespace
}  // namespace physik

namespace physik {
namespace {

TEST(Rotation, SeedAsShippedVirtualBoneSocketsMeetTheContractToo) {
  IkOptions opt;
  opt.socket_mode = SocketMode::kVirtualBone;
  test::expect_solver_contract(IkMethod::kRotation, opt);
}

TEST(Rotation, ZeroDampingMovesOnlyTheSelectedBone) {
  const Rig rig = make_chain_rig(4);
  IkOptions opt;
  opt.rotation_damping = 0.0;
  opt.max_iterations = 50;
  Pose pose = rest_pose(rig);
  Pose start = pose;
  bump_colinear_joints(rig, std::vector<char>(4, 1), opt.colinear_bump, start);
  solve_ik(IkMethod::kRotation, rig, {{3, 1.0, Vec3(1.0, 0.5, 3.0)}}, pose, opt);
  for (int i = 0; i < 3; ++i) {
    EXPECT_LT(pose.bone_local_rotation[i].angularDistance(start.bone_local_rotation[i]), 1e-12);
  }
  EXPECT_GT(pose.bone_local_rotation[3].angularDistance(start.bone_local_rotation[3]), 0.1);
}

TEST(Rotation, DampingSpreadsTheMotionLessUpTheHierarchy) {
  // after one iteration the joint angle change falls off up the chain
  const Rig rig = make_chain_rig(4);
  IkOptions opt;
  opt.max_iterations = 1;
  opt.springiness = 0.0;
  opt.max_angle_step = 10.0;  // no cap, so the damping alone sets the amounts
  Pose pose = rest_pose(rig);
  Pose start = pose;
  bump_colinear_joints(rig, std::vector<char>(4, 1), opt.colinear_bump, start);
  solve_ik(IkMethod::kRotation, rig, {{3, 1.0, Vec3(2.0, 0.0, 2.5)}}, pose, opt);
  for (int i = 0; i < 3; ++i) {
    EXPECT_LT(pose.bone_local_rotation[i].angularDistance(start.bone_local_rotation[i]),
              pose.bone_local_rotation[i + 1].angularDistance(start.bone_local_rotation[i + 1]));
  }
}

Rig socket_rig() {
  // a shoulder-like socket: swing x in [-0.4, 0.4], z in [-0.2, 0.2], twist y in [-0.3, 0.3] rad
  std::vector<BoneSpec> s(2);
  s[0].name = "base";
  s[0].tail_world = Vec3(0, 0, 1);
  s[0].rest_frame_world = rest_frame_from_roll(s[0].head_world, s[0].tail_world, 0.0);
  s[1].name = "arm";
  s[1].parent = "base";
  s[1].head_world = Vec3(0, 0, 1);
  s[1].tail_world = Vec3(0, 0, 2);
  s[1].rest_frame_world = rest_frame_from_roll(s[1].head_world, s[1].tail_world, 0.0);
  s[1].limit[0] = {true, -0.4, 0.4};
  s[1].limit[1] = {true, -0.3, 0.3};
  s[1].limit[2] = {true, -0.2, 0.2};
  return build_rig(s, "test");
}

TEST(Rotation, EllipticalConePullsTheSwingOntoItsBoundary) {
  const Rig rig = socket_rig();
  const Quat q = quat_from_rotation_vector(Vec3(0.5, 0.0, 0.5));
  const Vec3 v = rotation_vector(clamp_to_cone(rig, 1, q, ConeShape::kElliptical));
  EXPECT_NEAR(std::pow(v.x() / 0.4, 2) + std::pow(v.z() / 0.2, 2), 1.0, 1e-9);
  EXPECT_NEAR(v.x() / v.z(), (0.5 / 0.4) / (0.5 / 0.2) * 0.4 / 0.2, 1e-9);  // radial in (u, w)
  // circular: the smaller half-range is the radius
  const Vec3 c = rotation_vector(clamp_to_cone(rig, 1, q, ConeShape::kCircular));
  EXPECT_NEAR(std::hypot(c.x(), c.z()), 0.2, 1e-9);
  // inside the cone: unchanged
  const Quat inside = quat_from_rotation_vector(Vec3(0.2, 0.0, 0.1));
  EXPECT_LT(clamp_to_cone(rig, 1, inside, ConeShape::kElliptical).angularDistance(inside), 1e-12);
}

TEST(Rotation, TwistIsClampedSeparatelyFromTheSwing) {
  const Rig rig = socket_rig();
  const Quat q = Quat(Eigen::AngleAxisd(0.1, Vec3::UnitX())) *
                 Quat(Eigen::AngleAxisd(0.8, Vec3::UnitY()));  // swing then twist
  const Quat c = clamp_to_cone(rig, 1, q, ConeShape::kElliptical);
  const Quat twist = Quat(c.w(), 0, c.y(), 0).normalized();
  EXPECT_NEAR(2.0 * std::atan2(twist.y(), twist.w()), 0.3, 1e-9);
  EXPECT_LT((c * twist.conjugate()).angularDistance(Quat(Eigen::AngleAxisd(0.1, Vec3::UnitX()))),
            1e-9);
}

TEST(Rotation, SolvesWithinTheEllipticalCone) {
  const Rig rig = socket_rig();
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  for (int t = 0; t < 20; ++t) {
    Pose pose = rest_pose(rig);
    solve_ik(IkMethod::kRotation, rig, {{1, 1.0, Vec3(u(rng), u(rng), 1.0 + u(rng))}}, pose);
    EXPECT_LE(max_limit_violation(rig, LockedAxes::kSprings, pose), 1e-9);
    const Quat q = pose.bone_local_rotation[1];
    const Quat twist = Quat(q.w(), 0, q.y(), 0).normalized();
    const Vec3 sv = rotation_vector(q * twist.conjugate());
    EXPECT_LE(std::pow(sv.x() / 0.4, 2) + std::pow(sv.z() / 0.2, 2), 1.0 + 1e-6);
  }
}

}  // namespace
}  // namespace physik
