#include "physik/io/summary_io.h"

#include <cstdio>

#include "physik/engine/contact_data.h"
#include "physik/engine/measures.h"
#include "physik/engine/run_monitor.h"
#include "physik/io/scene_io.h"
#include "physik/model/joint_angles.h"

namespace physik {

namespace {

// the contacts of the final pose (contact_data.h), only for scenes with a ground or self-collision:
// how many, the deepest overlap (rig units) and that depth over the thinner capsule's radius
void add_contact_fields(const Scene& scene, const RunSummary& s, nlohmann::json& out) {
  if (!scene.collision.any()) return;
  const Penetration pen = penetration(scene, contacts_at_pose(scene, s.final_frames));
  out["final_contacts"] = pen.contacts;
  out["final_max_penetration"] = pen.max_depth;
  out["final_max_penetration_fraction"] = pen.max_depth_fraction;
}

// the implicit step's energy guard (implicit_advance.h), only for implicit runs
void add_implicit_fields(const Scene& scene, const RunSummary& s, nlohmann::json& out) {
  if (scene.params.scheme != Scheme::kImplicit) return;
  out["implicit_split_steps"] = s.implicit_split_steps;
  out["implicit_max_substeps"] = s.implicit_max_substeps;
  out["implicit_retaken_steps"] = s.implicit_retaken_steps;
  out["implicit_unresolved_steps"] = s.implicit_unresolved_steps;
  out["implicit_deepest_steps"] = s.implicit_deepest_steps;
  if (scene.params.implicit_linearisation == ImplicitLinearisation::kFull) {
    out["implicit_gauss_newton_steps"] = s.implicit_gauss_newton_steps;
  }
}

// the bone targets at the final pose (measures.h), each list only where the scene has them: pins
// (rig units), orientation targets and aims (rad)
void add_bone_target_fields(const Scene& scene, const RunSummary& s, nlohmann::json& out) {
  const BoneFrames& f = s.final_frames;
  if (!scene.pins.empty()) {
    nlohmann::json r = nlohmann::json::array();
    for (const Pin& p : scene.pins) r.push_back(pin_residual(f, p));
    out["pin_residuals"] = r;
  }
  if (!scene.orientation_targets.empty()) {
    nlohmann::json r = nlohmann::json::array();
    for (const OrientationTarget& t : scene.orientation_targets)
      r.push_back(orientation_residual(f, t));
    out["orientation_residuals_rad"] = r;
  }
  if (!scene.aim_targets.empty()) {
    nlohmann::json r = nlohmann::json::array();
    for (const AimTarget& t : scene.aim_targets) r.push_back(aim_residual(f, t));
    out["aim_residuals_rad"] = r;
  }
}

}  // namespace

nlohmann::json summary_to_json(const Scene& scene, const RunSummary& s) {
  // over the height, or the mean bone length for a flat rig (no inf or nan: Rig::reference_length)
  const double h = scene.rig.reference_length();
  nlohmann::json rel = nlohmann::json::array();
  for (double r : s.final_residuals) rel.push_back(r / h);
  nlohmann::json out = {
      {"scene", scene.file},
      {"rig", scene.rig_file},
      {"params", params_as_run_json(scene)},  // every row the run reads, at its value
      // N s/m, the damping the run used: damping auto's last choice, or the set value
      {"damping", scene.params.damping_auto ? s.damping_auto_value : scene.params.damping},
      {"converged", s.converged},
      {"diverged", s.diverged},
      {"divergence_reason", s.divergence_reason},
      {"steps_run", s.steps_run},
      {"steps_to_converge",
       s.steps_to_converge < 0 ? nlohmann::json(nullptr) : nlohmann::json(s.steps_to_converge)},
      {"final_residuals", s.final_residuals},
      {"final_pose_step", s.final_pose_step},
      {"final_residuals_over_height", rel},
      {"rig_height", scene.rig.height()},
      {"max_joint_separation", s.max_joint_separation},
      {"mean_passes_per_step", s.mean_passes_per_step},
      {"max_passes_in_a_step", s.max_passes_in_a_step},
      {"peak_kinetic_energy", s.peak_kinetic_energy},
      {"final_kinetic_energy", s.final_kinetic_energy},
      {"max_limit_violation_deg", s.max_limit_violation_deg},
      {"energy_given", s.energy_given},
      {"peak_energy_ratio", s.peak_energy_ratio},
      {"joint_unpropagated_steps", s.joint_unpropagated_steps},
      {"max_unreached_joints", s.max_unreached_joints},
      {"joint_solve_warning", s.joint_solve_warning},
      {"speed_tol", scene.speed_tol()},
      {"residual_tol", scene.residual_tol()},
      {"wall_time_s", s.wall_time_s},
      {"final_state_hash", [&] {
         char buf[17];
         std::snprintf(buf, sizeof buf, "%016llx",
                       static_cast<unsigned long long>(state_hash(s.final_frames)));
         return std::string(buf);
       }()}};
  if (s.diverged) out["divergence_hint"] = divergence_hint(scene);
  // damping_auto's choice (N s/m), only when it was asked for: other summaries stay as they were
  if (scene.params.damping_auto) {
    out["damping_auto_value"] = s.damping_auto_value;
    out["damping_auto_updates"] = s.damping_auto_updates;
  }
  add_contact_fields(scene, s, out);
  add_implicit_fields(scene, s, out);
  add_bone_target_fields(scene, s, out);
  return out;
}

namespace {

nlohmann::json engine_solve_json(const SceneSolveResult& r) {
  nlohmann::json j = summary_to_json(r.scene, r.run);
  const bool equilibrium = r.solve.method == SolveMethod::kEquilibrium;
  j["method"] = equilibrium ? "equilibrium" : "steps";
  j["iterations"] = r.solve.steps;
  j["time_s"] = r.time_s;
  j["residual"] = r.solve.residual;
  j["residual_tol"] = r.solve.tolerance;
  j["residual_tol_angle"] = r.solve.tolerance_angle;
  j["stalled"] = r.solve.stalled;
  j["out_of_steps"] = r.solve.out_of_steps;
  if (equilibrium) {  // the trust region's (physik/engine/equilibrium_solve.h)
    j["stationary"] = r.solve.stationary;
    j["refused_iterations"] = r.solve.refused;
    j["final_step"] = r.solve.final_dt;
  }
  j["finish"] = r.rule.finish == SolveFinish::kCcd   ? "ccd"
                : r.rule.finish == SolveFinish::kDls ? "dls"
                                                     : "none";
  j["finish_iterations"] = r.solve.finish_iterations;
  if (r.solver == "physik-steps") {  // the time-stepping solve mode
    j["dt_growth"] = r.rule.dt_growth;
    j["max_dt"] = r.rule.max_dt;
  }
  return j;
}

nlohmann::json classic_solve_json(const SceneSolveResult& r) {
  const IkReport& rep = r.classic;
  nlohmann::json j = {
      {"scene", r.scene.file},
      {"rig", r.scene.rig_file},
      {"converged", rep.converged},
      {"diverged", false},
      {"stalled", rep.stalled},
      {"iterations", rep.iterations},
      {"final_residuals", rep.residuals},
      {"residual", rep.residual},
      {"residual_tol", rep.tolerance},
      {"reach", rep.reach},
      {"max_limit_violation_deg",
       rad2deg(max_limit_violation(r.scene.rig, r.scene.params.locked_axes(), r.pose))},
      {"time_s", rep.time_s}};
  if (!r.scene.pins.empty()) j["pin_residuals"] = r.pin_residuals;
  if (!r.scene.orientation_targets.empty()) {  // DLS and JT's orientation rows (jacobian.cpp)
    j["orientation_residuals_rad"] = rep.orientation_residuals;
    j["orientation_residual_rad"] = rep.orientation_residual;
    j["orientation_tol_rad"] = rep.orientation_tolerance;
    j["orientation_length"] = rep.orientation_length;
  }
  return j;
}

}  // namespace

nlohmann::json solve_summary_to_json(const SceneSolveResult& r) {
  nlohmann::json j = r.engine ? engine_solve_json(r) : classic_solve_json(r);
  j["solver"] = r.solver;
  j["not_converged_reason"] = solve_shortfall(r);  // "" when it converged (or diverged)
  // every goal by its own measure, and those short of their tolerance (scene_solve.h)
  nlohmann::json goals = nlohmann::json::array(), short_goals = nlohmann::json::array();
  for (const GoalReport& g : goal_reports(r)) {
    const nlohmann::json row = {{"goal", g.goal},
                                {"residual", g.residual},
                                {"tolerance", g.tolerance},
                                {"unit", goal_unit(g.kind)},
                                {"met", g.met()}};
    goals.push_back(row);
    if (!g.met() && !r.diverged) short_goals.push_back(row);
  }
  j["goals"] = goals;
  j["short_goals"] = short_goals;
  return j;
}

}  // namespace physik
