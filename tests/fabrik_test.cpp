// fabrik.cpp: the solver contract (ik_test_util.h) and what is particular to this solver.
#include <cmath>

#include <gtest/gtest.h>

#include "physik/model/rig_generators.h"
#include "tests/ik_test_util.h"

namespace physik {
namespace {

TEST(Fabrik, MeetsTheSolverContract) {
  test::expect_solver_contract(IkMethod::kFabrik);
}

}  // namespace
}  // namespace physik

namespace physik {
namespace {

TEST(Fabrik, OneBoneAimsExactlyInOneIteration) {
  // backward puts the tail on the target, forward aims the bone at it: exact for |t| = L
  const Rig rig = make_chain_rig(1, 2.0);
  const Vec3 target = 2.0 * Vec3(0.3, -0.5, 0.8).normalized();
  Pose pose = rest_pose(rig);
  const IkReport rep = solve_ik(IkMethod::kFabrik, rig, {{0, 1.0, target}}, pose);
  EXPECT_EQ(rep.iterations, 1);
  EXPECT_LT(rep.residual, 1e-12);
}

TEST(Fabrik, RecoveredRotationsKeepTheBoneLengthsAndTwist) {
  // rotations are recovered by the smallest turn in the rest frame: a bone whose direction is
  // already right is not turned at all, so an initial twist of the tip bone survives
  const Rig rig = make_chain_rig(2);
  Pose pose = rest_pose(rig);
  pose.bone_local_rotation[1] = Quat(Eigen::AngleAxisd(0.7, Vec3::UnitY()));  // pure twist
  const Vec3 target(0.0, 1.0, 1.0);  // bone 1 horizontal, bone 0 as is
  IkOptions opt;
  opt.colinear_bump = 0.0;  // a bump would add a swing before the solve
  const IkReport rep = solve_ik(IkMethod::kFabrik, rig, {{1, 1.0, target}}, pose, opt);
  EXPECT_EQ(rep.iterations, 1);
  const BoneFrames f = forward_kinematics(rig, pose);
  EXPECT_NEAR((f.tail_world[1] - f.head_world[1]).norm(), 1.0, 1e-12);
  // twist about the bone's own axis: the y part of the swing-twist decomposition
  const Quat q = pose.bone_local_rotation[1];
  const double twist = 2.0 * std::atan2(q.y(), q.w());
  EXPECT_NEAR(twist, 0.7, 1e-6);
}

}  // namespace
}  // namespace physik
