// ccd.cpp: the solver contract (ik_test_util.h) and what is particular to this solver.
#include <cmath>

#include <gtest/gtest.h>

#include "physik/model/joint_angles.h"
#include "physik/model/rig_generators.h"
#include "tests/ik_test_util.h"

namespace physik {
namespace {

TEST(Ccd, MeetsTheSolverContract) {
  test::expect_solver_contract(IkMethod::kCcd);
}

}  // namespace
}  // namespace physik

namespace physik {
namespace {

TEST(Ccd, OneAxisStepIsTheClosedFormAngle) {
  // one bone along +Z (local x = world x); a target at the bone's length in the y-z plane is met
  // by the x step alone (atan2 of the 2D projections); the y and z steps then see no error
  const Rig rig = make_chain_rig(1);
  const double phi = 1.1;
  const Vec3 target(0.0, -std::sin(phi), std::cos(phi));
  Pose pose = rest_pose(rig);
  const IkReport rep = solve_ik(IkMethod::kCcd, rig, {{0, 1.0, target}}, pose);
  EXPECT_EQ(rep.iterations, 1);
  EXPECT_LT(rep.residual, 1e-12);
  EXPECT_TRUE(test::near(rotation_vector(pose.bone_local_rotation[0]), Vec3(phi, 0, 0), 1e-12));
}

TEST(Ccd, HingeStopsAtItsLimit) {
  // elbow: forearm x in [-90, 0] deg. A target that would need -120 deg is met at -90.
  const Rig rig = load_rig(test::model_path("rigs/elbow.json"));
  Pose pose = rest_pose(rig);
  pose.bone_local_rotation[0] = Quat::Identity();
  IkOptions opt;
  opt.max_iterations = 200;
  const Vec3 target(0.0, 2.0 * std::sin(deg2rad(120)), 2.0 + 2.0 * std::cos(deg2rad(120)));
  solve_ik(IkMethod::kCcd, rig, {{1, 1.0, target}}, pose, opt);
  EXPECT_LE(max_limit_violation(rig, LockedAxes::kSprings, pose), 1e-12);
}

}  // namespace
}  // namespace physik
