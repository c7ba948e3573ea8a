// mass_spring.cpp: the solver contract (ik_test_util.h) and what is particular to this solver.
#include <gtest/gtest.h>

#include "physik/model/rig_generators.h"
#include "tests/ik_test_util.h"

namespace physik {
namespace {

TEST(MassSpring, MeetsTheSolverContract) {
  test::expect_solver_contract(IkMethod::kMassSpring);
}

}  // namespace
}  // namespace physik

namespace physik {
namespace {

TEST(MassSpring, LengthConstraintKeepsTheCentreOfMassAndMovesTheLightNodeMore) {
  Vec3 a(0, 0, 0), b(3, 0, 0);
  const Vec3 a0 = a, b0 = b;
  const double ma = 3.0, mb = 1.0;
  mass_weighted_length(a, b, ma, mb, 2.0);
  EXPECT_NEAR((b - a).norm(), 2.0, 1e-12);
  EXPECT_TRUE(test::near(ma * a + mb * b, ma * a0 + mb * b0, 1e-12));
  EXPECT_NEAR((b - b0).norm() / (a - a0).norm(), ma / mb, 1e-12);
}

TEST(MassSpring, GravityPullsAFreeBoneDown) {
  // chain of two; the goal holds bone 1's head (alpha 0) out to the side, so bone 1's tail is a
  // free node: with gravity it hangs below its head, without gravity it keeps pointing up-ish
  const Rig rig = make_chain_rig(2);
  const std::vector<IkGoal> goals = {{1, 0.0, Vec3(1.0, 0.0, 0.0)}};
  for (bool gravity : {false, true}) {
    IkOptions opt;
    opt.gravity_world = gravity ? Vec3(0, 0, -9.81) : Vec3::Zero();
    opt.tolerance = 1e-300;  // run all iterations
    opt.stall_window = 0;
    opt.max_iterations = 3000;
    Pose pose = rest_pose(rig);
    solve_ik(IkMethod::kMassSpring, rig, goals, pose, opt);
    const BoneFrames f = forward_kinematics(rig, pose);
    EXPECT_TRUE(test::near(f.head_world[1], goals[0].target_world, 1e-6));
    const double dz = f.tail_world[1].z() - f.head_world[1].z();
    if (gravity) {
      EXPECT_LT(dz, -0.95);  // hanging (nearly) straight down
    } else {
      EXPECT_GT(dz, 0.0);
    }
  }
}

}  // namespace
}  // namespace physik
