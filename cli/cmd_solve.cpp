// physik solve SCENE --solver NAME: solve a scene's control points as IK goals with one of the
// classic solvers (physik/ik_solver.h) or with the PhysIK engine; writes final_pose.csv and a
// summary.json with the same keys as `physik simulate` (converged, final_residuals, ...).
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>

#include "cli/commands.h"
#include "physik/engine/run_monitor.h"
#include "physik/io/json_fields.h"
#include "physik/io/output_files.h"
#include "physik/io/pose_io.h"
#include "physik/io/scene_io.h"
#include "physik/io/scene_solve.h"
#include "physik/model/errors.h"
#include "physik/model/scene.h"

namespace physik::cli {

namespace {

struct SolveOptions {
  std::string scene;
  std::vector<std::string> set;  // param overrides key=value
  std::string out = "out";
  bool quiet = false;
  SceneSolveOptions solve;  // the solver and its settings (physik/io/scene_solve.h)
};

// final_pose.csv and summary.json, both written (and closed) before a divergence is reported
void write_solution(const Scene& scene, const SceneSolveResult& r, const std::string& out) {
  {
    std::ofstream csv = open_output_file(out + "/final_pose.csv", "--out");
    write_bones_csv(scene.rig, r.frames, csv);
  }
  write_json(r.summary, out + "/summary.json");
}

void run_solve(const SolveOptions& o) {
  check_solve_options(o.solve);  // before the scene: a bad flag is reported first
  const Scene scene = load_scene(o.scene, parse_param_overrides(o.set, "--set"));
  create_output_dir(o.out, "--out");
  const SceneSolveResult r = solve_scene(scene, o.solve);
  if (!r.warning.empty()) std::cerr << "physik: warning: " << scene.file << ": " << r.warning << "\n";
  write_solution(scene, r, o.out);
  if (!o.quiet) {
    std::cerr << "solve: " << o.solve.solver << " "
              << (r.summary["converged"].get<bool>() ? "converged" : "not converged") << " after "
              << r.summary["iterations"] << " iterations -> " << o.out << "\n";
  }
  if (r.diverged) {
    const std::string reason = r.summary.value("divergence_reason", std::string());
    Scene engine = scene;  // the hint is for the engine the solver ran
    if (o.solve.solver == "physik") use_solve_mode(engine);
    std::cerr << "physik: diverged: " << reason << "; " << divergence_hint(engine) << "\n";
    throw DivergedRun(reason);
  }
}

}  // namespace

void add_solve_commands(CLI::App& app) {
  auto opt = std::make_shared<SolveOptions>();
  auto* cmd = app.add_subcommand(
      "solve",
      "Solve a scene's control points (at their final targets) as IK goals with a classic solver "
      "or the PhysIK engine (physik: the implicit step, lengthening from the scene's dt into a "
      "quasi-static solve; physik-explicit: the scene's engine at its dt, the paper's scheme by "
      "default): writes <out>/final_pose.csv and <out>/summary.json.");
  cmd->add_option("SCENE", opt->scene, "Scene file (JSON, see models/README.md)")->required();
  cmd->add_option("--solver", opt->solve.solver, kSceneSolvers)->required();
  cmd->add_option("--out", opt->out, "Output folder")->capture_default_str();
  cmd->add_option("--tol", opt->solve.tol, "Residual tolerance in rig units (default 1e-4 of the reach)");
  cmd->add_option("--max-iterations", opt->solve.max_iterations, "Iteration cap of the classic solvers")
      ->capture_default_str();
  cmd->add_option("--lambda", opt->solve.lambda, "DLS damping in rig units (default 0.02 of the reach)");
  cmd->add_option("--jacobian", opt->solve.jacobian, "jt/dls Jacobian: analytic | fd")->capture_default_str();
  cmd->add_option("--gravity", opt->solve.gravity, "mass-spring gravity, three numbers (rig units/s^2)")
      ->expected(3);
  cmd->add_option("--rotation-damping", opt->solve.rotation_damping,
                  "rotation method: damping factor per joint up the hierarchy, in [0, 1]")
      ->capture_default_str();
  cmd->add_option("--socket", opt->solve.socket, "rotation method sockets: twist-bend | virtual-bone")
      ->capture_default_str();
  cmd->add_option("--cone", opt->solve.cone, "rotation method cone limits: none | circular | elliptical")
      ->capture_default_str();
  cmd->add_flag("--no-limits", opt->solve.no_limits, "classic solvers ignore the rig's joint limits");
  cmd->add_option("--dt-growth", opt->solve.dt_growth,
                  "physik: the implicit step lengthens by this factor every step the kinetic energy "
                  "falls (1 = the scene's dt throughout)")
      ->capture_default_str();
  cmd->add_option("--max-dt", opt->solve.max_dt, "physik: the longest step, s")
      ->capture_default_str();
  cmd->add_option("--finish", opt->solve.finish,
                  "physik, physik-explicit: when the residual stops improving, finish with ccd or dls "
                  "(the paper's hybrid) | none")
      ->capture_default_str();
  cmd->add_option("--set", opt->set,
                  "Override a scene parameter, as simulate's --set (the engine's solvers use it)");
  cmd->add_flag("--quiet", opt->quiet, "No progress output");
  cmd->callback([opt] { run_solve(*opt); });
}

}  // namespace physik::cli
