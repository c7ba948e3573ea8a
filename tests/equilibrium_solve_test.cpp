// The equilibrium solve (physik/engine/equilibrium_solve.h): a minimisation of the potential by
// a trust region of implicit steps at rest, and the goals by their own measure (measures.h).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "physik/engine/engine.h"
#include "physik/engine/equilibrium_solve.h"
#include "physik/engine/forces.h"
#include "physik/engine/implicit_step.h"
#include "physik/engine/integrate_joint_space.h"
#include "physik/engine/potential.h"
#include "physik/model/rig_generators.h"
#include "physik/posing/posing_session.h"
#include "tests/engine_test_util.h"
#include "tests/test_util.h"

namespace physik {
namespace {

// A chain of n unit bones along +Z whose root's head is pinned to the world (a ball).
Rig pinned_chain(int n) {
  std::vector<BoneSpec> specs(n);
  for (int i = 0; i < n; ++i) {
    BoneSpec& b = specs[i];
    b.name = "b" + std::to_string(i);
    b.parent = i == 0 ? "" : "b" + std::to_string(i - 1);
    b.head_world = Vec3(0, 0, i);
    b.tail_world = Vec3(0, 0, i + 1);
    b.rest_frame_world = rest_frame_from_roll(b.head_world, b.tail_world, 0.0);
    b.mass = 1.0;
  }
  return build_rig(specs, "pinned_chain", "pinned_chain", RootJoint::kPinned);
}

Scene solve_scene_of(const Rig& rig) {
  Scene s = test::scene_for(rig, preset_params("original"));
  use_solve_mode(s.params);
  return s;
}

// the effector's tail reaches a reachable target in a few iterations, within the tolerance
TEST(EquilibriumSolve, MeetsAReachableTargetInFewIterations) {
  const Rig rig = make_chain_rig(10);
  Scene scene = solve_scene_of(rig);
  scene.control_points = {test::control(9, 1.0, Vec3(3.0, 2.0, 6.0), 10.0),
                          test::control(0, 0.0, Vec3::Zero(), 10.0)};
  PosingSession session(scene);
  SolveRule rule;
  rule.tolerance = 1e-4 * 10.0;
  const SolveResult r = session.solve(rule);
  ASSERT_TRUE(r.converged);
  EXPECT_EQ(r.method, SolveMethod::kEquilibrium);
  EXPECT_LE(r.steps, 20);
  EXPECT_LT((session.frames().tail_world[9] - Vec3(3.0, 2.0, 6.0)).norm(), rule.tolerance);
  EXPECT_FALSE(r.diverged);
}

// Out of reach: the minimum of k |tail - t|^2 / 2 over a pinned chain is the chain straight
// toward t, its tail at the reach; the solve ends there, short, and says by how much. The stall
// rule stops it once the goal no longer improves by 1% in 6 iterations, near that pose (within
// the tolerance's scale); with no stall fraction only U's round-off stops it, on the pose to 1e-6
// (measured 3.4e-8: the round-off of U, 45 J, allows a few 1e-8 in the chain's flattest turn).
TEST(EquilibriumSolve, AnUnreachableTargetEndsWithTheChainStraightAtTheReach) {
  const Rig rig = pinned_chain(3);
  Scene scene = solve_scene_of(rig);
  const Vec3 dir = Vec3(1.0, 0.5, 0.4).normalized();
  scene.control_points = {test::control(2, 1.0, 6.0 * dir, 10.0)};
  const Vec3 straight = 3.0 * dir;
  for (double fraction : {0.01, 0.0}) {
    PosingSession session(scene);
    SolveRule rule;
    rule.tolerance = 1e-4;
    rule.stall_fraction = fraction;
    const SolveResult r = session.solve(rule);
    EXPECT_FALSE(r.converged);
    EXPECT_TRUE(r.stationary || r.stalled);
    EXPECT_FALSE(r.out_of_steps);
    const double within = fraction > 0.0 ? 1e-4 : 1e-6;
    EXPECT_TRUE(test::near(session.frames().tail_world[2], straight, within)) << fraction;
    EXPECT_NEAR(goal_residual(scene, session.state(), 0), 3.0, within);
  }
}

// U never rises from one accepted iteration to the next, and the state stays finite, on random
// limited trees pulled toward targets near and far (some out of reach, some past a limit)
TEST(EquilibriumSolve, ThePotentialNeverRisesAndTheStateStaysFinite) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    Rig rig = make_tree_rig(12, 2);
    for (int i = 1; i < rig.nbone; i += 2) {
      rig.bone_limit[i][0] = AxisLimit{true, -0.4, 0.6};
      rig.bone_limit[i][2] = AxisLimit{true, 0.0, 0.0};
    }
    Scene scene = solve_scene_of(rig);
    const double far = trial % 3 == 0 ? 3.0 : 1.0;
    scene.control_points = {
        test::control(rig.nbone - 1, 1.0, far * Vec3(4 * u(rng), 4 * u(rng), 4 * u(rng)), 10.0),
        test::control(rig.nbone / 2, 1.0, Vec3(2 * u(rng), 2 * u(rng), 3 * u(rng)), 10.0,
                      SpringLaw::kCapped, 0.5),
        test::control(0, 0.0, Vec3::Zero(), 10.0)};
    PosingSession session(scene);
    double last = std::numeric_limits<double>::infinity();
    bool rose = false;
    const SolveResult r = session.solve({}, [&](const SimState&, const StepStats& st) {
      rose = rose || st.potential_energy > last;
      last = st.potential_energy;
    });
    EXPECT_FALSE(rose) << "trial " << trial;
    EXPECT_TRUE(state_finite(session.state())) << "trial " << trial;
    EXPECT_FALSE(r.diverged);
    EXPECT_TRUE(r.converged || r.stalled || r.stationary || r.out_of_steps);
  }
}

