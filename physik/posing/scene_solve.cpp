#include "physik/posing/scene_solve.h"

#include <chrono>
#include <cmath>

#include "physik/engine/engine.h"
#include "physik/engine/measures.h"
#include "physik/model/errors.h"
#include "physik/model/message_number.h"

namespace physik {

namespace {

// the outside solvers registered (register_outside_solver), by name
std::vector<std::pair<std::string, OutsideSolver>>& outside_solvers() {
  static std::vector<std::pair<std::string, OutsideSolver>> solvers;
  return solvers;
}

OutsideSolver find_outside_solver(const std::string& name) {
  for (const auto& [n, f] : outside_solvers()) {
    if (n == name) return f;
  }
  return nullptr;
}

bool outside_solver(const std::string& s) {
  return s == "kdl" || s == "kdl-nr";
}

bool engine_solver(const std::string& s) {
  return s == "physik" || s == "physik-steps" || s == "physik-explicit";
}

bool jacobian_solver(const std::string& s) {
  return s == "dls" || s == "jt";
}

// The classic solvers, and the classic finish after the engine, know the rig's geometry, its
// limits and the control points only: a scene's ground, self-collision, gravity or aim targets
// would be ignored by them, so such a scene is refused rather than solved as if it had none.
// DLS and the Jacobian transpose also take orientation targets (orientation rows) and pins (a
// position goal each, classic_goals); the other classic solvers and the finish refuse them.
void refuse_unread_world(const Scene& scene, const SceneSolveOptions& o) {
  const bool classic = !engine_solver(o.solver);
  if (!classic && o.finish == "none") return;
  const char* field = scene.world_field();
  if (!field) return;
  const std::string f = field;
  const bool bone_target = f == "orientation_targets" || f == "pins";
  // world_field's order puts the ground, contacts and gravity first and aims between the two
  if (classic && jacobian_solver(o.solver) && bone_target) {
    if (scene.aim_targets.empty()) return;
    field = "aim_targets";
  }
  const std::string who = classic ? "the " + o.solver + " solver" : "the " + o.finish + " finish";
  const std::string what = std::string(field) == "orientation_targets" ? "orientation targets"
                           : std::string(field) == "aim_targets"       ? "aim targets"
                           : std::string(field) == "pins"              ? "pins"
                                                                       : "";
  if (!what.empty()) {
    const bool dls_takes = std::string(field) != "aim_targets";
    throw_input_error(scene.file, field, "",
                      who + " does not support " + what + " (" +
                          (dls_takes && classic ? "--solver dls or jt takes them; " : "") +
                          "the engine does: --solver physik and no --finish)");
  }
  throw_input_error(scene.file, field, "",
                    who +
                        " does not read it (only the rig and the control points): solve this "
                        "scene with --solver physik and no --finish");
}

}  // namespace

std::vector<IkGoal> scene_goals(const Scene& scene) {
  std::vector<IkGoal> goals;
  for (const ControlPoint& c : scene.control_points)
    goals.push_back({c.bone, c.alpha, c.target_world});
  for (const TargetChange& ch : scene.schedule)
    goals[ch.control_point].target_world = ch.target_world;
  return goals;
}

std::vector<IkGoal> classic_goals(const Scene& scene) {
  std::vector<IkGoal> goals = scene_goals(scene);
  for (const Pin& p : scene.pins) goals.push_back({p.bone, p.alpha, p.point_world});
  for (const OrientationTarget& t : scene.orientation_targets) {
    IkGoal g{t.bone, 1.0, Vec3::Zero()};
    g.has_position = false;
    g.has_orientation = true;
    g.orientation_world = t.target_world;
    goals.push_back(g);
  }
  return goals;
}

namespace {

IkOptions classic_options(const SceneSolveOptions& o);

// the engine in a posing session (physik/posing/posing_session.h): the solve mode (physik) or the
// scene's engine at its dt (physik-explicit); see scene_solve.h
SceneSolveResult solve_with_engine(Scene& scene, const SceneSolveOptions& o,
                                   const StepObserver& observer) {
  const bool equilibrium = o.solver == "physik", steps_mode = o.solver == "physik-steps";
  if (equilibrium || steps_mode) use_solve_mode(scene);
  SolveRule rule;
  rule.method = equilibrium ? SolveMethod::kEquilibrium : SolveMethod::kSteps;
  rule.tolerance = o.tol > 0.0 ? o.tol : 1e-4 * goals_reach(scene);
  rule.tolerance_angle = o.tol_angle;
  // the equilibrium's iterations are the classic solvers' (max_iterations); the physics' steps
  // are the scene's
  rule.max_steps = equilibrium ? o.max_iterations : scene.steps;
  rule.dt_growth = steps_mode ? o.dt_growth : 1.0;
  rule.max_dt = o.max_dt;
  rule.armature = o.armature;
  rule.finish = o.finish == "ccd"   ? SolveFinish::kCcd
                : o.finish == "dls" ? SolveFinish::kDls
                                    : SolveFinish::kNone;
  rule.finish_options = classic_options(o);  // --lambda, --max-iterations, --no-limits, ...
  PosingSession session(scene);  // the solver object: rig, state and buffers, before the clock
  const auto t0 = std::chrono::steady_clock::now();
  SceneSolveResult r;
  r.solve = session.solve(rule, observer);
  r.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.engine = true;
  r.rule = rule;
  r.scene = session.scene();
  r.run = session.summary(r.solve);
  r.run.wall_time_s = r.time_s;
  r.frames = r.run.final_frames;
  r.pose = r.run.final_pose;
  r.diverged = r.solve.diverged;
  r.warning = r.run.joint_solve_warning;
  return r;
}

IkOptions classic_options(const SceneSolveOptions& o) {
  IkOptions opt;
  opt.tolerance = o.tol;
  opt.max_iterations = o.max_iterations;
  opt.lambda = o.lambda;
  opt.respect_limits = !o.no_limits;
  opt.rotation_damping = o.rotation_damping;
  if (o.jacobian == "fd")
    opt.jacobian = JacobianKind::kFiniteDifference;
  else if (o.jacobian != "analytic")
    throw_input_error("--jacobian", "", o.jacobian, "analytic or fd");
  if (o.gravity.size() == 3) opt.gravity_world = Vec3(o.gravity[0], o.gravity[1], o.gravity[2]);
  if (o.socket == "virtual-bone")
    opt.socket_mode = SocketMode::kVirtualBone;
  else if (o.socket != "twist-bend")
    throw_input_error("--socket", "", o.socket, "twist-bend or virtual-bone");
  if (o.cone == "none")
    opt.cone_shape = ConeShape::kNone;
  else if (o.cone == "circular")
    opt.cone_shape = ConeShape::kCircular;
  else if (o.cone != "elliptical")
    throw_input_error("--cone", "", o.cone, "none, circular or elliptical");
  return opt;
}

SceneSolveResult solve_classic(const Scene& scene, const SceneSolveOptions& o,
                               const std::vector<IkGoal>& goals) {
  IkMethod method{};
  ik_method_from_string(o.solver, method);
  const IkOptions opt = classic_options(o);
  SceneSolveResult r;
  r.scene = scene;
  r.pose = scene.initial_pose;
  r.classic = solve_ik(method, scene.rig, classic_goals(scene), r.pose, opt);
  // the goals' residuals split: control points, pins (rig units), orientation targets (rad)
  const std::size_t ncp = goals.size(), npin = scene.pins.size();
  std::vector<double>& res = r.classic.residuals;
  r.pin_residuals.assign(res.begin() + ncp, res.begin() + ncp + npin);
  std::vector<double>& ores = r.classic.orientation_residuals;
  ores.erase(ores.begin(), ores.begin() + ncp + npin);
  res.resize(ncp);
  r.time_s = r.classic.time_s;
  r.frames = forward_kinematics(scene.rig, r.pose);
  return r;
}

}  // namespace

std::vector<GoalReport> goal_reports(const SceneSolveResult& r) {
  const Scene& scene = r.scene;
  std::vector<Vec3> targets;
  for (const IkGoal& g : scene_goals(scene)) targets.push_back(g.target_world);
  const GoalTolerance tol =
      r.engine ? r.solve.goal_tolerance()
               : GoalTolerance{r.classic.tolerance, r.classic.orientation_tolerance > 0.0
                                                        ? r.classic.orientation_tolerance
                                                        : kDefaultTolAngle};
  std::vector<GoalReport> out;
  for (int g = 0; g < goal_count(scene); ++g) {
    const GoalKind kind = goal_ref(scene, g).kind;
    out.push_back(
        {goal_label(scene, g), kind, goal_residual(scene, r.frames, targets, g), tol.of(kind)});
  }
  return out;
}

namespace {

// "; short: control point 0 on 'hand' 0.1 rig units (tolerance 0.0001), ..." or ""
std::string short_goals_text(const SceneSolveResult& r) {
  std::string out;
  for (const GoalReport& g : goal_reports(r)) {
    if (g.met()) continue;
    out += (out.empty() ? "; short: " : ", ") + g.goal + " " + message_number(g.residual) + " " +
           goal_unit(g.kind) + " (tolerance " + message_number(g.tolerance) + ")";
  }
  return out;
}

}  // namespace

std::string solve_shortfall(const SceneSolveResult& r) {
  const std::string residual = "residual " +
                               message_number(r.engine ? r.solve.residual : r.classic.residual) +
                               " rig units, above the tolerance " +
                               message_number(r.engine ? r.solve.tolerance : r.classic.tolerance);
  if (!r.engine) {
    if (r.classic.converged) return "";
    const std::string orientation =
        r.scene.orientation_targets.empty()
            ? ""
            : ", orientation residual " + message_number(r.classic.orientation_residual) +
                  " rad (tolerance " + message_number(r.classic.orientation_tolerance) + ")";
    return r.solver +
           (r.classic.stalled ? " stalled (the residual stopped improving)"
                              : " used its iterations (max_iterations)") +
           " after " + std::to_string(r.classic.iterations) + " iterations at " + residual +
           orientation + short_goals_text(r);
  }
  if (r.diverged || r.solve.converged) return "";
  std::string why;
  if (r.solve.method == SolveMethod::kEquilibrium) {
    why = r.solve.stationary
              ? "the equilibrium solve reached a rest pose (a stationary point of the potential)"
          : r.solve.stalled ? "the equilibrium solve stalled (no goal improved)"
                            : "the equilibrium solve used its iterations (max_iterations)";
    why += " after " + std::to_string(r.solve.steps) + " iterations";
  } else {
    why = r.solve.stalled ? "the physics stalled (no goal improved)"
                          : "the physics used the scene's steps";
    why += " after " + std::to_string(r.solve.steps) + " steps";
  }
  if (r.solve.finish_iterations > 0) {
    why += ", then the " + std::string(r.rule.finish == SolveFinish::kCcd ? "ccd" : "dls") +
           " finish " + std::to_string(r.solve.finish_iterations) + " iterations";
  }
  return why + ", at " + residual + short_goals_text(r);
}

void register_outside_solver(const std::string& name, OutsideSolver solver) {
  for (auto& entry : outside_solvers()) {
    if (entry.first == name) {
      entry.second = solver;
      return;
    }
  }
  outside_solvers().emplace_back(name, solver);
}

SceneSolveResult solve_scene(Scene scene, const SceneSolveOptions& o, OptionSpelling spelling,
                             const StepObserver& observer) {
  check_solve_options(o, spelling);
  if (scene.control_points.empty() && scene.orientation_targets.empty() &&
      scene.aim_targets.empty()) {
    throw_input_error(scene.file, "control_points", "",
                      "a solve needs a goal: a control point, an orientation target or an aim "
                      "(pins hold, they do not pull)");
  }
  if (outside_solver(o.solver)) {
    const OutsideSolver solve = find_outside_solver(o.solver);
    if (!solve) {
      throw_input_error(option_label("solver", spelling), "", o.solver,
                        "not in this program (its layer, kdl/, registers it: the physik command "
                        "and the Python module have it)");
    }
    SceneSolveResult r = solve(scene, o);  // it refuses what it cannot take (InputError)
    r.solver = o.solver;
    return r;
  }
  refuse_unread_world(scene, o);
  SceneSolveResult r = engine_solver(o.solver) ? solve_with_engine(scene, o, observer)
                                               : solve_classic(scene, o, scene_goals(scene));
  r.solver = o.solver;
  return r;
}

}  // namespace physik
