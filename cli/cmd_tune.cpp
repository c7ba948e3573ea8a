// physik tune SCENE: choose engine coefficients with Ceres (tune/tuner.h).
// physik equilibrium SCENE: the exact static pose of a scene with Ceres (tune/equilibrium.h).
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>

#include "cli/commands.h"
#include "physik/engine/run_monitor.h"
#include "physik/io/json_fields.h"
#include "physik/io/output_files.h"
#include "physik/io/pose_io.h"
#include "physik/io/scene_io.h"
#include "physik/io/scene_warnings.h"
#include "physik/io/summary_io.h"
#include "physik/model/errors.h"
#include "physik/model/scene.h"
#include "tune/equilibrium.h"
#include "tune/reports.h"
#include "tune/tuner.h"

namespace physik::cli {

namespace {

struct TuneCliOptions {
  std::string scene;
  std::vector<std::string> set;  // param overrides key=value, before tuning
  std::string params = "damping";
  std::string objective = "settle";
  std::string measure = "log";
  std::vector<std::string> bounds;
  std::string out;
  std::string report;
  int steps = 0;
  int scan_points = 13;
  int max_iterations = 50;
  bool quiet = false;
};

struct EquilibriumCliOptions {
  std::string scene;
  std::vector<std::string> set;  // param overrides key=value
  std::string out;
  std::string bones;
  bool compare = false;
  std::string start = "initial";
  int max_iterations = tune::EquilibriumOptions{}.max_iterations;
};

Scene load_existing_scene(const std::string& path, const std::vector<std::string>& set) {
  const ParamOverrides overrides = parse_param_overrides(set, "--set");
  if (!std::filesystem::exists(path)) throw_input_error(path, "", "", "scene file does not exist");
  std::vector<std::string> warnings;
  Scene scene = load_scene(path, overrides, warnings);
  for (const std::string& w : warnings) std::cerr << "physik: warning: " << w << "\n";
  return scene;
}

const char* const kSetHelp =
    "Override a scene parameter, as simulate's --set (e.g. --set damping=1, --set preset=paper)";

double max_of(const std::vector<double>& v) {
  return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end());
}

std::string tunable_list() {
  std::string names;
  for (const auto& t : tune::tunable_parameters()) {
    names += (names.empty() ? "" : ", ") + t.name + " [" + std::to_string(t.lo).substr(0, 6) +
             ", " + std::to_string(t.hi).substr(0, 7) + "] " + t.unit;
  }
  return names;
}

void add_tune_options(CLI::App* cmd, TuneCliOptions& o) {
  cmd->add_option("SCENE", o.scene, "Scene file (JSON)")->required();
  cmd->add_option("--params", o.params,
                  "Comma-separated parameters to tune, with default bounds: " + tunable_list())
      ->capture_default_str();
  cmd->add_option("--objective", o.objective,
                  "settle: control-point residuals over the run (divergence = finite penalty); "
                  "mujoco: trajectory against MuJoCo's same-forces run")
      ->capture_default_str();
  cmd->add_option("--measure", o.measure,
                  "settle objective's residual: log = ln(1 + error/tolerance) (sees the slow "
                  "tail), linear = error/height (integral of squared error)")
      ->capture_default_str();
  cmd->add_option("--bounds", o.bounds, "Override bounds, e.g. --bounds damping=0.1:10");
  cmd->add_option("--set", o.set, kSetHelp);
  cmd->add_option("--out", o.out, "Write the tuned scene here (JSON; '-' = stdout)");
  cmd->add_option("--report", o.report, "Write a JSON report (values, costs, scan) here");
  cmd->add_option("--steps", o.steps, "Steps per run (default: the scene's)");
  cmd->add_option("--scan-points", o.scan_points, "Grid points per parameter in the scan")
      ->capture_default_str();
  cmd->add_option("--max-iterations", o.max_iterations, "Ceres iterations")->capture_default_str();
  cmd->add_flag("--quiet", o.quiet,
                "No progress output, and Ceres' one-line brief instead of its full report");
}

// the tuner's options from the command line's; bad values exit 2 before any run
tune::TuneOptions tune_options(const TuneCliOptions& o) {
  tune::TuneOptions to;
  to.params = tune::parse_tune_params(o.params, "--params");
  for (const std::string& b : o.bounds) tune::apply_bounds(to.params, b, "--bounds");
  to.objective = tune::objective_from_string(o.objective, "--objective");
  to.measure = tune::measure_from_string(o.measure, "--measure");
  if (o.steps < 0) throw_input_error("--steps", "", "", "must not be negative");
  if (o.scan_points < 0 || o.scan_points == 1) {
    throw_input_error("--scan-points", "", "", "must be 0 (no scan) or at least 2");
  }
  to.scan_points = o.scan_points;
  to.max_iterations = std::max(1, o.max_iterations);
  to.verbose = !o.quiet;
  return to;
}

std::string run_text(const RunSummary& run) {
  return run.diverged    ? "diverged"
         : run.converged ? "converged at step " + std::to_string(run.steps_to_converge)
                         : std::string("not converged");
}

// the baseline: the scene as it runs, with damping auto's choice named
void print_tune_baseline(const tune::TuneResult& r) {
  if (r.damping_auto) {
    std::cout << "  scene's damping: auto, resolved to " << r.damping_auto_value
              << " N s/m at the start pose (chosen " << r.damping_auto_updates
              << (r.damping_auto_updates == 1 ? " time" : " times")
              << " in its run); the tuned damping is fixed\n";
  }
  std::cout << "  scene run (baseline, as it runs): " << run_text(r.scene_run)
            << ", max final residual " << max_of(r.scene_run.final_residuals) << "\n";
  if (r.start_cost != r.initial_cost) {
    std::cout << "  search start (the scene's values, fixed and within the bounds): J "
              << r.start_cost << "\n";
  }
}

// the result; Ceres' full report unless --quiet (its one-line brief then)
void print_tune_result(const tune::TuneResult& r, const tune::TuneOptions& to) {
  std::cout << (to.verbose ? r.ceres_full : "ceres: " + r.ceres_brief) << "\n";
  std::cout << "tuned (" << tune::to_string(to.objective) << ", " << r.evaluations << " runs + "
            << r.scene_evaluations << " of the scene as it is, " << r.wall_time_s << " s):\n";
  for (std::size_t i = 0; i < r.names.size(); ++i) {
    const bool auto_value = r.damping_auto && r.names[i] == "damping";
    std::cout << "  " << r.names[i] << ": " << (auto_value ? "auto = " : "") << r.initial_values[i]
              << " -> " << r.values[i] << "\n";
  }
  if (to.objective == tune::Objective::kMujoco) {
    std::cout << "  MuJoCo same-forces reference: " << r.reference_steps << " steps\n";
  }
  print_tune_baseline(r);
  std::cout << "  objective J: " << r.initial_cost << " (scene"
            << (r.damping_auto ? ", damping auto" : "") << ") -> " << r.scan_cost << " (scan) -> "
            << r.final_cost << " (ceres)\n";
  std::cout << "  tuned run: " << run_text(r.tuned_run) << ", max final residual "
            << max_of(r.tuned_run.final_residuals) << "\n";
  const std::string disagree = tune::measures_disagree(r);
  if (!disagree.empty()) std::cout << "  " << disagree << "\n";
  if (tune::no_improvement(r)) {
    std::cout << "  no improvement: the tuned values' J " << r.final_cost
              << " is not below the scene's " << r.initial_cost << " as it runs\n";
    std::cerr << "physik: warning: tune: no improvement on the scene as it runs (J " << r.final_cost
              << " tuned, " << r.initial_cost << " scene)\n";
  }
}

// Why tune exits 4, in words that hold as read: a tuned run that converges later than the
// scene's did converge ("converged later"), one that never does did not ("not converged").
std::string later_or_never(const Scene& scene, const tune::TuneResult& r) {
  const auto num_text = [](double v) {
    std::ostringstream s;
    s << std::setprecision(4) << v;
    return s.str();
  };
  const RunSummary &tuned = r.tuned_run, &base = r.scene_run;
  const std::string objective = std::string(tune::no_improvement(r) ? "not lower" : "lower") +
                                " (J " + num_text(r.initial_cost) + " scene, " +
                                num_text(r.final_cost) + " tuned)";
  if (tuned.converged) {
    const int later = tuned.steps_to_converge - base.steps_to_converge;
    return "physik: converged later: tune: " + scene.file + ": the tuned run converges at step " +
           std::to_string(tuned.steps_to_converge) + ", " + std::to_string(later) +
           (later == 1 ? " step" : " steps") + " later than the scene's (step " +
           std::to_string(base.steps_to_converge) + "); its objective is " + objective +
           "; exit 4, as tune exits 0 only where the tuned run converges no later than the "
           "scene's";
  }
  return "physik: not converged: tune: " + scene.file + ": the tuned run does not converge in " +
         std::to_string(tuned.steps_run) + " steps (" +
         (base.converged ? "the scene's does, at step " + std::to_string(base.steps_to_converge)
                         : std::string("nor does the scene's")) +
         "); its objective is " + objective;
}

void run_tune(const TuneCliOptions& o) {
  Scene scene = load_existing_scene(o.scene, o.set);
  const tune::TuneOptions to = tune_options(o);
  if (o.steps > 0) scene.steps = o.steps;
  // every run of the tuner starts from the scene's pose: a start into the ground warns, one
  // through it is bad input (start_contacts.h), before any run
  warn_start_contacts(scene);
  if (!o.out.empty()) check_output_file(o.out, "--out");
  if (!o.report.empty()) check_output_file(o.report, "--report");
  tune::TuneResult r;
  try {
    r = tune::tune_scene(scene, to);
  } catch (const DivergedRun& e) {  // the mujoco objective's reference run
    std::cerr << "physik: diverged: tune: " << e.what() << "\n";
    throw;
  }
  if (!o.report.empty()) write_json(tune::tune_report_to_json(scene, to, r), o.report);
  const std::string failure = tune::tune_failure(r);
  if (!failure.empty()) {  // no tuned value to print or write
    std::cerr << "physik: diverged: tune: " << failure << "; nothing tuned"
              << (o.out.empty() ? "" : ", " + o.out + " not written") << "\n";
    throw DivergedRun(failure);
  }
  print_tune_result(r, to);
  if (!o.out.empty()) write_json(scene_to_json(r.tuned_scene, false, o.out), o.out);
  if (!tune::converges_no_later(r)) {  // after the outputs, as solve says it
    std::cerr << later_or_never(scene, r)
              << (o.out.empty() ? "" : "; " + o.out + " holds the tuned values") << "\n";
    throw NotConverged("the tuned run converges later than the scene's, or never");
  }
}

void add_tune(CLI::App& app) {
  auto opt = std::make_shared<TuneCliOptions>();
  auto* cmd = app.add_subcommand(
      "tune",
      "Tune engine coefficients of a scene with Ceres: a coarse log-grid scan, then bounded "
      "Levenberg-Marquardt on a smoothed objective. The baseline is the scene as it runs: with "
      "\"damping\": \"auto\" the search starts at auto's choice, which the output names. Prints "
      "Ceres' summary; writes the tuned scene (--out) and a JSON report (--report).");
  add_tune_options(cmd, *opt);
  cmd->footer(kTuneExitStatusHelp);
  cmd->callback([opt] { run_tune(*opt); });
}

void add_equilibrium(CLI::App& app) {
  auto opt = std::make_shared<EquilibriumCliOptions>();
  auto* cmd = app.add_subcommand(
      "equilibrium",
      "The exact static pose of a scene: the minimum of control-spring + torsion potential "
      "over the root position and joint rotations (Ceres). Writes JSON (pose, residuals).");
  cmd->add_option("SCENE", opt->scene, "Scene file (JSON)")->required();
  cmd->add_option("--out", opt->out, "JSON output file (default: stdout)");
  cmd->add_option("--bones", opt->bones, "Also write the pose as a bones CSV here");
  cmd->add_option("--start", opt->start,
                  "Start pose: 'initial' (the scene's) or 'physik' (PhysIK's final pose: the "
                  "nearest exact equilibrium to it)")
      ->capture_default_str();
  cmd->add_flag(
      "--compare", opt->compare,
      "Also run PhysIK on the scene and report its final-pose distance to the equilibrium "
      "(exit 3 if that run diverges)");
  cmd->add_option("--max-iterations", opt->max_iterations,
                  "Ceres iterations at most; a minimisation that stops short of convergence "
                  "writes its last iterate and exits 4")
      ->capture_default_str();
  cmd->add_option("--set", opt->set, kSetHelp);
  cmd->footer(kEquilibriumExitStatusHelp);
  cmd->callback([opt] {
    tune::check_equilibrium_start(opt->start);
    const Scene scene = load_existing_scene(opt->scene, opt->set);
    if (!opt->out.empty() && opt->out != "-") check_output_file(opt->out, "--out");
    if (!opt->bones.empty()) check_output_file(opt->bones, "--bones");
    const tune::EquilibriumReport rep =
        tune::equilibrium_report(scene, opt->start, opt->compare, opt->max_iterations);
    const tune::EquilibriumResult& e = rep.result;
    const nlohmann::json& doc = rep.doc;
    std::cerr << "equilibrium: " << e.ceres_brief << "\n";
    if (rep.ran_physik && rep.physik_run.diverged) {
      write_json(doc, opt->out);
      std::cerr << "physik: diverged: PhysIK's run diverged (" << rep.physik_run.divergence_reason
                << "): no distance to report; " << divergence_hint(scene) << "\n";
      throw DivergedRun(rep.physik_run.divergence_reason);
    }
    if (rep.ran_physik) {
      std::cerr << "equilibrium: PhysIK's final pose is "
                << doc["physik"]["max_pose_distance"].get<double>()
                << " rig units from it (potential " << doc["physik"]["potential"].get<double>()
                << " J vs " << e.potential << " J)\n";
    }
    write_json(doc, opt->out);
    if (!opt->bones.empty()) {
      std::ofstream csv = open_output_file(opt->bones, "--bones");
      write_bones_csv(scene.rig, e.frames, csv);
    }
    if (!e.converged) {  // after the outputs, which hold the last iterate; said as solve says it
      std::cerr << "physik: not converged: " << scene.file
                << ": Ceres stopped before converging; the pose written is its last iterate\n";
      throw NotConverged("Ceres stopped before converging");
    }
  });
}

}  // namespace

void add_tune_commands(CLI::App& app) {
  add_tune(app);
  add_equilibrium(app);
}

}  // namespace physik::cli
