// physik simulate SCENE: run the PhysIK engine on a scene into a run folder (scene.json,
// trajectory.csv, targets_and_limits.csv, summary.json, final_pose.csv; physik/io/run_folder.h).
//
//   prepare_scene      load, --set, --steps; every bad option exits 2 before the run, and so
//                      does a rig that starts through the ground or an obstacle (a rig that
//                      starts into one gets a warning; physik/engine/start_contacts.h)
//   progress_observer  --bvh frames and progress lines, beside the run folder's tables
//   clear_run_folder   an earlier run in <out> goes first, the user's own files there stay
//   --reference        the MuJoCo run as a run folder of its own (<out>/mujoco) and
//                      comparison.json (reference/compare.h)
#include <algorithm>
#include <cmath>
#include <iostream>
#include <memory>

#include "cli/commands.h"
#include "physik/engine/measures.h"
#include "physik/engine/run_monitor.h"
#include "physik/engine/start_contacts.h"
#include "physik/io/bvh.h"
#include "physik/io/output_files.h"
#include "physik/io/run_folder.h"
#include "physik/io/scene_io.h"
#include "physik/io/scene_warnings.h"
#include "physik/model/errors.h"
#include "physik/model/scene.h"
#include "reference/compare.h"

namespace physik::cli {

namespace {

struct SimulateOptions {
  std::string scene;
  std::string out = "out";
  int steps = 0;  // 0 = the scene's
  int every = 1;  // CSV row every N steps
  bool quiet = false;
  std::vector<std::string> set;  // param overrides key=value
  std::string reference;         // "" or mujoco[:same-forces|:exact-constraints]
  std::string bvh;               // "" or the BVH/qBVH animation to record
  bool own_skeleton = false;     // --bvh on the rig's own skeleton, not its source's
  BoneTargetOptions targets;     // --orientation-target, --aim, --pin
};

void add_options(CLI::App* cmd, SimulateOptions& o) {
  cmd->add_option("SCENE", o.scene, "Scene file (JSON, see models/README.md)")->required();
  cmd->add_option("--out", o.out, "Output folder")->capture_default_str();
  cmd->add_option("--steps", o.steps, "Number of steps (default: the scene's)");
  cmd->add_option("--every", o.every, "Write a CSV row (and a --bvh frame) every N steps")
      ->capture_default_str();
  cmd->add_option("--bvh", o.bvh,
                  "Also record the run as a BVH animation (qBVH if the name ends in .qbvh): the "
                  "initial pose, then a frame every --every steps; on the rig's source "
                  "skeleton when it has one (a rig made by `rig from-bvh`)");
  cmd->add_flag("--own-skeleton", o.own_skeleton, kOwnSkeletonHelp);
  cmd->add_option(
      "--set", o.set,
      "Override a scene parameter before the scene is read (control points that take their k, "
      "spring or cap from the params follow), e.g. --set damping=20 --set control_k=30; "
      "--set preset=paper swaps the base preset under the scene's own params");
  add_bone_target_options(cmd, o.targets);
  cmd->add_flag("--quiet", o.quiet, "No progress output");
  cmd->add_option(
      "--reference", o.reference,
      "Also run MuJoCo from the same initial pose: mujoco[:same-forces|:exact-constraints]; "
      "writes the MuJoCo run as a run folder of its own, <out>/mujoco (the files of "
      "<out>), and <out>/comparison.json");
}

Scene prepare_scene(const SimulateOptions& o) {
  std::vector<std::string> warnings;
  Scene scene = load_scene(o.scene, parse_param_overrides(o.set, "--set"), warnings);
  for (const std::string& w : warnings) std::cerr << "physik: warning: " << w << "\n";
  if (o.steps < 0) throw_input_error("--steps", "", "", "must not be negative");
  if (o.every < 1) throw_input_error("--every", "", "", "must be at least 1");
  if (!o.reference.empty()) parse_reference_spec(o.reference);  // bad spec: exit 2 first
  if (!o.bvh.empty()) check_output_file(o.bvh, "--bvh");        // before the run, not after
  if (o.steps > 0) scene.steps = o.steps;
  apply_bone_target_options(o.targets, scene);
  warn_start_contacts(scene);
  return scene;
}

// What the step's solver did, by scheme: the joint passes of Gauss-Seidel, the energy guard's
// substeps of the implicit step, nothing for the exact step (one solve, no iteration).
std::string solver_work(const EngineParams& p, const StepStats& st) {
  switch (p.scheme) {
    case Scheme::kGaussSeidel:
      return "passes " + std::to_string(st.passes);
    case Scheme::kExact:
      return "exact solve";
    case Scheme::kImplicit:
      return "substeps " + std::to_string(st.substeps);
  }
  return "";
}

// What a run shows besides its run folder: the BVH frames, and a progress line every tenth of
// a long run.
StepObserver progress_observer(const Scene& scene, const SimulateOptions& o, BvhRecorder* bvh) {
  const int report_every = std::max(1, scene.steps / 10);
  return [&scene, &o, bvh, report_every](const SimState& s, const StepStats& st) {
    if (bvh && s.step % o.every == 0 && std::isfinite(st.kinetic_energy)) bvh->record(s.frames);
    if (!o.quiet && scene.steps >= 200 && s.step % report_every == 0) {
      std::cerr << "  step " << s.step << "/" << scene.steps << "  KE " << st.kinetic_energy
                << " J  " << solver_work(scene.params, st) << "  max residual " << st.max_residual
                << "\n";
    }
  };
}

// the line ends with the goal residual at the end (measures.h): the control points' largest
// distance, or the orientation targets' and aims' largest arc
void print_outcome(const Scene& scene, const RunSummary& sum, const std::string& out) {
  double residual = max_turning_arc(scene, sum.final_frames);
  for (double r : sum.final_residuals) residual = r <= residual ? residual : r;
  std::cerr << "simulate: " << sum.steps_run << " steps, "
            << (sum.converged ? "converged at step " + std::to_string(sum.steps_to_converge)
                              : std::string("not converged"))
            << ", mean passes/step " << sum.mean_passes_per_step << ", max residual " << residual
            << " -> " << out << "\n";
}

// A comparison with a run that diverged, or a MuJoCo run that raised a warning (not comparable),
// measures nothing: say which, and exit 3. MuJoCo alone ending early is its own limit (its Euler
// step, stable only below the stiffest spring's period, or its buffers), not PhysIK's: the hint
// says which (mujoco_runner.h mujoco_hint).
[[noreturn]] void report_diverged_comparison(const nlohmann::json& cmp, const std::string& out,
                                             const Scene& scene) {
  std::string which, reason;
  for (const auto& run : cmp["diverged"]) {
    const std::string name = run.get<std::string>();
    which += (which.empty() ? "" : " and ") + std::string(name == "physik" ? "PhysIK" : "MuJoCo");
    reason += (reason.empty() ? "" : "; ") + cmp[name]["divergence_reason"].get<std::string>();
  }
  std::cerr << "physik: diverged: " << which << " (" << reason
            << "): no gap to report (comparison.json in " << out << " lists the runs)";
  if (which == "MuJoCo") {
    std::cerr << "; PhysIK's own run did not diverge: " << mujoco_hint(scene, reason);
  }
  std::cerr << "\n";
  throw DivergedRun(reason);
}

void run_simulate(const SimulateOptions& o) {
  const Scene scene = prepare_scene(o);
  std::unique_ptr<BvhRecorder> bvh;
  if (!o.bvh.empty()) {
    BvhExportOptions bo;
    bo.source_skeleton = !o.own_skeleton;
    bvh = std::make_unique<BvhRecorder>(scene.rig, scene.params.dt * o.every, 1, bo);
    bvh->hold_source_row(scene.initial_source_row);  // every pose came from the initial one
    bvh->record(scene.initial_pose);
  }
  // the run folder (physik/io/run_folder.h): scene.json, both tables, summary.json, final_pose.csv;
  // an earlier run's files there go first (after every input check: a bad option keeps them),
  // its reference run and comparison too, so that the folder holds this run alone
  clear_run_folder(o.out, "--out", {kComparisonFile}, {kReferenceFolder});
  const RunSummary sum =
      simulate_into_folder(scene, o.out, o.every, progress_observer(scene, o, bvh.get()));
  if (bvh) print_bvh_report(o.bvh, bvh->save(o.bvh));
  if (!sum.joint_solve_warning.empty()) {
    std::cerr << "physik: warning: " << scene.file << ": " << sum.joint_solve_warning << "\n";
  }
  const std::string guard = energy_guard_warning(scene, sum);  // once a run
  if (!guard.empty()) std::cerr << "physik: warning: " << scene.file << ": " << guard << "\n";
  if (!o.quiet) print_outcome(scene, sum, o.out);
  if (!o.reference.empty()) {
    const nlohmann::json cmp =
        write_reference_comparison(scene, o.reference, o.out, o.every, !o.quiet);
    if (!cmp["diverged"].empty()) report_diverged_comparison(cmp, o.out, scene);
  }
  if (sum.diverged) {
    std::cerr << "physik: diverged: " << sum.divergence_reason << "; " << divergence_hint(scene)
              << "\n";
    throw DivergedRun(sum.divergence_reason);
  }
  if (!sum.converged) {  // a run that ends short says what to try, as a divergence does
    std::cerr << "physik: not converged: " << scene.file << ": the run ended after "
              << sum.steps_run << " steps short of convergence; " << not_converged_hint(scene, sum)
              << "\n";
  }
}

}  // namespace

void warn_start_contacts(const Scene& scene) {
  const std::string warning = check_start_contacts(scene);
  if (!warning.empty()) std::cerr << "physik: warning: " << scene.file << ": " << warning << "\n";
}

void add_simulate_commands(CLI::App& app) {
  auto opt = std::make_shared<SimulateOptions>();
  auto* cmd = app.add_subcommand(
      "simulate",
      "Run the PhysIK engine on a scene into a run folder: <out>/scene.json, trajectory.csv (a "
      "row every --every steps), targets_and_limits.csv, summary.json, final_pose.csv (`physik "
      "view <out>` shows it). Exit 3 if the run diverges.");
  add_options(cmd, *opt);
  cmd->callback([opt] { run_simulate(*opt); });
}

}  // namespace physik::cli
