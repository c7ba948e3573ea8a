// physik experiment list | run NAME...: the paper's figures and the studies.
#include <chrono>
#include <filesystem>
#include <iostream>
#include <memory>

#include "cli/commands.h"
#include "experiments/experiment.h"
#include "physik/io/output_files.h"
#include "physik/model/errors.h"

namespace physik::cli {

namespace {

struct RunOptions {
  std::vector<std::string> names;
  std::string out = "results";
  std::string models = "models";
  bool quick = false;
};

// the experiments named (all when none), in run order; an unknown name is bad input
std::vector<const experiments::Experiment*> chosen_experiments(
    const std::vector<std::string>& names) {
  const auto& all = experiments::all_experiments();
  std::vector<const experiments::Experiment*> chosen;
  for (const std::string& n : names) {
    const experiments::Experiment* found = nullptr;
    for (const auto& e : all) found = e.name == n ? &e : found;
    if (!found) {
      std::string known;
      for (const auto& e : all) known += (known.empty() ? "" : ", ") + e.name;
      throw_input_error("physik experiment run", "", "NAME",
                        "unknown experiment '" + n + "' (known: " + known + ")");
    }
    chosen.push_back(found);
  }
  if (chosen.empty()) {
    for (const auto& e : all) chosen.push_back(&e);
  }
  return chosen;
}

void run_experiments(const RunOptions& opt) {
  const std::vector<const experiments::Experiment*> chosen = chosen_experiments(opt.names);
  if (!std::filesystem::is_directory(opt.models + "/rigs")) {
    throw_input_error(opt.models, "", "--models", "no rigs/ folder here");
  }
  for (std::size_t k = 0; k < chosen.size(); ++k) {
    const auto& e = *chosen[k];
    const auto t0 = std::chrono::steady_clock::now();
    std::cerr << "[" << k + 1 << "/" << chosen.size() << "] " << e.name << " (" << e.figure
              << "): " << e.description << "\n";
    experiments::Context ctx;
    ctx.out_dir = opt.out + "/" + e.name;
    std::filesystem::remove_all(ctx.out_dir);  // reruns start clean
    create_output_dir(ctx.out_dir, "--out");
    ctx.models_dir = opt.models;
    ctx.quick = opt.quick;
    ctx.log = &std::cerr;
    e.run(ctx);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::cerr << "    done in " << s << " s -> " << ctx.out_dir << "\n";
  }
}

}  // namespace

void add_experiment_commands(CLI::App& app) {
  CLI::App* exp = app.add_subcommand("experiment", "Run the paper's experiments and studies");
  exp->require_subcommand(1);

  auto* list = exp->add_subcommand("list", "List the experiments in run order");
  list->callback([] {
    for (const auto& e : experiments::all_experiments()) {
      std::cout << e.name << "\t" << e.figure << "\t" << e.description << "\n";
    }
  });

  auto opt = std::make_shared<RunOptions>();
  auto* run = exp->add_subcommand("run", "Run experiments (all when no NAME is given)");
  run->add_option("NAME", opt->names, "Experiment names (see 'physik experiment list')");
  run->add_option("--out", opt->out, "Results folder; each experiment writes <out>/<name>/")
      ->capture_default_str();
  run->add_option("--models", opt->models, "The models/ folder with rigs/ and scenes/")
      ->capture_default_str();
  run->add_flag("--quick", opt->quick, "Smaller runs (smoke checks)");
  run->callback([opt] { run_experiments(*opt); });
}

}  // namespace physik::cli
