// Shared by the experiments' tests: run one experiment as `physik experiment run --quick` does.
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "experiments/experiment.h"
#include "physik/io/json_fields.h"

namespace physik::test {

// Experiment `name` in quick mode into `out_dir` (created if missing), the source tree's models/;
// returns its summary.json. std::runtime_error when no experiment has that name.
inline nlohmann::json run_quick_experiment(const std::string& name, const std::string& out_dir) {
  using experiments::all_experiments, experiments::Context, experiments::Experiment;
  Context ctx;
  ctx.out_dir = out_dir;
  ctx.models_dir = std::string(PHYSIK_SOURCE_DIR) + "/models";
  ctx.quick = true;
  std::filesystem::create_directories(out_dir);
  for (const Experiment& e : all_experiments()) {
    if (e.name != name) continue;
    e.run(ctx);
    return read_json_file(out_dir + "/summary.json");
  }
  throw std::runtime_error("no experiment named " + name);
}

// <TempDir>/<name>, emptied
inline std::string fresh_temp_dir(const std::string& name) {
  const std::string dir = ::testing::TempDir() + "/" + name;
  std::filesystem::remove_all(dir);
  return dir;
}

}  // namespace physik::test
