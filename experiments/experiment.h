// Experiments: one file per paper figure or study. Each writes CSV tables and a summary.json
// under <out>/<name>/; the analysis scripts draw them and analysis/report.py gathers every
// summary's "report" section into results/REPORT.md:
//
//   "report": {"title": "...", "section": "...", "claims": [
//       {"claim": "...", "measured": "...", "holds": "yes" | "no" | "partly" | "n/a"}],
//     "notes": ["..."]}
#pragma once

#include <functional>
#include <ostream>
#include <string>
#include <vector>

namespace physik::experiments {

struct Context {
  std::string out_dir;     // this experiment's folder, already created
  std::string models_dir;  // the repository's models/ folder
  bool quick = false;      // a smaller run (tests, smoke checks)
  std::ostream* log = nullptr;  // progress lines
};

struct Experiment {
  std::string name;         // folder name under results/
  std::string figure;       // the paper figure or study it reproduces
  std::string description;
  std::function<void(const Context&)> run;  // throws on failure
};

// Every experiment, in the order `make reproduce` runs them.
const std::vector<Experiment>& all_experiments();

}  // namespace physik::experiments
