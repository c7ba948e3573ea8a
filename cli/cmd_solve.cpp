// physik solve SCENE --solver NAME: solve a scene's control points as IK goals with one of the
// classic solvers (physik/ik_solver.h) or with the PhysIK engine; writes final_pose.csv and a
// summary.json with the same keys as `physik simulate` (converged, final_residuals, ...).
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>

#include "cli/commands.h"
#include "physik/engine/engine.h"
#include "physik/ik/ik_solver.h"
#include "physik/io/json_fields.h"
#include "physik/io/pose_io.h"
#include "physik/io/scene_io.h"
#include "physik/io/summary_io.h"
#include "physik/model/errors.h"
#include "physik/model/scene.h"

namespace physik::cli {

namespace {

struct SolveOptions {
  std::string scene;
  std::string solver;
  std::string out = "out";
  double tol = 0.0;             // rig units; 0 = 1e-4 of the reach
  int max_iterations = 1000;
  double lambda = 0.0;          // rig units; 0 = 0.02 of the reach
  std::string jacobian = "analytic";
  std::vector<double> gravity;  // rig units/s^2, three components
  double rotation_damping = 0.8;
  std::string socket = "twist-bend";
  std::string cone = "elliptical";
  bool no_limits = false;
  bool quiet = false;
};

const char* kSolvers = "fabrik|ccd|jt|dls|mass-spring|rotation|physik";

// The goals: every control point at its final target (the last scheduled change, if any).
std::vector<IkGoal> scene_goals(const Scene& scene) {
  std::vector<IkGoal> goals;
  for (const ControlPoint& c : scene.control_points) goals.push_back({c.bone, c.alpha, c.target_world});
  for (const TargetChange& ch : scene.schedule) goals[ch.control_point].target_world = ch.target_world;
  return goals;
}

// The classic solvers' options from the command line's (bad values exit 2).
IkOptions ik_options(const SolveOptions& o) {
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

// What a solve produced: summary.json's content and the final pose.
struct Solution {
  nlohmann::json summary;
  BoneFrames frames;
  bool diverged = false;
  std::string divergence_reason;
};

// The engine stops like the classic solvers: at the residual tolerance (default 1e-4 of the
// chain's reach), or when the residual stalls short of it (not converged).
Solution solve_with_engine(Scene scene, const std::vector<IkGoal>& goals, double tol) {
  scene.convergence.residual_tol = tol > 0.0 ? tol : 1e-4 * chain_reach(scene.rig, goals);
  scene.convergence.stop_at_residual_tol = true;
  const RunSummary s = run_scene(scene);
  Solution out;
  out.summary = summary_to_json(scene, s);
  out.summary["iterations"] = s.steps_run;
  out.summary["time_s"] = s.wall_time_s;
  out.frames = s.final_frames;
  out.diverged = s.diverged;
  out.divergence_reason = s.divergence_reason;
  return out;
}

Solution solve_classic(IkMethod method, const Scene& scene, const std::vector<IkGoal>& goals,
                       const IkOptions& opt) {
  Pose pose = scene.initial_pose;
  const IkReport rep = solve_ik(method, scene.rig, goals, pose, opt);
  Solution out;
  out.frames = forward_kinematics(scene.rig, pose);
  out.summary = {{"scene", scene.file},
                 {"rig", scene.rig_file},
                 {"converged", rep.converged},
                 {"diverged", false},
                 {"stalled", rep.stalled},
                 {"iterations", rep.iterations},
                 {"final_residuals", rep.residuals},
                 {"residual", rep.residual},
                 {"residual_tol", rep.tolerance},
                 {"reach", rep.reach},
                 {"max_limit_violation_deg", rad2deg(max_limit_violation(scene.rig, pose))},
                 {"time_s", rep.time_s}};
  return out;
}

// final_pose.csv and summary.json, both written (and closed) before a divergence is reported
void write_solution(const Scene& scene, const Solution& sol, const std::string& out) {
  std::filesystem::create_directories(out);
  {
    std::ofstream csv(out + "/final_pose.csv");
    if (!csv) throw_input_error(out, "", "--out", "cannot write final_pose.csv here");
    write_bones_csv(scene.rig, sol.frames, csv);
  }
  write_json(sol.summary, out + "/summary.json");
}

void run_solve(const SolveOptions& o) {
  IkMethod method{};
  const bool engine = o.solver == "physik";
  if (!engine && !ik_method_from_string(o.solver, method)) {
    throw_input_error("--solver", "", "", "unknown solver '" + o.solver + "'; one of " + kSolvers);
  }
  if (o.tol < 0.0) throw_input_error("--tol", "", "", "must not be negative");
  if (o.max_iterations < 0) throw_input_error("--max-iterations", "", "", "must not be negative");
  if (!o.gravity.empty() && o.gravity.size() != 3) {
    throw_input_error("--gravity", "", "", "expected three numbers");
  }
  const Scene scene = load_scene(o.scene);
  if (scene.control_points.empty()) {
    throw_input_error(o.scene, "control_points", "", "a solve needs at least one control point");
  }
  const std::vector<IkGoal> goals = scene_goals(scene);
  Solution sol = engine ? solve_with_engine(scene, goals, o.tol)
                        : solve_classic(method, scene, goals, ik_options(o));
  sol.summary["solver"] = o.solver;
  write_solution(scene, sol, o.out);
  if (!o.quiet) {
    std::cerr << "solve: " << o.solver << " " << (sol.summary["converged"].get<bool>() ? "converged" : "not converged")
              << " after " << sol.summary["iterations"] << " iterations -> " << o.out << "\n";
  }
  if (sol.diverged) {
    std::cerr << "physik: diverged: " << sol.divergence_reason << "\n";
    throw DivergedRun(sol.divergence_reason);
  }
}

}  // namespace

void add_solve_commands(CLI::App& app) {
  auto opt = std::make_shared<SolveOptions>();
  auto* cmd = app.add_subcommand(
      "solve",
      "Solve a scene's control points (at their final targets) as IK goals with a classic solver "
      "or the PhysIK engine: writes <out>/final_pose.csv and <out>/summary.json.");
  cmd->add_option("SCENE", opt->scene, "Scene file (JSON, see models/README.md)")->required();
  cmd->add_option("--solver", opt->solver, kSolvers)->required();
  cmd->add_option("--out", opt->out, "Output folder")->capture_default_str();
  cmd->add_option("--tol", opt->tol, "Residual tolerance in rig units (default 1e-4 of the reach)");
  cmd->add_option("--max-iterations", opt->max_iterations, "Iteration cap of the classic solvers")
      ->capture_default_str();
  cmd->add_option("--lambda", opt->lambda, "DLS damping in rig units (default 0.02 of the reach)");
  cmd->add_option("--jacobian", opt->jacobian, "jt/dls Jacobian: analytic | fd")->capture_default_str();
  cmd->add_option("--gravity", opt->gravity, "mass-spring gravity, three numbers (rig units/s^2)")
      ->expected(3);
  cmd->add_option("--rotation-damping", opt->rotation_damping,
                  "rotation method: damping factor per joint up the hierarchy, in [0, 1]")
      ->capture_default_str();
  cmd->add_option("--socket", opt->socket, "rotation method sockets: twist-bend | virtual-bone")
      ->capture_default_str();
  cmd->add_option("--cone", opt->cone, "rotation method cone limits: none | circular | elliptical")
      ->capture_default_str();
  cmd->add_flag("--no-limits", opt->no_limits, "classic solvers ignore the rig's joint limits");
  cmd->add_flag("--quiet", opt->quiet, "No progress output");
  cmd->callback([opt] { run_solve(*opt); });
}

}  // namespace physik::cli
