// The shared IK interface (ik_solver.h): goal bookkeeping, limits clamping, the colinearity bump,
// bad input, and the cross-check that all solvers agree on reachable goals.
#include "physik/ik/ik_solver.h"

#include <gtest/gtest.h>

#include "physik/model/errors.h"
#include "physik/model/rig_generators.h"
#include "tests/ik_test_util.h"

namespace physik {
namespace {

const IkMethod kAll[] = {IkMethod::kFabrik,
                         IkMethod::kCcd,
                         IkMethod::kJacobianTranspose,
                         IkMethod::kDampedLeastSquares,
                         IkMethod::kMassSpring,
                         IkMethod::kRotation};

TEST(IkSolver, NamesRoundTrip) {
  for (IkMethod m : kAll) {
    IkMethod back;
    ASSERT_TRUE(ik_method_from_string(to_string(m), back));
    EXPECT_EQ(back, m);
  }
  IkMethod x;
  EXPECT_FALSE(ik_method_from_string("newton", x));
}

TEST(IkSolver, ReachIsThePathLengthToTheEffector) {
  const Rig rig = make_chain_rig(4, 0.5);
  EXPECT_DOUBLE_EQ(chain_reach(rig, {{3, 1.0, Vec3::Zero()}}), 2.0);
  EXPECT_DOUBLE_EQ(chain_reach(rig, {{1, 0.5, Vec3::Zero()}}), 0.75);
  EXPECT_DOUBLE_EQ(chain_reach(rig, {{1, 0.5, Vec3::Zero()}, {2, 0.0, Vec3::Zero()}}), 1.0);
}

TEST(IkSolver, GoalsAreSortedInDfsOrderStably) {
  const std::vector<IkGoal> goals = {
      {5, 1, Vec3::Zero()}, {2, 1, Vec3::Zero()}, {5, 0, Vec3::Zero()}, {0, 1, Vec3::Zero()}};
  EXPECT_EQ(dfs_goal_order(goals), (std::vector<int>{3, 1, 0, 2}));
}

TEST(IkSolver, ClampProjectsTheRotationVectorOntoTheBox) {
  const Rig rig = load_rig(test::model_path("rigs/elbow.json"));  // forearm x in [-90, 0] deg
  const Quat q = quat_from_rotation_vector(Vec3(-2.0, 0.3, 0.0));
  const Vec3 v = rotation_vector(clamp_to_limits(rig, 1, q));
  EXPECT_TRUE(test::near(v, Vec3(-kPi / 2, 0.0, 0.0), 1e-12));
  // inside: unchanged
  const Quat inside = quat_from_rotation_vector(Vec3(-0.5, 0.0, 0.0));
  EXPECT_LT(clamp_to_limits(rig, 1, inside).angularDistance(inside), 1e-15);
}

TEST(IkSolver, ColinearJointsGetABumpWithinLimits) {
  const Rig rig = make_chain_rig(3);
  Pose pose = rest_pose(rig);
  const std::vector<char> active(3, 1);
  EXPECT_EQ(bump_colinear_joints(rig, active, 0.01, pose), 2);  // bones 1 and 2; the root has none
  EXPECT_NEAR(rotation_vector(pose.bone_local_rotation[1]).x(), 0.01, 1e-12);
  EXPECT_EQ(bump_colinear_joints(rig, active, 0.01, pose), 0);  // nothing colinear any more
  // elbow: x in [-90, 0] deg, so +0.01 is illegal and the bump goes the other way
  const Rig elbow = load_rig(test::model_path("rigs/elbow.json"));
  Pose ep = rest_pose(elbow);
  EXPECT_EQ(bump_colinear_joints(elbow, {1, 1}, 0.01, ep), 1);
  EXPECT_NEAR(rotation_vector(ep.bone_local_rotation[1]).x(), -0.01, 1e-12);
}

TEST(IkSolver, AStraightChainFoldsOntoItsOwnAxis) {
  // a target on the straight chain's own axis: the transpose step J^T e is exactly zero there
  // (every column a x r is normal to e), so only the colinearity bump gets the solvers moving
  const Rig rig = make_chain_rig(3);
  for (IkMethod m : kAll) {
    Pose pose = rest_pose(rig);
    const IkReport rep = solve_ik(m, rig, {{2, 1.0, Vec3(0, 0, 2)}}, pose);
    EXPECT_TRUE(rep.converged) << to_string(m) << " residual " << rep.residual;
  }
}

void expect_agreement(const Rig& rig, int hand, const std::vector<IkMethod>& methods) {
  std::mt19937 rng(5);
  for (int t = 0; t < 5; ++t) {
    const Vec3 target = forward_kinematics(rig, test::random_pose(rig, rng, 0.6)).tail_world[hand];
    std::vector<Vec3> tips;
    for (IkMethod m : methods) {
      Pose pose = rest_pose(rig);
      IkOptions opt;
      opt.max_iterations = 5000;
      const IkReport rep = solve_ik(m, rig, {{hand, 1.0, target}}, pose, opt);
      if (!rep.converged) {
        ADD_FAILURE() << to_string(m) << " did not reach target " << t << ": residual "
                      << rep.residual;
        continue;
      }
      tips.push_back(forward_kinematics(rig, pose).tail_world[hand]);
    }
    for (std::size_t a = 1; a < tips.size(); ++a) {
      EXPECT_TRUE(test::near(tips[a], tips[0], 2e-4 * chain_reach(rig, {{hand, 1, target}})));
    }
  }
}

TEST(IkSolver, AllSolversAgreeOnTheEffectorForReachableGoals) {
  expect_agreement(make_chain_rig(10), 9, {std::begin(kAll), std::end(kAll)});
}

TEST(IkSolver, AngleBasedSolversAgreeOnPinheadsHand) {
  // pinhead's locked collars and hinge elbows: the position-based solvers (FABRIK, mass-spring)
  // only meet limits by clamping, so they are compared on the free chain above
  const Rig rig = load_rig(test::model_path("rigs/pinhead.json"));
  expect_agreement(rig, rig.find_bone("hand.L"),
                   {IkMethod::kCcd, IkMethod::kJacobianTranspose, IkMethod::kDampedLeastSquares,
                    IkMethod::kRotation});
}

TEST(IkSolver, SeveralGoalsAreMetTogether) {
  // a mid-chain point and the tip of a free chain, targets from one pose, given out of DFS order
  const Rig rig = make_chain_rig(5);
  std::mt19937 rng(8);
  const BoneFrames f = forward_kinematics(rig, test::random_pose(rig, rng, 0.5));
  const std::vector<IkGoal> goals = {{4, 1.0, f.tail_world[4]}, {1, 0.5, point_on_bone(f, 1, 0.5)}};
  IkOptions opt;
  opt.max_iterations = 20000;
  for (IkMethod m : {IkMethod::kCcd, IkMethod::kJacobianTranspose, IkMethod::kDampedLeastSquares,
                     IkMethod::kMassSpring}) {
    Pose pose = rest_pose(rig);
    const IkReport rep = solve_ik(m, rig, goals, pose, opt);
    EXPECT_TRUE(rep.converged) << to_string(m) << ": " << rep.residual;
    ASSERT_EQ(rep.residuals.size(), 2u);
    EXPECT_LE(std::max(rep.residuals[0], rep.residuals[1]), rep.tolerance);
  }
  // FABRIK averages the wishes of the two goals (the guide's advice) and the rotation method
  // serves them in turn: both settle on a compromise. They get closer, never worse, and finite.
  std::vector<double> start;
  goal_residuals(forward_kinematics(rig, rest_pose(rig)), goals, start);
  for (IkMethod m : {IkMethod::kFabrik, IkMethod::kRotation}) {
    Pose pose = rest_pose(rig);
    const IkReport rep = solve_ik(m, rig, goals, pose, opt);
    EXPECT_TRUE(test::pose_is_finite(pose));
    EXPECT_LT(rep.residual, 0.5 * std::max(start[0], start[1])) << to_string(m);
  }
}

TEST(IkSolver, BadGoalsAreInputErrors) {
  const Rig rig = make_chain_rig(2);
  Pose pose = rest_pose(rig);
  EXPECT_THROW(solve_ik(IkMethod::kCcd, rig, {}, pose), InputError);
  EXPECT_THROW(solve_ik(IkMethod::kCcd, rig, {{2, 1.0, Vec3::Zero()}}, pose), InputError);
  EXPECT_THROW(solve_ik(IkMethod::kCcd, rig, {{1, 1.5, Vec3::Zero()}}, pose), InputError);
  EXPECT_THROW(solve_ik(IkMethod::kCcd, rig, {{1, 1.0, Vec3(NAN, 0, 0)}}, pose), InputError);
  Pose wrong;
  EXPECT_THROW(solve_ik(IkMethod::kCcd, rig, {{1, 1.0, Vec3::Zero()}}, wrong), InputError);
}

}  // namespace
}  // namespace physik
