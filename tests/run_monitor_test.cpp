// RunMonitor: convergence and divergence rules fed with hand-made observations, so every
// expected step number follows from the rules in run_monitor.h.
#include "physik/engine/run_monitor.h"
#include "physik/engine/engine.h"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "tests/engine_test_util.h"
#include "tests/test_util.h"

namespace physik {
namespace {

// speed_tol 0.1 rig units/s and mass 2 kg: at rest when KE < 0.5 * 2 * 0.1^2 = 0.01 J
RunRules rules(int settle_steps = 5, int last_event = 0, bool stop = false) {
  RunRules r;
  r.speed_tol = 0.1;
  r.energy_bound = 100.0;
  r.total_mass = 2.0;
  r.last_event = last_event;
  r.settle_steps = settle_steps;
  r.stop_when_converged = stop;
  return r;
}

constexpr double kMovingKe = 1.0;  // v = 1 rig unit/s
constexpr double kRestKe = 0.001;  // v = sqrt(0.001) ~ 0.032 rig units/s

StepObservation at(int step, double ke) {
  StepObservation o;
  o.step = step;
  o.kinetic_energy = ke;
  return o;
}

TEST(RunMonitor, ConvergesAfterSettleStepsAtRestFromTheFirstRestStep) {
  RunMonitor mon(rules(5));
  for (int k = 1; k <= 7; ++k) EXPECT_FALSE(mon.observe(at(k, kMovingKe)));
  // at rest from step 8: the window 8..12 completes at step 12
  for (int k = 8; k <= 11; ++k) {
    EXPECT_FALSE(mon.observe(at(k, kRestKe)));
    EXPECT_FALSE(mon.converged()) << "step " << k;
  }
  EXPECT_FALSE(mon.observe(at(12, kRestKe)));  // no stop_when_converged
  EXPECT_TRUE(mon.converged());
  // staying at rest keeps the first step of the window
  for (int k = 13; k <= 20; ++k) mon.observe(at(k, kRestKe));
  const RunSummary s = mon.summary();
  EXPECT_TRUE(s.converged);
  EXPECT_FALSE(s.diverged);
  EXPECT_EQ(s.steps_to_converge, 8);
  EXPECT_EQ(s.steps_run, 20);
}

TEST(RunMonitor, SpeedExactlyAtTheToleranceIsNotAtRest) {
  RunMonitor mon(rules(1));
  mon.observe(at(1, 0.5 * 2.0 * 0.1 * 0.1 * 1.0001));
  EXPECT_FALSE(mon.converged());
  mon.observe(at(2, 0.5 * 2.0 * 0.1 * 0.1 * 0.9999));
  EXPECT_TRUE(mon.converged());
  EXPECT_EQ(mon.summary().steps_to_converge, 2);
}

TEST(RunMonitor, MotionResumingClearsConvergenceAndTheWindowStartsOver) {
  RunMonitor mon(rules(3));
  for (int k = 1; k <= 3; ++k) mon.observe(at(k, kRestKe));
  ASSERT_TRUE(mon.converged());
  EXPECT_EQ(mon.summary().steps_to_converge, 1);

  mon.observe(at(4, kMovingKe));  // one step of motion
  EXPECT_FALSE(mon.converged());
  EXPECT_EQ(mon.summary().steps_to_converge, -1);
  EXPECT_EQ(mon.rest_run(), 0);

  // a window broken before it completes does not count either
  mon.observe(at(5, kRestKe));
  mon.observe(at(6, kRestKe));
  mon.observe(at(7, kMovingKe));
  for (int k = 8; k <= 10; ++k) mon.observe(at(k, kRestKe));
  EXPECT_TRUE(mon.converged());
  EXPECT_EQ(mon.summary().steps_to_converge, 8);
}

TEST(RunMonitor, NoRestWhileATargetMovesOrBeforeTheLastScheduleEvent) {
  RunMonitor mon(rules(2, /*last_event=*/4));
  for (int k = 1; k <= 4; ++k) mon.observe(at(k, 0.0));  // still, but the schedule is not done
  EXPECT_EQ(mon.rest_run(), 0);
  StepObservation o = at(5, 0.0);
  o.target_moving = true;  // a target still interpolating
  mon.observe(o);
  EXPECT_EQ(mon.rest_run(), 0);
  mon.observe(at(6, 0.0));
  mon.observe(at(7, 0.0));
  EXPECT_TRUE(mon.converged());
  EXPECT_EQ(mon.summary().steps_to_converge, 6);
}

TEST(RunMonitor, StopsAtConvergenceOnlyWhenTheRulesSaySo) {
  RunMonitor stop(rules(2, 0, /*stop=*/true));
  EXPECT_FALSE(stop.observe(at(1, kRestKe)));
  EXPECT_TRUE(stop.observe(at(2, kRestKe)));
  RunMonitor go_on(rules(2, 0, /*stop=*/false));
  EXPECT_FALSE(go_on.observe(at(1, kRestKe)));
  EXPECT_FALSE(go_on.observe(at(2, kRestKe)));
  EXPECT_TRUE(go_on.converged());
}

TEST(RunMonitor, EnergyAboveTheBoundDivergesWithAReason) {
  RunMonitor mon(rules(), "MuJoCo: ");
  EXPECT_FALSE(mon.observe(at(1, 100.0)));  // at the bound is not past it
  EXPECT_TRUE(mon.observe(at(2, 250.0)));
  const RunSummary s = mon.summary();
  EXPECT_TRUE(s.diverged);
  EXPECT_FALSE(s.converged);
  EXPECT_EQ(s.steps_run, 2);
  EXPECT_EQ(s.peak_kinetic_energy, 250.0);
  EXPECT_EQ(s.divergence_reason.rfind("MuJoCo: kinetic energy 250", 0), 0u) << s.divergence_reason;
  EXPECT_NE(s.divergence_reason.find("bound 100"), std::string::npos) << s.divergence_reason;
  EXPECT_NE(s.divergence_reason.find("at step 2"), std::string::npos) << s.divergence_reason;
}

TEST(RunMonitor, NonFiniteEnergyStateOrEngineFlagDiverges) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  StepObservation bad_state = at(3, kRestKe);
  bad_state.state_finite = false;
  StepObservation engine_flag = at(3, kRestKe);
  engine_flag.engine_non_finite = true;
  for (const StepObservation& bad : {at(3, nan), at(3, inf), bad_state, engine_flag}) {
    RunMonitor mon(rules(1));
    mon.observe(at(1, 5.0));
    mon.observe(at(2, kMovingKe));
    EXPECT_TRUE(mon.observe(bad));
    const RunSummary s = mon.summary();
    EXPECT_TRUE(s.diverged);
    EXPECT_EQ(s.divergence_reason, "non-finite state at step 3");
    EXPECT_EQ(s.steps_run, 3);
    // the peak keeps the last finite value against a NaN (std::max), and takes an inf
    if (std::isinf(bad.kinetic_energy)) {
      EXPECT_TRUE(std::isinf(s.peak_kinetic_energy));
    } else {
      EXPECT_EQ(s.peak_kinetic_energy, 5.0);
    }
  }
}

TEST(RunMonitor, DivergenceAfterConvergenceKeepsBothFlags) {
  // the divergence step does not run the rest test: an earlier convergence stays reported
  RunMonitor mon(rules(2));
  mon.observe(at(1, kRestKe));
  mon.observe(at(2, kRestKe));
  ASSERT_TRUE(mon.converged());
  EXPECT_TRUE(mon.observe(at(3, 1e9)));
  EXPECT_TRUE(mon.summary().diverged);
  EXPECT_TRUE(mon.summary().converged);
  EXPECT_EQ(mon.summary().steps_to_converge, 1);
}

TEST(RunMonitor, RunStatisticsArePeaksAndMeansOverTheSteps) {
  RunMonitor mon(rules());
  const int passes[] = {3, 7, 2, 4};
  const double ke[] = {0.5, 2.0, 1.0, 0.25};
  const double sep[] = {1e-4, 3e-3, 2e-3, 0.0};
  const double viol[] = {0.0, 0.1, 0.05, 0.0};  // rad
  for (int k = 0; k < 4; ++k) {
    StepObservation o = at(k + 1, ke[k]);
    o.passes = passes[k];
    o.joint_separation = sep[k];
    o.limit_violation = viol[k];
    mon.observe(o);
  }
  const RunSummary s = mon.summary();
  EXPECT_EQ(s.steps_run, 4);
  EXPECT_EQ(s.max_passes_in_a_step, 7);
  EXPECT_DOUBLE_EQ(s.mean_passes_per_step, 16.0 / 4.0);
  EXPECT_EQ(s.peak_kinetic_energy, 2.0);
  EXPECT_EQ(s.max_joint_separation, 3e-3);
  EXPECT_NEAR(s.max_limit_violation_deg, 0.1 * 180.0 / kPi, 1e-12);
}

TEST(RunMonitor, NoStepsGiveAnEmptySummary) {
  const RunSummary s = RunMonitor(rules()).summary();
  EXPECT_FALSE(s.converged);
  EXPECT_FALSE(s.diverged);
  EXPECT_EQ(s.steps_run, 0);
  EXPECT_EQ(s.steps_to_converge, -1);
  EXPECT_EQ(s.mean_passes_per_step, 0.0);
}

TEST(RunRules, TakenFromTheScene) {
  Scene scene = test::scene_for(test::one_rod(2.0, 3.0), test::bare_params());
  scene.control_points.push_back(test::control(0, 1.0, Vec3(0, 0, 2), 10.0));
  scene.schedule = {{40, 0, Vec3(1, 0, 0)}, {15, 0, Vec3(0, 1, 0)}};
  scene.convergence.settle_steps = 7;
  scene.convergence.stop_when_converged = true;
  const RunRules r = run_rules(scene);
  EXPECT_DOUBLE_EQ(r.speed_tol, 1e-3 * scene.rig.length_scale());  // the rod: 2e-3
  EXPECT_EQ(r.energy_bound, 0.0);    // no fixed bound given: the energy rule
  EXPECT_EQ(r.initial_energy, 0.0);  // at rest, no limit engaged
  EXPECT_DOUBLE_EQ(r.energy_floor, 0.5 * 3.0 * r.speed_tol * r.speed_tol);
  scene.convergence.divergence_energy = 50.0;
  scene.initial_velocity_world = Vec3(0, 2, 0);
  EXPECT_EQ(run_rules(scene).energy_bound, 50.0);
  EXPECT_DOUBLE_EQ(run_rules(scene).initial_energy, 0.5 * 3.0 * 4.0);
  EXPECT_DOUBLE_EQ(r.total_mass, 3.0);
  EXPECT_EQ(r.last_event, 40);
  EXPECT_EQ(r.settle_steps, 7);
  EXPECT_TRUE(r.stop_when_converged);
}

TEST(StateFinite, ANonFiniteVelocityOrOrientationIsCaught) {
  Scene scene = test::scene_for(test::one_rod(), test::bare_params());
  SimState s;
  init_state(scene, s);
  EXPECT_TRUE(state_finite(s));
  SimState bad = s;
  bad.omega_world[0].x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(state_finite(bad));
  bad = s;
  bad.frames.orient_world[0].w() = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(state_finite(bad));
}

TEST(ObserveStep, ReadsTheStateAndStats) {
  Scene scene = test::scene_for(test::one_rod(), test::bare_params());
  scene.control_points.push_back(test::control(0, 1.0, Vec3(0, 0, 1), 10.0));
  SimState s;
  init_state(scene, s);
  s.step = 9;
  s.interp_steps_left[0] = 2;
  StepStats st;
  st.kinetic_energy = 0.3;
  st.passes = 4;
  st.joint_separation = 1e-3;
  const StepObservation o = observe_step(scene, s, st);
  EXPECT_EQ(o.step, 9);
  EXPECT_EQ(o.kinetic_energy, 0.3);
  EXPECT_EQ(o.passes, 4);
  EXPECT_EQ(o.joint_separation, 1e-3);
  EXPECT_TRUE(o.state_finite);
  EXPECT_FALSE(o.engine_non_finite);
  EXPECT_TRUE(o.target_moving);
  EXPECT_EQ(o.limit_violation, 0.0);  // the rest pose of a free rod
  s.interp_steps_left[0] = 0;
  EXPECT_FALSE(observe_step(scene, s, st).target_moving);
}

}  // namespace
}  // namespace physik

