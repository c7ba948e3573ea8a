// physik simulate SCENE: run the PhysIK engine on a scene; per-step CSV + summary.json.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>

#include "cli/commands.h"
#include "physik/engine/engine.h"
#include "physik/io/bvh.h"
#include "physik/io/pose_io.h"
#include "physik/io/scene_io.h"
#include "physik/io/summary_io.h"
#include "physik/model/errors.h"
#include "physik/model/scene.h"
#include "reference/compare.h"

namespace physik::cli {

namespace {

struct SimulateOptions {
  std::string scene;
  std::string out = "out";
  int steps = 0;          // 0 = the scene's
  int every = 1;          // CSV row every N steps
  bool quiet = false;
  std::vector<std::string> set;  // param overrides key=value
  std::string reference;         // "" or mujoco[:same-forces|:exact-constraints]
  std::string bvh;               // "" or the BVH/qBVH animation to record
};

}  // namespace

void add_simulate_commands(CLI::App& app) {
  auto opt = std::make_shared<SimulateOptions>();
  auto* cmd = app.add_subcommand(
      "simulate",
      "Run the PhysIK engine on a scene: writes <out>/trajectory.csv (one row per step) and "
      "<out>/summary.json. Exit 3 if the run diverges.");
  cmd->add_option("SCENE", opt->scene, "Scene file (JSON, see models/README.md)")->required();
  cmd->add_option("--out", opt->out, "Output folder")->capture_default_str();
  cmd->add_option("--steps", opt->steps, "Number of steps (default: the scene's)");
  cmd->add_option("--every", opt->every, "Write a CSV row (and a --bvh frame) every N steps")->capture_default_str();
  cmd->add_option("--bvh", opt->bvh, "Also record the run as a BVH animation (qBVH if the name ends in .qbvh): the initial pose, then a frame every --every steps");
  cmd->add_option("--set", opt->set, "Override a scene parameter before the scene is read (control points that take their k, "
                  "spring or cap from the params follow), e.g. --set damping=20 --set control_k=30; "
                  "--set preset=paper swaps the base preset under the scene's own params");
  cmd->add_flag("--quiet", opt->quiet, "No progress output");
  cmd->add_option("--reference", opt->reference,
                  "Also run MuJoCo from the same initial pose: mujoco[:same-forces|:exact-constraints]; "
                  "writes mujoco_trajectory.csv, mujoco_summary.json and comparison.json");
  cmd->callback([opt] {
    Scene scene = load_scene(opt->scene, parse_param_overrides(opt->set, "--set"));
    if (opt->steps < 0) throw_input_error("--steps", "", "", "must not be negative");
    if (opt->every < 1) throw_input_error("--every", "", "", "must be at least 1");
    if (!opt->reference.empty()) parse_reference_spec(opt->reference);  // bad spec: exit 2 first
    if (opt->steps > 0) scene.steps = opt->steps;
    std::filesystem::create_directories(opt->out);

    // per-step table
    std::ofstream csv(opt->out + "/trajectory.csv");
    if (!csv) throw_input_error(opt->out, "", "--out", "cannot write trajectory.csv here");
    csv << "step,time,kinetic_energy,passes,joint_mismatch,joint_separation";
    for (std::size_t c = 0; c < scene.control_points.size(); ++c) csv << ",residual_" << c;
    for (const std::string& name : bone_column_names(scene.rig)) csv << "," << name;
    csv << "\n" << std::setprecision(9);
    std::vector<double> row, residuals;
    row.reserve(6 * scene.rig.nbone);
    const int report_every = std::max(1, scene.steps / 10);
    std::unique_ptr<BvhRecorder> bvh;
    if (!opt->bvh.empty()) {
      bvh = std::make_unique<BvhRecorder>(scene.rig, scene.params.dt * opt->every);
      bvh->record(scene.initial_pose);
    }
    const auto observer = [&](const SimState& s, const StepStats& st) {
      if (bvh && s.step % opt->every == 0 && std::isfinite(st.kinetic_energy)) bvh->record(s.frames);
      // a diverged state with non-finite values is reported in summary.json, not written out
      if ((s.step % opt->every == 0 || s.step == scene.steps) && std::isfinite(st.kinetic_energy) &&
          std::isfinite(st.max_residual)) {
        control_residuals(scene, s, residuals);
        csv << s.step << "," << s.time << "," << st.kinetic_energy << "," << st.passes << ","
            << st.mismatch << "," << st.joint_separation;
        for (double r : residuals) csv << "," << r;
        row.clear();
        append_bone_values(s.frames, row);
        for (double v : row) csv << "," << v;
        csv << "\n";
      }
      if (!opt->quiet && scene.steps >= 200 && s.step % report_every == 0) {
        std::cerr << "  step " << s.step << "/" << scene.steps << "  KE " << st.kinetic_energy
                  << " J  passes " << st.passes << "  max residual " << st.max_residual << "\n";
      }
    };
    const RunSummary sum = run_scene(scene, observer);
    if (!sum.joint_solve_warning.empty()) {
      std::cerr << "physik: warning: " << scene.file << ": " << sum.joint_solve_warning << "\n";
    }
    write_json(summary_to_json(scene, sum), opt->out + "/summary.json");
    if (bvh) bvh->save(opt->bvh);
    {
      std::ofstream pose(opt->out + "/final_pose.csv");
      write_bones_csv(scene.rig, sum.final_frames, pose);
    }
    if (!opt->quiet) {
      std::cerr << "simulate: " << sum.steps_run << " steps, "
                << (sum.converged ? "converged at step " + std::to_string(sum.steps_to_converge)
                                  : std::string("not converged"))
                << ", mean passes/step " << sum.mean_passes_per_step << ", max residual "
                << (sum.final_residuals.empty()
                        ? 0.0
                        : *std::max_element(sum.final_residuals.begin(), sum.final_residuals.end()))
                << " -> " << opt->out << "\n";
    }
    if (!opt->reference.empty()) {
      write_reference_comparison(scene, opt->reference, opt->out, opt->every, !opt->quiet);
    }
    if (sum.diverged) {
      std::cerr << "physik: diverged: " << sum.divergence_reason << "\n";
      throw DivergedRun(sum.divergence_reason);
    }
  });
}

}  // namespace physik::cli
