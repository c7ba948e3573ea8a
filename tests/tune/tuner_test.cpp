// Tuning recovers closed-form optima of the settle objective on one degree of freedom, and
// rejects bad input.
//
// The 1-DOF case: one free rod (mass m, along z), a linear control spring k at its centre
// (alpha = 1/2, so no torque), target offset x0 sideways, damping c at both ends (no rotation
// starts: the two damping torques cancel). PhysIK's articulated scheme moves the root by
// semi-implicit Euler with step h:
//   v' = v + h (-k x - 2 c v) / m,   x' = x + h v'.
// With w = h v, a = k h^2 / m, b = 2 c h / m the map is
//   [x'; w'] = A [x; w],  A = [[1 - a, 1 - b], [-a, 1 - b]],  trace 2 - a - b, det 1 - b,
// starting at (x0, 0).
//
// Linear measure (ISE): J(b) = sum_{n>=1} x_n^2 (times constants). P = sum_n (A^T)^n C^T C A^n
// with C = [1 0] solves the Lyapunov equation A^T P A - P + C^T C = 0, and J = P_11 - 1 for
// x0 = 1. Solving the 2x2 system (sympy):
//   J = -(a^2 b + 2 a b^2 - 6 a b + 2 a - b^3 + 2 b^2) / (a b (a + 2 b - 4)),
// and dJ/db = 0 reduces to   b^2 (b - 2)^2 + a (b - 2)(b^2 - b + 2) + a^2 = 0,
// a quadratic in a. So the optimum b* is known through its inverse: for a chosen b*,
//   a = (2 - b*)/2 [ (b*^2 - b* + 2) - sqrt((1 - b*)(2 - b*)(b*^2 + b* + 2)) ]
// is the stiffness for which b* minimises J (the smaller root; both roots are minima). We pick
// b* = 1/2 (a = 0.2354), set k = a m / h^2 and expect c* = b* m / (2 h). (For small a,
// b* -> sqrt(a): damping ratio 1/2, the continuous-time ISE optimum.)
//
// Log measure: rho_n = ln(1 + |x_n| / eps). For a = 1 (k = m / h^2) the first step lands on the
// target for every b (x_1 = (1 - a) x0 = 0) with w_1 = -a x0, and x_2 = x_1 + (1 - b) w_1 - a x_1
// = -(1 - b) x0: only b = 1 makes every later x_n zero (dead beat: both eigenvalues of A are 0,
// the double root b = 2 sqrt(a) - a = 1). So c* = m / (2 h) is the unique global minimum of any
// objective that is zero only at zero error, the log measure included.
#include <cmath>
#include <tuple>

#include <gtest/gtest.h>

#include "physik/io/rig_io.h"
#include "physik/io/scene_io.h"
#include "physik/model/errors.h"
#include "tests/test_util.h"
#include "tune/tuner.h"

