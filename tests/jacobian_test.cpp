// jacobian.cpp: the solver contract for the transpose and DLS methods, with both Jacobians, and
// the Jacobians themselves against brute-force finite differences through FK.
#include <algorithm>

#include <gtest/gtest.h>

#include "physik/model/rig_generators.h"
#include "tests/ik_test_util.h"

namespace physik {
namespace {

TEST(JacobianTranspose, MeetsTheSolverContract) {
  test::expect_solver_contract(IkMethod::kJacobianTranspose);
}
TEST(DampedLeastSquares, MeetsTheSolverContract) {
  test::expect_solver_contract(IkMethod::kDampedLeastSquares);
}
TEST(DampedLeastSquares, MeetsTheSolverContractWithTheFiniteDifferenceJacobian) {
  IkOptions opt;
  opt.jacobian = JacobianKind::kFiniteDifference;
  test::expect_solver_contract(IkMethod::kDampedLeastSquares, opt);
}

}  // namespace
}  // namespace physik

namespace physik {
namespace {

TEST(Jacobian, AnalyticMemoisedAndBruteForceAgree) {
  const Rig rig = load_rig(test::model_path("rigs/pinhead.json"));
  std::mt19937 rng(3);
  const Pose pose = test::random_pose(rig, rng, 0.8);
  const BoneFrames f = forward_kinematics(rig, pose);
  IkProblem pb;
  pb.rig = &rig;
  const int l = rig.find_bone("hand.L"), r = rig.find_bone("forearm.R");
  pb.goals = {{r, 0.3, Vec3::Zero()}, {l, 1.0, Vec3::Zero()}};
  pb.active = active_bones(rig, pb.goals);
  std::vector<int> bones, axes;
  ik_dofs(rig, pb.active, true, bones, axes);
  Eigen::MatrixXd Ja, Jf;
  goal_jacobian(pb, f, bones, axes, JacobianKind::kAnalytic, 0.0, Ja);
  const double eps = 1e-6;
  goal_jacobian(pb, f, bones, axes, JacobianKind::kFiniteDifference, eps, Jf);
  EXPECT_LT((Ja - Jf).cwiseAbs().maxCoeff(), 10 * eps);
  // brute force: turn the bone's rest-frame axis, rerun FK
  for (std::size_t c = 0; c < bones.size(); ++c) {
    Pose p = pose;
    p.bone_local_rotation[bones[c]] =
        Quat(Eigen::AngleAxisd(eps, Vec3::Unit(axes[c]))) * p.bone_local_rotation[bones[c]];
    const BoneFrames g = forward_kinematics(rig, p);
    for (int k = 0; k < 2; ++k) {
      const Vec3 d = (point_on_bone(g, pb.goals[k].bone, pb.goals[k].alpha) -
                      point_on_bone(f, pb.goals[k].bone, pb.goals[k].alpha)) /
                     eps;
      EXPECT_TRUE(test::near(d, Ja.block<3, 1>(3 * k, c), 10 * eps)) << "column " << c;
    }
  }
  // locked axes (collars, hips) have no column; the elbow hinge has only its z column
  EXPECT_EQ(std::count(bones.begin(), bones.end(), rig.find_bone("collar.L")), 0);
  EXPECT_EQ(std::count(bones.begin(), bones.end(), rig.find_bone("forearm.L")), 1);
}

TEST(DampedLeastSquares, LargerLambdaTakesSmallerSteps) {
  // DLS shrinks the step as lambda grows: the first iteration moves the tip less
  const Rig rig = make_chain_rig(3);
  const Vec3 target(1.5, 0.5, 1.5);
  double previous = 1e9;
  for (double lambda : {0.01, 0.3, 1.0, 3.0}) {
    IkOptions opt;
    opt.lambda = lambda;
    opt.max_iterations = 1;
    opt.max_angle_step = 10.0;
    Pose pose = rest_pose(rig);
    Pose start = pose;
    bump_colinear_joints(rig, active_bones(rig, {{2, 1, target}}), opt.colinear_bump, start);
    solve_ik(IkMethod::kDampedLeastSquares, rig, {{2, 1.0, target}}, pose, opt);
    const double moved =
        (forward_kinematics(rig, pose).tail_world[2] - forward_kinematics(rig, start).tail_world[2])
            .norm();
    EXPECT_LT(moved, previous) << "lambda " << lambda;
    previous = moved;
  }
}

}  // namespace
}  // namespace physik

namespace physik {
namespace {

TEST(DampedLeastSquares, LineSearchStretchesALongChainTowardAFarTarget) {
  // 50 bones, target 60 away: the stretched chain (tip 50 along the target direction) is the
  // answer; without the backtracking line search DLS oscillates far from it
  const Rig rig = make_chain_rig(50);
  const Vec3 target(60.0, 0.0, 0.0);
  IkOptions opt;
  opt.max_iterations = 3000;
  Pose pose = rest_pose(rig);
  const IkReport rep = solve_ik(IkMethod::kDampedLeastSquares, rig, {{49, 1.0, target}}, pose, opt);
  EXPECT_FALSE(rep.converged);
  EXPECT_NEAR(rep.residual, 10.0, 1e-3 * 50);
}

}  // namespace
}  // namespace physik

namespace physik {
namespace {

TEST(DampedLeastSquares, TwentyThousandGoalsSolveInTheSmallSystem) {
  // 20,000 goals on 9 unknowns: J J^T would be 60,000^2 doubles (29 GB, bad_alloc); the
  // push-through form solves 9 x 9 and reaches the same (reachable) target as one goal does
  const Rig rig = make_chain_rig(3);
  const Vec3 target(1.0, 0.5, 2.0);
  std::vector<IkGoal> many(20000, IkGoal{2, 1.0, target});
  Pose pose = rest_pose(rig), one = rest_pose(rig);
  IkOptions opt;
  const IkReport rep = solve_ik(IkMethod::kDampedLeastSquares, rig, many, pose, opt);
  const IkReport rep1 = solve_ik(IkMethod::kDampedLeastSquares, rig, {{2, 1.0, target}}, one, opt);
  EXPECT_TRUE(rep.converged);
  EXPECT_TRUE(rep1.converged);
  EXPECT_LT((forward_kinematics(rig, pose).tail_world[2] - target).norm(), 2 * rep.tolerance);
}

}  // namespace
}  // namespace physik
