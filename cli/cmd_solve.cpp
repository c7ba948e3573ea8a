// physik solve SCENE --solver NAME: solve a scene's control points as IK goals with one of the
// classic solvers (physik/ik_solver.h) or with the PhysIK engine; writes final_pose.csv and a
// summary.json with the same keys as `physik simulate` (converged, final_residuals, ...). Exit 3
// for a diverged engine run, 4 for a solve short of its tolerance (scene_solve.h
// solve_shortfall), after writing both.
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>

#include "cli/commands.h"
#include "physik/engine/run_monitor.h"
#include "physik/io/bvh.h"
#include "physik/io/json_fields.h"
#include "physik/io/output_files.h"
#include "physik/io/pose_io.h"
#include "physik/io/run_folder.h"
#include "physik/io/scene_io.h"
#include "physik/io/scene_warnings.h"
#include "physik/io/summary_io.h"
#include "physik/model/errors.h"
#include "physik/model/scene.h"
#include "physik/posing/scene_solve.h"

namespace physik::cli {

namespace {

struct SolveOptions {
  std::string scene;
  std::vector<std::string> set;  // param overrides key=value
  std::string out = "out";
  std::string bvh;            // "" or the BVH/qBVH file of the final pose
  bool own_skeleton = false;  // --bvh on the rig's own skeleton, not its source's
  bool quiet = false;
  BoneTargetOptions targets;  // --orientation-target, --aim, --pin
  // the solve options' flags as given (their table, physik/posing/solve_options.h), by name
  std::map<std::string, std::string> texts;
  std::map<std::string, std::vector<std::string>> vectors;  // three-number options
  std::map<std::string, bool> flags;                        // boolean options
};

// final_pose.csv and summary.json, both written (and closed) before a divergence is reported;
// a solve that did not diverge writes a pose folder (run_folder.h: scene.json, a one-row
// trajectory.csv and targets_and_limits.csv besides), which `physik view` shows
void write_solution(const Scene& scene, const SceneSolveResult& r, const nlohmann::json& summary,
                    const std::string& out) {
  if (!r.diverged) {
    write_pose_folder(r.scene, out, r.frames, summary);
    // the solve's own summary, as Python's physik.solve gives it (no pose folder "kind")
    write_json(summary, out + "/summary.json");
    return;
  }
  {
    std::ofstream csv = open_output_file(out + "/final_pose.csv", "--out");
    write_bones_csv(scene.rig, r.frames, csv);
  }
  write_json(summary, out + "/summary.json");
}

// --bvh: the final pose as a one-frame animation, on the rig's source skeleton when it has one,
// keeping what the rig cannot hold from the clip frame the initial pose came from (if it did),
// at the source file's frame time (the step's when the rig does not know it)
void write_solution_bvh(const Scene& scene, const SceneSolveResult& r, const SolveOptions& o) {
  const Pose& pose = r.pose;
  BvhExportOptions bo;
  bo.source_skeleton = !o.own_skeleton;
  bo.quaternion = is_qbvh_path(o.bvh);
  const double source_frame_time = scene.rig.source_skeleton.frame_time;
  bo.frame_time = source_frame_time > 0.0 ? source_frame_time : scene.params.dt;
  SourceFrames source;
  if (!scene.initial_source_row.empty()) source = {{scene.initial_source_row}, {0}};
  print_bvh_report(o.bvh, save_bvh(o.bvh, scene.rig, {pose}, bo, source));
}

// the scene's "solve" object, then the flags given on top
SceneSolveOptions solve_options(const SolveOptions& o, const CLI::App& cmd) {
  SceneSolveOptions out = load_solve_options(o.scene);
  for (const SolveOptionRow& row : solve_option_table()) {
    const std::string flag = option_label(row.name, OptionSpelling::kFlag);
    if (cmd.count(flag) == 0) continue;
    SolveOptionValue v;
    if (row.kind == SolveOptionKind::kBoolean) {
      v.number = o.flags.at(row.name) ? 1.0 : 0.0;
    } else if (row.kind == SolveOptionKind::kVec3) {
      std::string joined;
      for (const std::string& t : o.vectors.at(row.name)) joined += t + " ";
      v = parse_solve_option(row, joined, OptionSpelling::kFlag);
    } else {
      v = parse_solve_option(row, o.texts.at(row.name), OptionSpelling::kFlag);
    }
    set_solve_option(out, row, v, OptionSpelling::kFlag);
  }
  return out;
}

// The solve mode (--solver physik) runs the implicit scheme whatever the scene's: an --set of a
// row that only the implicit scheme reads (implicit_linearisation, implicit_max_splits) is the
// run's, so scheme=implicit goes in front of the overrides
std::vector<std::string> solve_mode_overrides(const std::vector<std::string>& set) {
  const EngineParams scene_default = preset_params("original");
  EngineParams implicit = scene_default;
  implicit.scheme = Scheme::kImplicit;
  for (const std::string& assignment : set) {
    const ParamRow* row = find_param(assignment.substr(0, assignment.find('=')));
    if (row && row->conflict && !row->conflict_reason(scene_default).empty() &&
        row->conflict_reason(implicit).empty()) {
      std::vector<std::string> out{"scheme=implicit"};
      out.insert(out.end(), set.begin(), set.end());
      return out;
    }
  }
  return set;
}

void run_solve(const SolveOptions& o, const CLI::App& cmd) {
  if (!std::filesystem::exists(o.scene))
    throw_input_error(o.scene, "", "", "scene file does not exist");
  const SceneSolveOptions options = solve_options(o, cmd);
  const bool solve_mode = options.solver == "physik" || options.solver == "physik-steps";
  const ParamOverrides overrides =
      parse_param_overrides(solve_mode ? solve_mode_overrides(o.set) : o.set, "--set");
  check_solve_options(options);  // before the scene: a bad flag is reported first
  std::vector<std::string> warnings;
  Scene scene = load_scene(o.scene, overrides, warnings);
  for (const std::string& w : warnings) std::cerr << "physik: warning: " << w << "\n";
  apply_bone_target_options(o.targets, scene);
  if (!o.bvh.empty()) check_output_file(o.bvh, "--bvh");  // before the solve, not after
  // the engine runs the contacts from the initial pose (start_contacts.h); a classic solver
  // refuses a ground or obstacles outright (scene_solve.h)
  if (solve_mode || options.solver == "physik-explicit") {
    warn_start_contacts(scene);
  }
  create_output_dir(o.out, "--out");
  const SceneSolveResult r = solve_scene(scene, options);
  const nlohmann::json summary = solve_summary_to_json(r);
  if (!r.warning.empty())
    std::cerr << "physik: warning: " << scene.file << ": " << r.warning << "\n";
  write_solution(scene, r, summary, o.out);
  if (!o.bvh.empty() && !r.diverged) write_solution_bvh(scene, r, o);
  if (!o.quiet) {
    std::cerr << "solve: " << options.solver << " "
              << (summary["converged"].get<bool>() ? "converged" : "not converged") << " after "
              << summary["iterations"] << " iterations -> " << o.out << "\n";
  }
  if (r.diverged) {
    const std::string reason = summary.value("divergence_reason", std::string());
    std::cerr << "physik: diverged: " << reason << "; " << divergence_hint(r.scene) << "\n";
    throw DivergedRun(reason);
  }
  const std::string shortfall = solve_shortfall(r);
  if (!shortfall.empty()) {  // said even with --quiet, as a divergence is
    std::cerr << "physik: not converged: " << shortfall << "; the last pose is in " << o.out
              << "\n";
    throw NotConverged(shortfall);
  }
}

// one CLI option per row of the solve options' table
void add_solve_options(CLI::App* cmd, SolveOptions& o) {
  for (const SolveOptionRow& row : solve_option_table()) {
    const std::string flag = option_label(row.name, OptionSpelling::kFlag);
    std::string help = row.doc;
    if (!row.unit.empty() && row.unit != "1") help += " (" + row.unit + ")";
    if (row.kind == SolveOptionKind::kBoolean) {
      cmd->add_flag(flag, o.flags[row.name], help);
      continue;
    }
    if (row.kind == SolveOptionKind::kChoice) {
      std::string all;
      for (const std::string& c : row.choices) all += (all.empty() ? "" : "|") + c;
      help += ": " + all;
    }
    const std::string def = solve_option_default_text(row);
    if (!def.empty()) help += " [default: " + def + "]";
    // the values are read as text (parse_solve_option checks them by the row), so the help's
    // type name is the row's kind, not CLI11's TEXT for a string
    if (row.kind == SolveOptionKind::kVec3) {
      cmd->add_option(flag, o.vectors[row.name], help)->expected(3)->type_name("FLOAT");
    } else {
      cmd->add_option(flag, o.texts[row.name], help)
          ->type_name(row.kind == SolveOptionKind::kReal      ? "FLOAT"
                      : row.kind == SolveOptionKind::kInteger ? "INT"
                                                              : "TEXT");
    }
  }
}

}  // namespace

void add_solve_commands(CLI::App& app) {
  auto opt = std::make_shared<SolveOptions>();
  auto* cmd = app.add_subcommand(
      "solve",
      "Solve a scene's goals (control points at their final targets, orientation targets, aims) "
      "with a classic solver, Orocos KDL or the PhysIK engine (physik: the equilibrium solve, "
      "the rest pose by a trust region of implicit steps at rest; physik-steps: the implicit "
      "step lengthening from the scene's dt into a quasi-static solve; physik-explicit: the "
      "scene's own engine at its dt). Position goals are met within --tol (rig units), "
      "orientation targets and aims within --tol-angle (rad). Writes "
      "<out>/final_pose.csv and <out>/summary.json, and, unless it diverged, the rest of a pose "
      "folder (scene.json, a one-row trajectory.csv and targets_and_limits.csv: `physik view "
      "<out>` shows the solved pose). The scene's \"solve\" object gives options "
      "the flags do not. A solve that stops short of a goal's tolerance (out of reach, against "
      "a limit, stalled, or out of iterations or steps) writes both, names each goal short and "
      "by how much, and exits 4.");
  cmd->footer(kSolveExitStatusHelp);
  cmd->add_option("SCENE", opt->scene, "Scene file (JSON, see models/README.md)")->required();
  add_solve_options(cmd, *opt);
  cmd->add_option("--out", opt->out, "Output folder")->capture_default_str();
  cmd->add_option("--set", opt->set,
                  "Override a scene parameter, as simulate's --set (the engine's solvers use it)");
  add_bone_target_options(cmd, opt->targets);
  cmd->add_option("--bvh", opt->bvh,
                  "Also write the final pose as a one-frame BVH (qBVH if the name ends in .qbvh): "
                  "on the rig's source skeleton when it has one (a rig made by `rig from-bvh`)");
  cmd->add_flag("--own-skeleton", opt->own_skeleton, kOwnSkeletonHelp);
  cmd->add_flag("--quiet", opt->quiet, "No progress output");
  cmd->callback([opt, cmd] { run_solve(*opt, *cmd); });
}

}  // namespace physik::cli
