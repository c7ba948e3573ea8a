// PosingSession (physik/posing/posing_session.h): the engine as an embedded IK solver.
#include <gtest/gtest.h>

#include "physik/engine/engine.h"
#include "physik/io/scene_io.h"
#include "physik/model/errors.h"
#include "physik/model/joint_angles.h"
#include "physik/model/rig_generators.h"
#include "physik/posing/posing_session.h"
#include "tests/engine_test_util.h"
#include "tests/test_util.h"

namespace physik {
namespace {

Scene two_hands() {
  return load_scene(test::model_path("scenes/pinhead_two_hands.json"));
}

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

// the time-stepping solve (physik-steps, physik-explicit)
SolveRule by_steps() {
  SolveRule rule;
  rule.method = SolveMethod::kSteps;
  return rule;
}

// solve() by steps is the engine's run to the residual tolerance: the same steps, bit for bit,
// as run_scene with the scene's stop_at_residual_tol (what `physik solve --solver
// physik-explicit` runs).
TEST(PosingSession, SolveIsTheEnginesRunToTheResidualTolerance) {
  Scene scene = two_hands();
  PosingSession session(scene);
  const SolveResult r = session.solve(by_steps());
  ASSERT_TRUE(r.converged);
  EXPECT_LT(r.residual, r.tolerance);
  EXPECT_EQ(r.finish_iterations, 0);

  scene.convergence.stop_at_residual_tol = true;
  scene.convergence.residual_tol = r.tolerance;
  const RunSummary s = run_scene(scene);
  EXPECT_EQ(s.steps_run, r.steps);
  EXPECT_EQ(state_hash(s.final_frames), state_hash(session.frames()));
}

// A target the schedule still has to move is waited for: the solve by steps goes on toward the
// moved target; its per-goal stall rule counts from the step the targets stop moving, so it meets
// the moved target, where run_scene's rule, whose best residual is the one met before the move,
// stalls 61 steps after it. The same steps as run_scene up to there. The equilibrium solve plays
// the schedule at once (pull_at_goals) and meets the moved target too.
TEST(PosingSession, SolveWaitsForAScheduledTargetChange) {
  Scene scene = two_hands();
  const Vec3 moved = scene.control_points[0].target_world + Vec3(0.0, 0.0, 0.3);
  scene.schedule.push_back({120, 0, moved});
  PosingSession session(scene);
  const SolveResult r = session.solve(by_steps());
  EXPECT_GT(r.steps, 120);  // not stopped at the first target, met by step ~90
  EXPECT_TRUE(r.converged);
  const ControlPoint& cp = scene.control_points[0];
  EXPECT_LT((point_on_bone(session.frames(), cp.bone, cp.alpha) - moved).norm(), r.tolerance);
  scene.convergence.stop_at_residual_tol = true;
  scene.convergence.residual_tol = r.tolerance;
  SimState at;
  const RunSummary engine = run_scene(scene, [&](const SimState& st, const StepStats&) {
    if (st.step == 181) at = st;  // where run_scene stalls
  });
  EXPECT_FALSE(engine.converged);
  EXPECT_EQ(engine.steps_run, 181);
  PosingSession again(scene);
  SolveRule cut = by_steps();
  cut.max_steps = 181;
  again.solve(cut);
  EXPECT_EQ(state_hash(at.frames), state_hash(again.frames()));
  PosingSession eq(scene);
  const SolveResult e = eq.solve();
  EXPECT_TRUE(e.converged);
  EXPECT_LT((point_on_bone(eq.frames(), cp.bone, cp.alpha) - moved).norm(), e.tolerance);
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
  // the residual is the pose's: from the pose's own forward kinematics, not the session's frames
  const BoneFrames from_pose = forward_kinematics(scene.rig, session.pose());
  EXPECT_NEAR((point_on_bone(from_pose, 2, 1.0) - (tip + Vec3(0.3, 0.0, -0.2))).norm(),
              session.residual(), 1e-12);
}

// The hybrid: physics for 15 steps, then DLS closes the rest; the physics alone is short.
TEST(PosingSession, DlsFinishClosesWhatThePhysicsLeft) {
  SolveRule rule = by_steps();
  rule.max_steps = 15;
  PosingSession physics_only(two_hands());
  const SolveResult a = physics_only.solve(rule);
  EXPECT_FALSE(a.converged);
  EXPECT_GT(a.residual, a.tolerance);
  EXPECT_TRUE(a.out_of_steps);  // the step cap ended it, not the stall rule
  EXPECT_FALSE(a.stalled);

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
    EXPECT_LE(
        max_limit_violation(hybrid.scene().rig, hybrid.scene().params.locked_axes(), hybrid.pose()),
        max_limit_violation(physics_only.scene().rig, physics_only.scene().params.locked_axes(),
                            physics_only.pose()) +
            1e-12);
  }
}

// The solve mode: on the implicit step, a step that lengthens as the motion settles reaches the
// tolerance in fewer steps than the physical dt alone, lands on the same pose (the scene's
// equilibrium for these reachable targets) and gives the scene its dt back.
TEST(PosingSession, ALengtheningImplicitStepSolvesInFewerSteps) {
  Scene scene = two_hands();
  scene.params.scheme = Scheme::kImplicit;
  PosingSession fixed(scene), lengthening(scene);
  const SolveResult a = fixed.solve(by_steps());
  SolveRule rule = by_steps();
  rule.dt_growth = 1.5;
  const SolveResult b = lengthening.solve(rule);
  ASSERT_TRUE(a.converged);
  ASSERT_TRUE(b.converged) << "residual " << b.residual;
  EXPECT_LT(b.steps, a.steps);
  EXPECT_EQ(lengthening.scene().params.dt, scene.params.dt);
  for (int c = 0; c < 2; ++c) {
    const ControlPoint& cp = scene.control_points[c];
    EXPECT_LT((point_on_bone(lengthening.frames(), cp.bone, cp.alpha) - cp.target_world).norm(),
              b.tolerance);
  }
  std::cout << "[solve mode] pinhead_two_hands implicit: dt fixed " << a.steps
            << " steps, lengthening x1.5 " << b.steps << " steps\n";
  PosingSession explicit_session(two_hands());
  expect_input_error([&] { explicit_session.solve(rule); }, "needs scheme implicit");
}

// set_pose puts a pose in at rest for every integration: a solve from it equals a fresh
// session's (the exact and implicit steps integrate the joint-space state, which set_pose rebuilds)
TEST(PosingSession, SetPoseRestartsTheImplicitStepFromThatPose) {
  Scene scene = two_hands();
  scene.params.scheme = Scheme::kImplicit;
  scene.params.interpolation = Interpolation::kNone;  // both sessions start with targets in place
  SolveRule rule = by_steps();
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

// With the targets moved along the interpolation (ik_comparison's rows), a session reused
// through set_pose solves as a fresh one: each pull starts again from the point on the new pose,
// not from the previous solve's target; and the summary is this solve's, not the session's.
TEST(PosingSession, AReusedSessionSolvesAsAFreshOne) {
  for (int method = 0; method < 3; ++method) {
    const bool implicit = method > 0;
    Scene scene = two_hands();
    ASSERT_NE(scene.params.interpolation, Interpolation::kNone);
    if (implicit) use_solve_mode(scene.params);
    const SolveRule rule = method == 2 ? solve_mode_rule()
                           : implicit  ? steps_mode_rule()
                                       : by_steps();
    const Vec3 first = scene.control_points[0].target_world + Vec3(0.3, -0.2, 0.1);
    const Vec3 other = scene.control_points[0].target_world + Vec3(-0.4, 0.2, 0.3);
    PosingSession reused(scene), fresh(scene);
    reused.set_target(0, first, true);
    ASSERT_TRUE(reused.solve(rule).converged);
    reused.set_pose(scene.initial_pose);
    reused.set_target(0, other, true);
    const SolveResult a = reused.solve(rule);
    fresh.set_target(0, other, true);
    const SolveResult b = fresh.solve(rule);
    ASSERT_TRUE(b.converged);
    EXPECT_EQ(a.steps, b.steps) << "method " << method;
    EXPECT_EQ(state_hash(reused.frames()), state_hash(fresh.frames()));
    const RunSummary sa = reused.summary(a), sb = fresh.summary(b);
    EXPECT_EQ(sa.steps_run, a.steps);
    EXPECT_EQ(sa.steps_to_converge, sb.steps_to_converge);
    EXPECT_EQ(sa.mean_passes_per_step, sb.mean_passes_per_step);
    EXPECT_EQ(sa.implicit_split_steps, sb.implicit_split_steps);
    EXPECT_EQ(sa.implicit_max_substeps, sb.implicit_max_substeps);
  }
}

// The stall rule ends a solve as stalled, not out of steps (DlsFinishClosesWhatThePhysicsLeft
// has the step cap).
TEST(PosingSession, StalledIsTheStallRuleNotTheStepCap) {
  SolveRule impatient = by_steps();  // improve by 99% every step or stall
  impatient.stall_steps = 1;
  impatient.stall_fraction = 0.99;
  PosingSession b(two_hands());
  const SolveResult rb = b.solve(impatient);
  EXPECT_FALSE(rb.converged);
  EXPECT_TRUE(rb.stalled);
  EXPECT_FALSE(rb.out_of_steps);
  EXPECT_LT(rb.steps, impatient.max_steps);
}

// The paper's damping diverges on this scene: reported, and the session is back where the
// solve started (pose at rest, step, targets and their interpolation), so a retry is the same
// solve.
TEST(PosingSession, ADivergedSolveReturnsToItsStart) {
  Scene scene = two_hands();
  scene.params.damping = 20.0;
  PosingSession session(scene);
  const BoneFrames start = session.frames();
  const SimState before = session.state();
  const SolveResult r = session.solve(by_steps());
  EXPECT_TRUE(r.diverged);
  EXPECT_FALSE(r.converged);
  EXPECT_FALSE(r.stalled);
  EXPECT_EQ(state_hash(start), state_hash(session.frames()));
  EXPECT_EQ(kinetic_energy(scene.rig, session.state()), 0.0);
  EXPECT_EQ(session.state().step, before.step);
  EXPECT_EQ(session.state().interp_steps_left, before.interp_steps_left);
  for (int c = 0; c < session.num_control_points(); ++c) {
    EXPECT_EQ(session.state().target_effective_world[c], before.target_effective_world[c]);
    EXPECT_EQ(session.state().target_goal_world[c], before.target_goal_world[c]);
  }
  const SolveResult again = session.solve(by_steps());
  EXPECT_TRUE(again.diverged);
  EXPECT_EQ(again.steps, r.steps);
  // the equilibrium solve takes the same scene to its rest pose: a minimisation does not diverge
  const SolveResult e = session.solve();
  EXPECT_FALSE(e.diverged);
  EXPECT_TRUE(e.converged) << "residual " << e.residual;
  EXPECT_EQ(session.scene().params.damping, 20.0);  // the session's settings are back
  EXPECT_EQ(session.scene().params.scheme, scene.params.scheme);
}

// damping auto: a target moved through the session chooses the damping again at the current
// pose, as a run does when its schedule moves a target
TEST(PosingSession, DampingAutoIsChosenAgainWhenATargetMoves) {
  Scene scene = two_hands();
  scene.params.damping_auto = true;
  scene.params.scheme = Scheme::kImplicit;
  PosingSession session(scene);
  const int updates = session.state().damping_auto_updates;
  const double at_start = session.state().damping_auto_value;
  session.advance(40);  // the pose has moved: its modes differ
  session.set_target(0, scene.control_points[0].target_world + Vec3(0.0, 0.0, 0.2));
  EXPECT_EQ(session.state().damping_auto_updates, updates + 1);
  EXPECT_NE(session.state().damping_auto_value, at_start);
  EXPECT_GT(session.state().damping_auto_value, 0.0);
}

TEST(PosingSession, BadInputIsAnInputError) {
  PosingSession session(two_hands());
  expect_input_error([&] { session.set_target(2, Vec3::Zero()); },
                     "no control point 2 (the scene has 2)");
  expect_input_error([&] { session.set_target(-1, Vec3::Zero()); }, "no control point -1");
  expect_input_error([&] { session.set_target(0, Vec3(0, std::nan(""), 0)); }, "not finite");
  Pose short_pose = session.pose();
  short_pose.bone_local_rotation.pop_back();
  expect_input_error([&] { session.set_pose(short_pose); },
                     "17 bone rotations for a rig of 18 bones");
  Pose nan_pose = session.pose();
  nan_pose.bone_local_rotation[3] = Quat(std::nan(""), 0, 0, 0);
  expect_input_error([&] { session.set_pose(nan_pose); }, "not a finite unit quaternion");
  const auto rule_error = [&](auto edit, const std::string& text) {
    SolveRule rule;
    edit(rule);
    expect_input_error([&] { session.solve(rule); }, text);
  };
  rule_error([](SolveRule& r) { r.stall_steps = -1; }, "stall_steps");
  rule_error([](SolveRule& r) { r.tolerance_angle = -1e-3; }, "tolerance_angle");
  rule_error([](SolveRule& r) { r.tolerance_angle = std::nan(""); }, "tolerance_angle");
  rule_error([](SolveRule& r) { r.initial_step = 0.0; }, "initial_step");
  rule_error([](SolveRule& r) { r.max_dt = std::nan(""); }, "max_dt");
  rule_error([](SolveRule& r) { r.dt_growth = 0.5; }, "dt_growth");
  rule_error([](SolveRule& r) { r.tolerance = -1.0; }, "tolerance");
  rule_error([](SolveRule& r) { r.stall_fraction = 1.0; }, "stall_fraction");
  rule_error([](SolveRule& r) { r.max_steps = -1; }, "max_steps");
  Scene none = test::scene_for(make_chain_rig(2), EngineParams());
  PosingSession empty(none);
  expect_input_error([&] { empty.solve(); }, "a solve needs a goal");
  Scene bad = test::scene_for(make_chain_rig(2), EngineParams());
  bad.control_points.push_back(test::control(5, 1.0, Vec3::Zero(), 10.0));
  expect_input_error([&] { PosingSession s(bad); }, "no such bone");
}

}  // namespace
}  // namespace physik