namespace physik::tune {
namespace {

// one rod of mass m along z, a linear spring k on its centre pulled 1 unit along +x
Scene rod_scene(double m, double k, double dt) {
  BoneSpec b;
  b.name = "rod";
  b.head_world = Vec3(0, 0, 0);
  b.tail_world = Vec3(0, 0, 1);
  b.rest_frame_world = rest_frame_from_roll(b.head_world, b.tail_world, 0.0);
  b.mass = m;
  Scene s;
  s.file = "rod";
  s.rig = build_rig({b}, "rod");
  s.params = preset_params("original");
  s.params.dt = dt;
  s.params.interpolation = Interpolation::kNone;
  ControlPoint cp;
  cp.bone = 0;
  cp.alpha = 0.5;
  cp.target_world = Vec3(1, 0, 0.5);
  s.params.control_k = k;  // linear (the preset's law), k from the params
  s.control_points.push_back(cp);
  s.steps = 400;
  s.initial_pose = rest_pose(s.rig);
  return s;
}

TEST(Tuner, LinearMeasureRecoversTheClosedFormIseOptimum) {
  const double m = 2.0, h = 0.05, bstar = 0.5;
  const double a = (2 - bstar) / 2 *
                   ((bstar * bstar - bstar + 2) -
                    std::sqrt((1 - bstar) * (2 - bstar) * (bstar * bstar + bstar + 2)));
  // the stationarity polynomial vanishes at (a, b*)
  EXPECT_NEAR(bstar * bstar * (bstar - 2) * (bstar - 2) +
                  a * (bstar - 2) * (bstar * bstar - bstar + 2) + a * a,
              0.0, 1e-12);
  const Scene s = rod_scene(m, a * m / (h * h), h);
  const double c_star = bstar * m / (2 * h);  // 10 N s/m
  TuneOptions opt;
  opt.params = parse_tune_params("damping", "test");
  opt.measure = SettleMeasure::kLinear;
  const TuneResult r = tune_scene(s, opt);
  ASSERT_EQ(r.values.size(), 1u);
  EXPECT_NEAR(r.values[0], c_star, 0.05 * c_star) << r.ceres_brief;
  EXPECT_LE(r.final_cost, r.initial_cost);
  EXPECT_FALSE(r.tuned_run.diverged);
}

TEST(Tuner, LogMeasureRecoversTheDeadBeatDamping) {
  const double m = 1.5, h = 0.05;
  const Scene s = rod_scene(m, m / (h * h), h);  // a = 1
  const double c_star = m / (2 * h);             // b = 1: 15 N s/m
  TuneOptions opt;
  opt.params = parse_tune_params("damping", "test");
  opt.measure = SettleMeasure::kLog;
  const TuneResult r = tune_scene(s, opt);
  EXPECT_NEAR(r.values[0], c_star, 0.05 * c_star) << r.ceres_brief;
}

TEST(Tuner, DivergenceIsALargeFinitePenalty) {
  // b = 2 c h / m > 2 makes det(A) = 1 - b < -1: the run diverges
  const Scene stable = rod_scene(1.0, 10.0, 0.05);
  Scene unstable = stable;
  set_param(unstable, "damping", 40.0);  // b = 4
  unstable.steps = 2000;
  std::vector<double> rs, ru;
  settle_residuals(stable, SettleMeasure::kLog, rs);
  const RunSummary su = settle_residuals(unstable, SettleMeasure::kLog, ru);
  EXPECT_TRUE(su.diverged);
  const double cu = cost_of(ru);
  EXPECT_TRUE(std::isfinite(cu));
  EXPECT_GT(cu, 10 * cost_of(rs));
}

TEST(Tuner, ControlKAndCapReachThePointsThatGiveNone) {
  Scene s = rod_scene(1.0, 10.0, 0.05);
  s.control_points.push_back(s.control_points[0]);
  s.control_points[1].k = 20.0;  // a k and cap of its own stay fixed
  s.control_points[1].cap = 0.5;
  set_param(s, "control_k", 30.0);
  set_param(s, "control_cap", 2.0);
  EXPECT_EQ(get_param(s, "control_k"), 30.0);
  EXPECT_EQ(get_param(s, "control_cap"), 2.0);
  EXPECT_EQ(s.control_points[0].k_in(s.params), 30.0);
  EXPECT_EQ(s.control_points[1].k_in(s.params), 20.0);
  EXPECT_EQ(s.control_points[0].cap_in(s.params), 2.0);
  EXPECT_EQ(s.control_points[1].cap_in(s.params), 0.5);
  // the rod tuned to k = 40 runs as the rod built with k = 40
  Scene tuned = rod_scene(1.0, 10.0, 0.05);
  set_param(tuned, "control_k", 40.0);
  EXPECT_EQ(state_hash(run_scene(tuned).final_frames),
            state_hash(run_scene(rod_scene(1.0, 40.0, 0.05)).final_frames));
}

// A scene with damping auto runs at auto's choice, not at params.damping (which it never reads):
// the tuner's baseline is that run. Its J equals the objective of the scene as it is, the start
// is auto's choice (the value the run reports), and with no target change fixing damping at that
// value runs the same scene, so the start's J is the baseline's.
TEST(Tuner, TheBaselineOfADampingAutoSceneIsTheSceneAsItRuns) {
  Scene s = load_scene(test::model_path("scenes/fig6_elbow_linear.json"));
  s.params.damping_auto = true;
  s.steps = 300;
  ASSERT_TRUE(s.schedule.empty());  // no target change: auto chooses once
  std::vector<double> res;
  settle_residuals(s, SettleMeasure::kLog, res);
  const double scene_cost = cost_of(res);
  const RunSummary run = run_scene(s);
  ASSERT_GT(run.damping_auto_value, 0.0);
  ASSERT_GT(std::abs(run.damping_auto_value - s.params.damping), 0.1);  // auto is not params'
  TuneOptions opt;
  opt.params = parse_tune_params("damping", "test");
  opt.scan_points = 3;
  opt.max_iterations = 2;
  const TuneResult r = tune_scene(s, opt);
  EXPECT_TRUE(r.damping_auto);
  EXPECT_EQ(r.damping_auto_updates, 1);
  EXPECT_NEAR(r.initial_cost, scene_cost, 1e-12 * scene_cost);
  EXPECT_NEAR(r.initial_values[0], run.damping_auto_value, 1e-12);
  EXPECT_NEAR(r.damping_auto_value, run.damping_auto_value, 1e-12);
  EXPECT_NEAR(r.start_cost, r.initial_cost, 1e-9 * scene_cost);
  EXPECT_EQ(r.scene_run.converged, run.converged);
  EXPECT_EQ(r.scene_run.steps_to_converge, run.steps_to_converge);
  EXPECT_LE(r.final_cost, r.start_cost);
  EXPECT_EQ(no_improvement(r), !(r.final_cost < scene_cost));
}

// A scene whose own value lies outside the bounds is still the baseline: the dead-beat rod (c* =
// 15 N s/m, J = the first step's residual only) tuned within [1, 5] cannot match it, and the
// result says there is no improvement, although the search improved on its clamped start (5).
TEST(Tuner, NoImprovementOverASceneOutsideTheBounds) {
  const double m = 1.5, h = 0.05;
  Scene s = rod_scene(m, m / (h * h), h);
  set_param(s, "damping", m / (2 * h));
  TuneOptions opt;
  opt.params = parse_tune_params("damping", "test");
  apply_bounds(opt.params, "damping=1:5", "test");
  opt.scan_points = 5;
  const TuneResult r = tune_scene(s, opt);
  std::vector<double> res;
  settle_residuals(s, SettleMeasure::kLog, res);
  EXPECT_NEAR(r.initial_cost, cost_of(res), 1e-12 * cost_of(res));
  EXPECT_EQ(r.initial_values[0], m / (2 * h));
  EXPECT_GT(r.start_cost, r.initial_cost);  // the start is clamped to 5
  EXPECT_LE(r.final_cost, r.start_cost);
  EXPECT_GT(r.final_cost, r.initial_cost);
  EXPECT_TRUE(no_improvement(r));
}

TEST(Tuner, EveryTunableIsATableRowWithItsBounds) {
  for (const TunableSpec& t : tunable_parameters()) {
    const ParamRow* row = find_param(t.name);
    ASSERT_NE(row, nullptr) << t.name;
    ASSERT_TRUE(row->tune.has_value());
    EXPECT_EQ(row->tune->first, t.lo);
    EXPECT_EQ(row->tune->second, t.hi);
    Scene s = rod_scene(1.0, 10.0, 0.05);
    set_param(s, t.name, t.hi);  // through the table to the field
    EXPECT_EQ(row->get(s.params), t.hi);
    EXPECT_EQ(get_param(s, t.name), t.hi);
  }
  // today's bounds
  const std::vector<std::tuple<std::string, double, double>> expected = {
      {"damping", 0.01, 100.0},   {"angular_velocity_factor", 0.01, 1.0},
      {"control_k", 0.1, 1000.0}, {"control_cap", 0.01, 100.0},
      {"torsion_k", 0.1, 1000.0}, {"torsion_cap", 0.01, 3.2}};
  ASSERT_EQ(tunable_parameters().size(), expected.size());
  for (const auto& [name, lo, hi] : expected) {
    const auto params = parse_tune_params(name, "--params");
    EXPECT_EQ(params[0].lo, lo) << name;
    EXPECT_EQ(params[0].hi, hi) << name;
  }
  Scene s = rod_scene(1.0, 10.0, 0.05);
  EXPECT_THROW(set_param(s, "dt", 0.01), InputError);  // a row, but not a tunable one
}

TEST(Tuner, BadInputs) {
  EXPECT_THROW(parse_tune_params("damping,bogus", "--params"), InputError);
  EXPECT_THROW(parse_tune_params("damping,damping", "--params"), InputError);
  EXPECT_THROW(parse_tune_params("", "--params"), InputError);
  try {
    parse_tune_params("bogus", "--params");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bogus"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("unknown tunable parameter"), std::string::npos);
  }
  auto p = parse_tune_params("damping", "--params");
  EXPECT_THROW(apply_bounds(p, "damping=2:1", "--bounds"), InputError);
  EXPECT_THROW(apply_bounds(p, "damping=0:1", "--bounds"), InputError);
  EXPECT_THROW(apply_bounds(p, "damping=x:1", "--bounds"), InputError);
  EXPECT_THROW(apply_bounds(p, "torsion_k=1:2", "--bounds"), InputError);
  EXPECT_THROW(apply_bounds(p, "damping", "--bounds"), InputError);
  apply_bounds(p, "damping=0.5:2", "--bounds");
  EXPECT_DOUBLE_EQ(p[0].lo, 0.5);
  EXPECT_DOUBLE_EQ(p[0].hi, 2.0);
  EXPECT_THROW(objective_from_string("fast", "--objective"), InputError);
  EXPECT_THROW(measure_from_string("cubic", "--measure"), InputError);
  Scene none = rod_scene(1.0, 10.0, 0.05);
  none.control_points.clear();
  TuneOptions opt;
  opt.params = p;
  EXPECT_THROW(tune_scene(none, opt), InputError);
  opt.params.clear();
  EXPECT_THROW(tune_scene(rod_scene(1.0, 10.0, 0.05), opt), InputError);
}

}  // namespace
}  // namespace physik::tune

namespace physik::tune {
namespace {

TEST(Tuner, MujocoObjectiveIdentifiesTheDampingOfAFreeRod) {
  // one free rod pulled at its tail (it turns and translates): PhysIK and MuJoCo's same-forces
  // run integrate the same free body the same way, so the damping MuJoCo was given is the
  // unique zero of the trajectory gap, and tuning from another value must find it
  Scene truth = rod_scene(1.0, 10.0, 0.05);
  truth.control_points[0].alpha = 1.0;
  truth.control_points[0].target_world = Vec3(1.0, 0.5, 1.5);
  truth.steps = 200;
  set_param(truth, "damping", 1.7);
  Scene start = truth;
  set_param(start, "damping", 0.4);
  TuneOptions opt;
  opt.params = parse_tune_params("damping", "test");
  opt.objective = Objective::kMujoco;
  opt.mujoco_scene = &truth;
  const TuneResult r = tune_scene(start, opt);
  EXPECT_EQ(r.reference_steps, 200);
  EXPECT_NEAR(r.values[0], 1.7, 0.01 * 1.7) << r.ceres_brief;
  EXPECT_LT(r.final_cost, 1e-3 * r.initial_cost);
}

}  // namespace
}  // namespace physik::tune