// (2)'s terms are the step's own: as h -> 0 the actual decrease of U is the predicted one, and
// the metric's part is twice the kinetic energy of the step's velocities (dq = h v+)
TEST(EquilibriumSolve, ThePredictedDecreaseIsTheModelsAtShortSteps) {
  const Rig rig = make_chain_rig(6);
  Scene scene = solve_scene_of(rig);
  scene.params.damping = 0.0;
  scene.params.angular_velocity_factor = 1.0;  // no dampers: the metric is M / h^2 alone
  scene.control_points = {test::control(5, 1.0, Vec3(2.0, 1.0, 4.0), 10.0)};
  SimState s;
  init_state(scene, s);
  pull_at_goals(scene, s);
  const double u0 = potential_energy(scene, s);
  for (double h : {1e-2, 1e-3}) {
    SimState t = s;
    apply_forces(scene, t);
    solve_implicit(scene, t, h);
    const double pred = predicted_decrease(scene, t, h);
    integrate_joint_space(scene.rig, h, t);
    // the metric's part, h^2 sum (m |a|^2 + alpha I alpha) = 2 KE(v+) (at the new pose, to O(h^2))
    const double metric = 2.0 * kinetic_energy(scene.rig, t);
    const double u1 = potential_energy(scene, t);
    EXPECT_NEAR((u0 - u1) / pred, 1.0, 10.0 * h) << "h " << h;
    // (tau^T dq + dq^T M dq / h^2) / 2 with dq^T M dq / h^2 = 2 KE: the force's work is the rest
    EXPECT_GT(pred, 0.5 * metric) << "h " << h;
  }
}

