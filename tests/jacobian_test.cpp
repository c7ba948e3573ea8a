// jacobian.cpp: the solver contract for the transpose and DLS methods, with both Jacobians, and
// the Jacobians themselves against brute-force finite differences through FK.
#include <algorithm>

#include <gtest/gtest.h>

#include "physik/model/errors.h"
#include "physik/model/rig_generators.h"
#include "tests/engine_test_util.h"
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

namespace physik {
namespace {

// a goal with the position of bone's tail and the orientation of its frame in a random pose
IkGoal pose_goal(const Rig& rig, int bone, std::mt19937& rng) {
  const BoneFrames f = forward_kinematics(rig, test::random_pose(rig, rng, 1.0));
  IkGoal g{bone, 1.0, f.tail_world[bone]};
  g.has_orientation = true;
  g.orientation_world = f.orient_world[bone];
  return g;
}

TEST(Jacobian, OrientationRowsAreTheAngularJacobianTimesTheLength) {
  const Rig rig = load_rig(test::model_path("rigs/pinhead.json"));
  std::mt19937 rng(5);
  const Pose pose = test::random_pose(rig, rng, 0.8);
  const BoneFrames f = forward_kinematics(rig, pose);
  IkProblem pb;
  pb.rig = &rig;
  pb.orientation_length = 2.5;
  pb.any_orientation = true;
  IkGoal g = pose_goal(rig, rig.find_bone("hand.L"), rng);
  pb.goals = {g};
  pb.active = active_bones(rig, pb.goals);
  std::vector<int> bones, axes;
  ik_dofs(rig, pb.active, true, bones, axes);
  Eigen::MatrixXd J;
  goal_jacobian(pb, f, bones, axes, JacobianKind::kAnalytic, 0.0, J);
  ASSERT_EQ(J.rows(), 6);
  // brute force: the world turn of the hand's frame per radian of each axis, through FK
  const double eps = 1e-6;
  for (std::size_t c = 0; c < bones.size(); ++c) {
    Pose p = pose;
    p.bone_local_rotation[bones[c]] =
        Quat(Eigen::AngleAxisd(eps, Vec3::Unit(axes[c]))) * p.bone_local_rotation[bones[c]];
    const BoneFrames h = forward_kinematics(rig, p);
    const Vec3 w = rotation_vector(h.orient_world[g.bone] * f.orient_world[g.bone].conjugate());
    EXPECT_TRUE(test::near(Vec3(pb.orientation_length * w / eps), J.block<3, 1>(3, c), 1e-5))
        << "column " << c;
  }
  // an orientation-only goal has its three angular rows alone
  pb.goals[0].has_position = false;
  goal_jacobian(pb, f, bones, axes, JacobianKind::kFiniteDifference, 1e-6, J);
  EXPECT_EQ(J.rows(), 3);
}

// reachable position + orientation goals (the tail and frame of the bone in a random pose),
// solved from the rest pose: both errors under their tolerances
// (near > 0: from the goal's pose with every axis turned by up to `near` rad, not from rest)
void expect_reaches_pose_goals(IkMethod m, const Rig& rig, int bone, int count,
                               const IkOptions& opt = {}, double near = 0.0) {
  std::mt19937 rng(77);
  for (int t = 0; t < count; ++t) {
    const Pose goal_pose = test::random_pose(rig, rng, 1.0);
    const BoneFrames gf = forward_kinematics(rig, goal_pose);
    IkGoal g{bone, 1.0, gf.tail_world[bone]};
    g.has_orientation = true;
    g.orientation_world = gf.orient_world[bone];
    Pose pose = rest_pose(rig);
    if (near > 0.0) {
      std::uniform_real_distribution<double> u(-near, near);
      for (int i = 0; i < rig.nbone; ++i) {
        pose.bone_local_rotation[i] = quat_from_rotation_vector(Vec3(u(rng), u(rng), u(rng))) *
                                      goal_pose.bone_local_rotation[i];
      }
    }
    const IkReport rep = solve_ik(m, rig, {g}, pose, opt);
    EXPECT_TRUE(rep.converged) << to_string(m) << " target " << t << ": residual " << rep.residual
                               << ", orientation " << rep.orientation_residual << " rad after "
                               << rep.iterations;
    const BoneFrames f = forward_kinematics(rig, pose);
    EXPECT_LE((f.tail_world[bone] - g.target_world).norm(), rep.tolerance + 1e-12);
    const double angle =
        rotation_vector(g.orientation_world * f.orient_world[bone].conjugate()).norm();
    EXPECT_LE(angle, rep.orientation_tolerance + 1e-12);
    EXPECT_NEAR(rep.orientation_residuals[0], angle, 1e-12);
    // the stated tolerance: the position tolerance over the reach, i.e. 1e-4 rad
    EXPECT_NEAR(rep.orientation_tolerance, rep.tolerance / rep.reach, 1e-15);
    EXPECT_NEAR(rep.orientation_tolerance, 1e-4, 1e-15);
  }
}

TEST(DampedLeastSquares, ReachesPositionAndOrientationOnASingleBone) {
  expect_reaches_pose_goals(IkMethod::kDampedLeastSquares, make_chain_rig(1), 0, 10);
}
TEST(DampedLeastSquares, ReachesPositionAndOrientationOnAThreeBoneChain) {
  expect_reaches_pose_goals(IkMethod::kDampedLeastSquares, make_chain_rig(3), 2, 10);
}
TEST(JacobianTranspose, ReachesPositionAndOrientationOnASingleBone) {
  expect_reaches_pose_goals(IkMethod::kJacobianTranspose, make_chain_rig(1), 0, 10);
}
// From the rest pose the transpose stops short on most of these goals (a gradient method: it
// stalls where the position and orientation rows pull against each other, and crawls near the
// goal: one of these ten needs more than 5,000 iterations); started within 0.3 rad of the goal's
// pose it reaches both
TEST(JacobianTranspose, ReachesPositionAndOrientationOnAThreeBoneChainFromNearby) {
  IkOptions opt;
  opt.max_iterations = 50000;
  expect_reaches_pose_goals(IkMethod::kJacobianTranspose, make_chain_rig(3), 2, 10, opt, 0.3);
}

TEST(DampedLeastSquares, AnOrientationOnlyGoalTurnsTheBoneAndLeavesItsPositionFree) {
  const Rig rig = make_chain_rig(3);
  std::mt19937 rng(8);
  IkGoal g = pose_goal(rig, 1, rng);
  g.has_position = false;
  g.target_world = Vec3(NAN, NAN, NAN);  // unread
  Pose pose = rest_pose(rig);
  const IkReport rep = solve_ik(IkMethod::kDampedLeastSquares, rig, {g}, pose);
  EXPECT_TRUE(rep.converged);
  EXPECT_EQ(rep.residual, 0.0);
  EXPECT_LE(rep.orientation_residual, rep.orientation_tolerance);
  // bone 2 is below the goal's bone: not on its path, it keeps its rest rotation
  EXPECT_TRUE(pose.bone_local_rotation[2].isApprox(Quat::Identity(), 1e-15));
}

// a welded bone turns with its weld (FK ignores its own rotation): it has no column, and every
// other column is right through the welded chest
TEST(DampedLeastSquares, AWeldedBoneHasNoAxisOfItsOwn) {
  const Rig rig = test::welded_figure();
  const int arm = rig.find_bone("arm.L"), chest = rig.find_bone("chest");
  std::vector<int> bones, axes;
  ik_dofs(rig, active_bones(rig, {{arm, 1.0, Vec3::Zero()}}), true, bones, axes);
  EXPECT_EQ(std::count(bones.begin(), bones.end(), chest), 0);
  EXPECT_EQ(std::count(bones.begin(), bones.end(), arm), 3);
  // every column is what turning its axis does to the arm's tail, through FK
  std::mt19937 rng(4);
  const Pose pose = test::random_pose(rig, rng, 0.5);
  const BoneFrames f = forward_kinematics(rig, pose);
  IkProblem pb;
  pb.rig = &rig;
  pb.goals = {{arm, 1.0, Vec3::Zero()}};
  Eigen::MatrixXd J;
  goal_jacobian(pb, f, bones, axes, JacobianKind::kAnalytic, 0.0, J);
  const double eps = 1e-6;
  for (std::size_t c = 0; c < bones.size(); ++c) {
    Pose p = pose;
    p.bone_local_rotation[bones[c]] =
        Quat(Eigen::AngleAxisd(eps, Vec3::Unit(axes[c]))) * p.bone_local_rotation[bones[c]];
    const Vec3 d = (forward_kinematics(rig, p).tail_world[arm] - f.tail_world[arm]) / eps;
    EXPECT_TRUE(test::near(d, J.block<3, 1>(0, c), 1e-5)) << "column " << c;
  }
}

TEST(IkOrientation, OnlyTheJacobianSolversTakeOrientationsAndBadOnesAreInputErrors) {
  const Rig rig = make_chain_rig(2);
  std::mt19937 rng(9);
  const IkGoal g = pose_goal(rig, 1, rng);
  for (IkMethod m :
       {IkMethod::kFabrik, IkMethod::kCcd, IkMethod::kMassSpring, IkMethod::kRotation}) {
    Pose pose = rest_pose(rig);
    try {
      solve_ik(m, rig, {g}, pose);
      ADD_FAILURE() << to_string(m) << " took an orientation";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("does not support orientation targets"),
                std::string::npos)
          << e.what();
    }
  }
  Pose pose = rest_pose(rig);
  IkGoal bad = g;
  bad.orientation_world = Quat(2, 0, 0, 0);
  EXPECT_THROW(solve_ik(IkMethod::kDampedLeastSquares, rig, {bad}, pose), InputError);
  bad.orientation_world = Quat(0, 0, 0, 0);
  EXPECT_THROW(solve_ik(IkMethod::kDampedLeastSquares, rig, {bad}, pose), InputError);
  bad = g;
  bad.has_position = false;
  bad.has_orientation = false;
  EXPECT_THROW(solve_ik(IkMethod::kDampedLeastSquares, rig, {bad}, pose), InputError);
}

}  // namespace
}  // namespace physik
