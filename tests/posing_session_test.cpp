// PosingSession (physik/posing/posing_session.h): the engine as an embedded IK solver.
#include <gtest/gtest.h>

#include "physik/engine/engine.h"
#include "physik/io/scene_io.h"
#include "physik/model/errors.h"
#include "physik/model/rig_generators.h"
#include "physik/posing/posing_session.h"
#include "tests/engine_test_util.h"
#include "tests/test_util.h"

namespace physik {
namespace {

Scene two_hands() { return load_scene(test::model_path("scenes/pinhead_two_hands.json")); }

// f() throws InputError whose message contains `text`.
template <class F>
void expect_input_error(F f, const std::string& text) {
  try {
    f();
    ADD_FAILURE() << "no InputError; expected: " << text;
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
  }
}

// solve() is the engine's run to the residual tolerance: the same steps, bit for bit, as
// run_scene with the scene's stop_at_residual_tol (what `physik solve --solver physik` runs).
TEST(PosingSession, SolveIsTheEnginesRunToTheResidualTolerance) {
  Scene scene = two_hands();
  PosingSession session(scene);
  const SolveResult r = session.solve();
  ASSERT_TRUE(r.converged);
  EXPECT_LT(r.residual, r.tolerance);
  EXPECT_EQ(r.finish_iterations, 0);

  scene.convergence.stop_at_residual_tol = true;
  scene.convergence.residual_tol = r.tolerance;
  const RunSummary s = run_scene(scene);
  EXPECT_EQ(s.steps_run, r.steps);
  EXPECT_EQ(state_hash(s.final_frames), state_hash(session.frames()));
}

// A target the schedule still has to move is waited for: the solve goes on toward the moved
// target and stops where run_scene does (the same steps, verdict and state).
TEST(PosingSession, SolveWaitsForAScheduledTargetChange) {
  Scene scene = two_hands();
  const Vec3 moved = scene.control_points[0].target_world + Vec3(0.0, 0.0, 0.3);
  scene.schedule.push_back({120, 0, moved});
  PosingSession session(scene);
  const SolveResult r = session.solve();
  EXPECT_GT(r.steps, 120);  // not stopped at the first target, met by step ~90
  const ControlPoint& cp = scene.control_points[0];
  const Vec3 tip = point_on_bone(session.frames(), cp.bone, cp.alpha);
  EXPECT_LT((tip - moved).norm(), 0.1 * (tip - cp.target_world).norm());
  scene.convergence.stop_at_residual_tol = true;
  scene.convergence.residual_tol = r.tolerance;
  const RunSummary engine = run_scene(scene);
  EXPECT_EQ(engine.steps_run, r.steps);
  EXPECT_EQ(engine.converged, r.converged);
  EXPECT_EQ(state_hash(engine.final_frames), state_hash(session.frames()));
}

// A dragged point: each jump of the target is followed, the residual shrinks while advancing,
// and a solve from there meets the new target.
TEST(PosingSession, FollowsADraggedTarget) {
  Scene scene = test::scene_for(make_chain_rig(3), EngineParams());
  scene.control_points.push_back(test::control(2, 1.0, Vec3::Zero(), 10.0));
  PosingSession session(scene);
  const Vec3 tip = point_on_bone(session.frames(), 2, 1.0);
  session.set_target(0, tip + Vec3(0.3, 0.0, -0.2));
  const double before = session.residual();
  EXPECT_NEAR(before, std::sqrt(0.13), 1e-12);
  session.advance(20);
  EXPECT_LT(session.residual(), before);
  const SolveResult r = session.solve();
  EXPECT_TRUE(r.converged);
  EXPECT_LT(session.residual(), r.tolerance);
  EXPECT_NEAR((point_on_bone(session.frames(), 2, 1.0) - (tip + Vec3(0.3, 0.0, -0.2))).norm(),
              session.residual(), 1e-15);
}

// The hybrid: physics for 15 steps, then DLS closes the rest; the physics alone is short.
TEST(PosingSession, DlsFinishClosesWhatThePhysicsLeft) {
  SolveRule rule;
  rule.max_steps = 15;
  PosingSession physics_only(two_hands());
  const SolveResult a = physics_only.solve(rule);
  EXPECT_FALSE(a.converged);
  EXPECT_GT(a.residual, a.tolerance);

  for (SolveFinish finish : {SolveFinish::kDls, SolveFinish::kCcd}) {
    rule.finish = finish;
    PosingSession hybrid(two_hands());
    const SolveResult b = hybrid.solve(rule);
    EXPECT_EQ(b.steps, 15);
    EXPECT_GT(b.finish_iterations, 0);
    EXPECT_TRUE(b.converged) << "residual " << b.residual;
    EXPECT_LT(hybrid.residual(), b.tolerance);
    // the finished pose is put in at rest; the IK solver clamps what it moves into the limits,
    // so the soft torsion springs' overshoot during the transient grows no worse
    EXPECT_EQ(kinetic_energy(hybrid.scene().rig, hybrid.state()), 0.0);
    EXPECT_LE(max_limit_violation(hybrid.scene().rig, hybrid.pose()),
              max_limit_violation(physics_only.scene().rig, physics_only.pose()) + 1e-12);
  }
}

// The solve mode: on the implicit step, a step that lengthens as the motion settles reaches the
// tolerance in fewer steps than the physical dt alone, lands on the same pose (the scene's
// equilibrium for these reachable targets) and gives the scene its dt back.
TEST(PosingSession, ALengtheningImplicitStepSolvesInFewerSteps) {
  Scene scene = two_hands();
  scene.params.integration = Integration::kImplicit;
  PosingSession fixed(scene), lengthening(scene);
  const SolveResult a = fixed.solve();
  SolveRule rule;
  rule.dt_growth = 1.5;
  const SolveResult b = lengthening.solve(rule);
  ASSERT_TRUE(a.converged);
  ASSERT_TRUE(b.converged) << "residual " << b.residual;
  EXPECT_LT(b.steps, a.steps);
  EXPECT_EQ(lengthening.scene().params.dt, scene.params.dt);
  for (int c = 0; c < 2; ++c) {
    const ControlPoint& cp = scene.control_points[c];
    EXPECT_LT((point_on_bone(lengthening.frames(), cp.bone, cp.alpha) - cp.target_world).norm(), b.tolerance);
  }
  std::cout << "[solve mode] pinhead_two_hands implicit: dt fixed " << a.steps << " steps, lengthening x1.5 "
            << b.steps << " steps\n";
  PosingSession explicit_session(two_hands());
  expect_input_error([&] { explicit_session.solve(rule); }, "needs integration implicit");
}

// set_pose puts a pose in at rest for every integration: a solve from it equals a fresh
// session's (the exact and implicit steps integrate the joint-space state, which set_pose rebuilds)
TEST(PosingSession, SetPoseRestartsTheImplicitStepFromThatPose) {
  Scene scene = two_hands();
  scene.params.integration = Integration::kImplicit;
  scene.params.interpolation = Interpolation::kNone;  // both sessions start with targets in place
  SolveRule rule;
  rule.dt_growth = 2.0;
  rule.max_dt = 100.0;
  const Vec3 other = scene.control_points[0].target_world + Vec3(-0.4, 0.2, 0.3);
  PosingSession reused(scene);
  ASSERT_TRUE(reused.solve(rule).converged);
  reused.set_pose(scene.initial_pose);
  reused.set_target(0, other);
  const SolveResult a = reused.solve(rule);
  PosingSession fresh(scene);
  fresh.set_target(0, other);
  const SolveResult b = fresh.solve(rule);
  ASSERT_TRUE(b.converged);
  EXPECT_TRUE(a.converged);
  EXPECT_EQ(a.steps, b.steps);
  EXPECT_EQ(state_hash(reused.frames()), state_hash(fresh.frames()));
}

// The paper's damping diverges on this scene: reported, and the session is back where the
// solve started, at rest, with finite frames.
TEST(PosingSession, ADivergedSolveReturnsToItsStart) {
  Scene scene = two_hands();
  scene.params.damping = 20.0;
  PosingSession session(scene);
  const BoneFrames start = session.frames();
  const SolveResult r = session.solve();
  EXPECT_TRUE(r.diverged);
  EXPECT_FALSE(r.converged);
  EXPECT_EQ(state_hash(start), state_hash(session.frames()));
  EXPECT_EQ(kinetic_energy(scene.rig, session.state()), 0.0);
}

TEST(PosingSession, BadInputIsAnInputError) {
  PosingSession session(two_hands());
  expect_input_error([&] { session.set_target(2, Vec3::Zero()); },
                           "no control point 2 (the scene has 2)");
  expect_input_error([&] { session.set_target(-1, Vec3::Zero()); }, "no control point -1");
  expect_input_error([&] { session.set_target(0, Vec3(0, std::nan(""), 0)); }, "not finite");
  Scene none = test::scene_for(make_chain_rig(2), EngineParams());
  PosingSession empty(none);
  expect_input_error([&] { empty.solve(); }, "a solve needs a control point");
  Scene bad = test::scene_for(make_chain_rig(2), EngineParams());
  bad.control_points.push_back(test::control(5, 1.0, Vec3::Zero(), 10.0));
  expect_input_error([&] { PosingSession s(bad); }, "no such bone");
}

}  // namespace
}  // namespace physik