// A rod pinned at its head, pulled sideways at its tail by a spring against gravity: at the
// solved pose the torques about the pin balance (the forces' generalised force is zero).
TEST(EquilibriumSolve, TheTorquesBalanceAtTheSolvedPoseWithGravity) {
  std::vector<BoneSpec> specs(1);
  specs[0].name = "rod";
  specs[0].head_world = Vec3(0, 0, 0);
  specs[0].tail_world = Vec3(0, 0, -1);
  specs[0].rest_frame_world = rest_frame_from_roll(specs[0].head_world, specs[0].tail_world, 0.0);
  specs[0].mass = 2.0;
  const Rig rig = build_rig(specs, "rod", "rod", RootJoint::kPinned);
  Scene scene = solve_scene_of(rig);
  scene.gravity_world = Vec3(0, 0, -9.81);
  scene.control_points = {test::control(0, 1.0, Vec3(3.0, 0.0, -1.0), 5.0)};
  PosingSession session(scene);
  SolveRule rule;
  rule.tolerance = 1e-9;  // out of reach: it ends at the balance, stationary
  session.solve(rule);
  const BoneFrames& f = session.frames();
  const Vec3 tail = f.tail_world[0], com = 0.5 * (f.head_world[0] + tail);
  const Vec3 torque =
      tail.cross(5.0 * (Vec3(3.0, 0.0, -1.0) - tail)) + com.cross(Vec3(0, 0, -9.81 * 2.0));
  EXPECT_LT(torque.norm(), 1e-6 * 2.0 * 9.81);
  EXPECT_GT(tail.x(), 0.1);  // pulled aside, held down
}

// An orientation target is met by its angle (rad), not by an arc on its bone: a short bone
// turned 2e-3 rad off is short at tolerance_angle 1e-4 whatever the position tolerance
TEST(EquilibriumSolve, TurningGoalsAreMetByTheirAngle) {
  const Rig rig = make_chain_rig(3, 0.04);
  Scene scene = solve_scene_of(rig);
  scene.control_points = {test::control(0, 0.0, Vec3::Zero(), 10.0)};
  OrientationTarget o;
  o.bone = 2;
  o.target_world = Quat(Eigen::AngleAxisd(0.8, Vec3::UnitX())) * rig.bone_rest_orient_world[2];
  scene.orientation_targets = {o};
  PosingSession session(scene);
  SolveRule rule;
  rule.tolerance = 1e-3;  // an arc of 1e-3 on a 4 cm bone would pass at 0.025 rad
  rule.tolerance_angle = 1e-4;
  const SolveResult r = session.solve(rule);
  ASSERT_TRUE(r.converged);
  EXPECT_LT(orientation_residual(session.frames(), o), 1e-4);
  EXPECT_DOUBLE_EQ(r.tolerance_angle, 1e-4);
}

// The stall rule counts progress per goal: a goal still short that improves keeps the solve
// going while another is stuck; once every goal short of its tolerance stops improving, stalled.
TEST(EquilibriumSolve, TheStallRuleCountsProgressPerGoal) {
  const Rig rig = make_chain_rig(2);
  Scene scene = solve_scene_of(rig);
  scene.control_points = {test::control(1, 1.0, Vec3(0, 0, 2), 10.0),
                          test::control(0, 1.0, Vec3(0, 0, 1), 10.0)};
  SimState s;
  init_state(scene, s);
  GoalProgress progress;
  progress.restart(scene, 0, 3, 0.01);
  const GoalTolerance tol{1e-3, 1e-3};
  s.target_goal_world = {Vec3(0, 0, 3), Vec3(0, 0, 2)};  // both short by 1
  EXPECT_FALSE(progress.observe(scene, s, tol, 0));
  for (int k = 1; k <= 6; ++k) {  // goal 0 improves by half every time, goal 1 is stuck
    s.target_goal_world[0] = Vec3(0, 0, 2.0 + std::pow(0.5, k));
    EXPECT_FALSE(progress.observe(scene, s, tol, k)) << k;
  }
  for (int k = 7; k <= 10; ++k) EXPECT_EQ(progress.observe(scene, s, tol, k), k >= 9) << k;
  // a met goal does not count: with goal 0 met, goal 1 alone stuck stalls after the window
  s.target_goal_world[0] = Vec3(0, 0, 2);
  progress.restart(scene, 0, 3, 0.01);
  for (int k = 0; k <= 3; ++k) EXPECT_EQ(progress.observe(scene, s, tol, k), k >= 3) << k;
}

}  // namespace
}  // namespace physik