namespace physik {
namespace {

// IK use: converged as soon as every control point is within the tolerance (even while still
// moving); a residual that stops improving stops the run without converging, like a stalled
// classic solver, however fast the rig still moves
TEST(RunMonitorResidual, StopsAtTheResidualToleranceOrWhenItStalls) {
  RunRules r = rules(3);
  r.stop_at_residual = true;
  r.residual_tol = 0.01;
  r.stall_steps = 4;
  r.stall_fraction = 0.1;
  {
    RunMonitor mon(r);
    StepObservation o = at(1, kMovingKe);
    o.max_residual = 0.5;
    EXPECT_FALSE(mon.observe(o));
    o = at(2, kMovingKe);
    o.max_residual = 0.009;  // met, while still moving
    EXPECT_TRUE(mon.observe(o));
    EXPECT_TRUE(mon.converged());
    EXPECT_EQ(mon.summary().steps_to_converge, 2);
  }
  {
    // improving by 20% a step never stalls; a plateau at 0.2 stalls 4 steps after its start
    RunMonitor mon(r);
    double res = 1.0;
    int k = 1;
    for (; k <= 8; ++k, res *= 0.8) {
      StepObservation o = at(k, kMovingKe);
      o.max_residual = res;
      EXPECT_FALSE(mon.observe(o)) << k;
    }
    // the plateau's first value (0.8^8) is still a 20% improvement on step 8: the last one
    const int last_improvement = k;
    for (;; ++k) {
      StepObservation o = at(k, kMovingKe);
      o.max_residual = res;  // no longer improving
      if (mon.observe(o)) break;
      ASSERT_LT(k, 100);
    }
    EXPECT_EQ(k, last_improvement + 4);
    EXPECT_FALSE(mon.converged());
    EXPECT_EQ(mon.summary().steps_to_converge, -1);
  }
  {
    // a target still interpolating does not count as met
    RunMonitor mon(r);
    StepObservation o = at(1, kMovingKe);
    o.max_residual = 0.0;
    o.target_moving = true;
    EXPECT_FALSE(mon.observe(o));
  }
}

}  // namespace
}  // namespace physik
