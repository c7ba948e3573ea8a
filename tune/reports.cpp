#include "tune/reports.h"

#include <algorithm>

#include "physik/io/summary_io.h"
#include "physik/model/errors.h"

namespace physik::tune {

namespace {

double max_of(const std::vector<double>& v) {
  return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end());
}

}  // namespace

nlohmann::json tune_report_to_json(const Scene& scene, const TuneOptions& to, const TuneResult& r) {
  nlohmann::json scan = nlohmann::json::array();
  for (const auto& s : r.scan) {
    scan.push_back({{"values", s.values},
                    {"cost", s.cost},
                    {"diverged", s.diverged},
                    {"steps_to_converge", s.steps_to_converge}});
  }
  nlohmann::json doc = {{"scene", scene.file},
                        {"objective", to_string(to.objective)},
                        {"measure", to_string(to.measure)},
                        {"params", r.names},
                        {"initial_values", r.initial_values},
                        {"values", r.values},
                        {"initial_cost", r.initial_cost},
                        {"start_cost", r.start_cost},
                        {"scan_cost", r.scan_cost},
                        {"final_cost", r.final_cost},
                        {"improved", !no_improvement(r)},
                        {"evaluations", r.evaluations},
                        {"scene_evaluations", r.scene_evaluations},
                        {"reference_steps", r.reference_steps},
                        {"wall_time_s", r.wall_time_s},
                        {"ceres", r.ceres_brief},
                        {"scene_run", summary_to_json(scene, r.scene_run)},
                        {"tuned_run", summary_to_json(r.tuned_scene, r.tuned_run)},
                        {"scan", scan}};
  // the scene's damping was auto: the value it resolved to at the start (N s/m)
  if (r.damping_auto) {
    doc["damping_auto"] = {{"value_at_start", r.damping_auto_value},
                           {"updates", r.damping_auto_updates}};
  }
  return doc;
}

void check_equilibrium_start(const std::string& start) {
  if (start != "initial" && start != "physik") {
    throw_input_error("--start", "", "", "expected 'initial' or 'physik'");
  }
}

EquilibriumReport equilibrium_report(const Scene& scene, const std::string& start, bool compare,
                                     int max_iterations) {
  check_equilibrium_start(start);
  if (max_iterations < 1) {
    throw_input_error("--max-iterations", "", "", "expected a positive integer");
  }
  EquilibriumReport out;
  out.ran_physik = compare || start == "physik";
  if (out.ran_physik) out.physik_run = run_scene(scene);
  EquilibriumOptions eo;
  eo.max_iterations = max_iterations;
  if (start == "physik") eo.start = &out.physik_run.final_pose;
  out.result = solve_equilibrium(scene, eo);
  const EquilibriumResult& e = out.result;
  out.doc = equilibrium_to_json(scene, e);
  out.doc["start"] = start;
  if (out.ran_physik) {
    const RunSummary& run = out.physik_run;
    const double gap = max_pose_distance(run.final_frames, e.frames);
    // a diverged run's pose is its last finite one: no distance to report
    const nlohmann::json distance = run.diverged ? nlohmann::json(nullptr) : nlohmann::json(gap);
    out.doc["physik"] = {
        {"converged", run.converged},
        {"diverged", run.diverged},
        {"divergence_reason", run.divergence_reason},
        {"steps_to_converge", run.steps_to_converge},
        {"max_final_residual", max_of(run.final_residuals)},
        {"potential", scene_potential(scene, run.final_pose)},
        {"max_pose_distance", distance},
        {"max_pose_distance_over_height",
         run.diverged ? nlohmann::json(nullptr) : nlohmann::json(gap / scene.rig.height())}};
  }
  return out;
}

}  // namespace physik::tune
