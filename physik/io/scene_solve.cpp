#include "physik/io/scene_solve.h"

#include <chrono>
#include <cmath>

#include "physik/engine/engine.h"
#include "physik/io/summary_io.h"
#include "physik/model/errors.h"

namespace physik {

const char* const kSceneSolvers = "fabrik|ccd|jt|dls|mass-spring|rotation|physik|physik-explicit";

namespace {

bool engine_solver(const std::string& s) { return s == "physik" || s == "physik-explicit"; }

}  // namespace

void check_solve_options(const SceneSolveOptions& o) {
  IkMethod method{};
  if (!engine_solver(o.solver) && !ik_method_from_string(o.solver, method)) {
    throw_input_error("--solver", "", "", "unknown solver '" + o.solver + "'; one of " + kSceneSolvers);
  }
  if (!(o.dt_growth >= 1.0) || !std::isfinite(o.dt_growth)) {
    throw_input_error("--dt-growth", "", "", "must be a number >= 1 (1 = a fixed step)");
  }
  if (!(o.max_dt > 0.0) || !std::isfinite(o.max_dt)) {
    throw_input_error("--max-dt", "", "", "must be a positive number of seconds");
  }
  if (o.finish != "none" && o.finish != "ccd" && o.finish != "dls") {
    throw_input_error("--finish", "", "", "unknown finish '" + o.finish + "'; one of none|ccd|dls");
  }
  if (!(o.tol >= 0.0) || !std::isfinite(o.tol)) {
    throw_input_error("--tol", "", "", "must be a finite number >= 0 (0 = 1e-4 of the reach)");
  }
  if (!(o.lambda >= 0.0) || !std::isfinite(o.lambda)) {
    throw_input_error("--lambda", "", "", "must be a finite number >= 0 (0 = 0.02 of the reach)");
  }
  if (!(o.rotation_damping >= 0.0 && o.rotation_damping <= 1.0)) {
    throw_input_error("--rotation-damping", "", "", "must lie in [0, 1]");
  }
  if (o.max_iterations < 0) throw_input_error("--max-iterations", "", "", "must not be negative");
  if (!o.gravity.empty() && o.gravity.size() != 3) {
    throw_input_error("--gravity", "", "", "expected three numbers");
  }
  for (double g : o.gravity) {
    if (!std::isfinite(g)) throw_input_error("--gravity", "", "", "not a finite number");
  }
}

std::vector<IkGoal> scene_goals(const Scene& scene) {
  std::vector<IkGoal> goals;
  for (const ControlPoint& c : scene.control_points) goals.push_back({c.bone, c.alpha, c.target_world});
  for (const TargetChange& ch : scene.schedule) goals[ch.control_point].target_world = ch.target_world;
  return goals;
}

namespace {

IkOptions classic_options(const SceneSolveOptions& o);

// the engine in a posing session (physik/posing/posing_session.h): the solve mode (physik) or the
// scene's engine at its dt (physik-explicit); see scene_solve.h
SceneSolveResult solve_with_engine(Scene& scene, const SceneSolveOptions& o,
                                   const std::vector<IkGoal>& goals) {
  const bool mode = o.solver == "physik";
  if (mode) use_solve_mode(scene);
  SolveRule rule;
  rule.tolerance = o.tol > 0.0 ? o.tol : 1e-4 * chain_reach(scene.rig, goals);
  rule.max_steps = scene.steps;
  rule.dt_growth = mode ? o.dt_growth : 1.0;
  rule.max_dt = o.max_dt;
  rule.finish = o.finish == "ccd" ? SolveFinish::kCcd : o.finish == "dls" ? SolveFinish::kDls
                                                                          : SolveFinish::kNone;
  rule.finish_options = classic_options(o);  // --lambda, --max-iterations, --no-limits, ...
  PosingSession session(scene);  // the solver object: rig, state and buffers, before the clock
  const auto t0 = std::chrono::steady_clock::now();
  const SolveResult res = session.solve(rule);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  RunSummary s = session.summary(res);
  s.wall_time_s = seconds;
  SceneSolveResult r;
  r.summary = summary_to_json(session.scene(), s);
  r.summary["iterations"] = res.steps;
  r.summary["time_s"] = seconds;
  r.summary["residual"] = res.residual;
  r.summary["residual_tol"] = res.tolerance;
  r.summary["stalled"] = res.stalled;
  r.summary["out_of_steps"] = res.out_of_steps;
  r.summary["finish"] = o.finish;
  r.summary["finish_iterations"] = res.finish_iterations;
  if (mode) {
    r.summary["dt_growth"] = rule.dt_growth;
    r.summary["max_dt"] = rule.max_dt;
  }
  r.frames = s.final_frames;
  r.pose = s.final_pose;
  r.diverged = res.diverged;
  r.warning = s.joint_solve_warning;
  return r;
}

IkOptions classic_options(const SceneSolveOptions& o) {
  IkOptions opt;
  opt.tolerance = o.tol;
  opt.max_iterations = o.max_iterations;
  opt.lambda = o.lambda;
  opt.respect_limits = !o.no_limits;
  opt.rotation_damping = o.rotation_damping;
  if (o.jacobian == "fd") opt.jacobian = JacobianKind::kFiniteDifference;
  else if (o.jacobian != "analytic") throw_input_error("--jacobian", "", o.jacobian, "analytic or fd");
  if (o.gravity.size() == 3) opt.gravity_world = Vec3(o.gravity[0], o.gravity[1], o.gravity[2]);
  if (o.socket == "virtual-bone") opt.socket_mode = SocketMode::kVirtualBone;
  else if (o.socket != "twist-bend") throw_input_error("--socket", "", o.socket, "twist-bend or virtual-bone");
  if (o.cone == "none") opt.cone_shape = ConeShape::kNone;
  else if (o.cone == "circular") opt.cone_shape = ConeShape::kCircular;
  else if (o.cone != "elliptical") throw_input_error("--cone", "", o.cone, "none, circular or elliptical");
  return opt;
}

SceneSolveResult solve_classic(const Scene& scene, const SceneSolveOptions& o,
                               const std::vector<IkGoal>& goals) {
  IkMethod method{};
  ik_method_from_string(o.solver, method);
  const IkOptions opt = classic_options(o);
  SceneSolveResult r;
  r.pose = scene.initial_pose;
  const IkReport rep = solve_ik(method, scene.rig, goals, r.pose, opt);
  r.frames = forward_kinematics(scene.rig, r.pose);
  r.summary = {{"scene", scene.file},
               {"rig", scene.rig_file},
               {"converged", rep.converged},
               {"diverged", false},
               {"stalled", rep.stalled},
               {"iterations", rep.iterations},
               {"final_residuals", rep.residuals},
               {"residual", rep.residual},
               {"residual_tol", rep.tolerance},
               {"reach", rep.reach},
               {"max_limit_violation_deg", rad2deg(max_limit_violation(scene.rig, r.pose))},
               {"time_s", rep.time_s}};
  return r;
}

}  // namespace

SceneSolveResult solve_scene(Scene scene, const SceneSolveOptions& o) {
  check_solve_options(o);
  if (scene.control_points.empty()) {
    throw_input_error(scene.file, "control_points", "", "a solve needs at least one control point");
  }
  const std::vector<IkGoal> goals = scene_goals(scene);
  SceneSolveResult r = engine_solver(o.solver) ? solve_with_engine(scene, o, goals)
                                                : solve_classic(scene, o, goals);
  r.summary["solver"] = o.solver;
  return r;
}

}  // namespace physik
