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

// the solve mode's engine settings: the implicit scheme's joint-space state, the gradient torque
Scene solve_scene_of(const Rig& rig) {
  Scene s = test::scene_for(rig, preset_params("original"));
  s.params.scheme = Scheme::kImplicit;
  s.params.torsion_torque = TorsionTorque::kGradient;
  return s;
}

// Out of reach, by the engine alone: the minimum of k |tail - t|^2 / 2 over a pinned chain is
// the chain straight toward t; with no stall fraction only U's round-off stops the solve, there
// (stationary), the goal short by the reach's gap, U never rising on the way.
TEST(EquilibriumSolve, TheEngineSolveEndsStationaryWithTheChainStraight) {
  const Rig rig = pinned_chain(3);
  Scene scene = solve_scene_of(rig);
  const Vec3 dir = Vec3(1.0, 0.5, 0.4).normalized();
  scene.control_points = {test::control(2, 1.0, 6.0 * dir, 10.0)};
  SimState s;
  init_state(scene, s);
  EquilibriumWorkspace ws;
  size_equilibrium(scene, s.contact.anchors.capacity(), ws);
  EquilibriumRule rule;
  rule.tolerance = GoalTolerance{1e-4, 1e-4};
  rule.stall_fraction = 0.0;
  double last = std::numeric_limits<double>::infinity();
  bool rose = false;
  const EquilibriumResult r =
      equilibrium_solve(scene, s, ws, rule, [&](const SimState&, const StepStats& st) {
        rose = rose || st.potential_energy > last;
        last = st.potential_energy;
      });
  EXPECT_FALSE(rose);
  EXPECT_FALSE(r.converged);
  EXPECT_TRUE(r.stationary);
  EXPECT_TRUE(test::near(s.frames.tail_world[2], 3.0 * dir, 1e-6));
  EXPECT_NEAR(goal_residual(scene, s, 0), 3.0, 1e-6);
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
