// The JSON reports of `physik tune --report` and `physik equilibrium`, shared by the CLI and the
// Python module (one function each, so both write the same keys and values).
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "physik/model/scene.h"
#include "tune/equilibrium.h"
#include "tune/tuner.h"

namespace physik::tune {

// `physik tune --report`: values, costs, Ceres' brief report, the tuned run's summary, the scan.
nlohmann::json tune_report_to_json(const Scene& scene, const TuneOptions& options,
                                   const TuneResult& result);

// `physik equilibrium --start S [--compare]`: "initial" or "physik" (InputError naming --start).
void check_equilibrium_start(const std::string& start);

struct EquilibriumReport {
  nlohmann::json doc;        // what `physik equilibrium` writes
  EquilibriumResult result;  // the minimiser (pose, frames, potentials)
  bool ran_physik = false;   // PhysIK was run (compare, or start = physik)
  RunSummary physik_run;     // its summary when it ran
};

// The exact static pose from `start`; with `compare` (or start = physik) PhysIK's run too and
// its final-pose distance to the equilibrium in doc["physik"]. max_iterations: Ceres's
// (EquilibriumOptions), > 0.
EquilibriumReport equilibrium_report(const Scene& scene, const std::string& start, bool compare,
                                     int max_iterations = EquilibriumOptions{}.max_iterations);

}  // namespace physik::tune
