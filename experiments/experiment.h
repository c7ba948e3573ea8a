// Experiments: one file per paper figure or study. Each writes CSV tables and a summary.json
// under <out>/<name>/; the analysis scripts draw them and analysis/report.py gathers every
// summary's "report" section (experiments/report.h builds it) into results/REPORT.md.
//
// Each experiment registers itself from its own file, with an order key that places it in the
// run order of `physik experiment list` and `make reproduce`:
//
//   const Registration registered{50, {"fig5_running", "Fig 5", "running pose ...", run}};
//
// No central list to edit. (physik_experiments is an OBJECT library, so the linker keeps every
// experiment's object file although nothing names it.)
#pragma once

#include <functional>
#include <ostream>
#include <string>
#include <vector>

namespace physik::experiments {

struct Context {
  std::string out_dir;          // this experiment's folder, already created
  std::string models_dir;       // the repository's models/ folder
  bool quick = false;           // a smaller run (tests, smoke checks)
  std::ostream* log = nullptr;  // progress lines
};

struct Experiment {
  std::string name;    // folder name under results/
  std::string figure;  // the paper figure or study it reproduces
  std::string description;
  std::function<void(const Context&)> run;  // throws on failure
};

// Registers an experiment at static initialisation; `order` (unique, ascending) is its place in
// the run order.
struct Registration {
  Registration(int order, Experiment experiment);
};

// Every registered experiment, in run order. Throws std::logic_error if two share a name or an
// order key.
const std::vector<Experiment>& all_experiments();

}  // namespace physik::experiments
