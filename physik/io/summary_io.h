// A run's summary as JSON: the keys of `physik simulate`'s summary.json (docs/engine.md
// "Run outputs"), shared by every command and experiment that writes one.
#pragma once

#include <nlohmann/json.hpp>

#include "physik/engine/run_summary.h"
#include "physik/model/scene.h"
#include "physik/posing/scene_solve.h"

namespace physik {

nlohmann::json summary_to_json(const Scene& scene, const RunSummary& s);

// `physik solve`'s summary.json: for the engine, `simulate`'s keys (the scene as solved) plus the
// solve's (iterations = physics steps, residual, residual_tol, stalled, out_of_steps, finish,
// finish_iterations; dt_growth and max_dt for the solve mode); for a classic solver its report
// (converged, stalled, iterations, final_residuals, residual, residual_tol, reach,
// max_limit_violation_deg); both with "solver", "time_s" and "not_converged_reason" (why a solve
// that did not diverge stopped short of its tolerance, "" when it converged: scene_solve.h
// solve_shortfall).
nlohmann::json solve_summary_to_json(const SceneSolveResult& result);

}  // namespace physik
