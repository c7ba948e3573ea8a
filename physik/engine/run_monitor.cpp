#include "physik/engine/run_monitor.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "physik/engine/engine.h"
#include "physik/model/kinematics.h"

namespace physik {

RunRules run_rules(const Scene& scene) {
  RunRules r;
  r.speed_tol = scene.speed_tol();
  r.energy_bound = scene.divergence_energy();
  r.total_mass = scene.rig.total_mass();
  for (const TargetChange& t : scene.schedule) r.last_event = std::max(r.last_event, t.step);
  r.settle_steps = scene.convergence.settle_steps;
  r.stop_when_converged = scene.convergence.stop_when_converged;
  r.stop_at_residual = scene.convergence.stop_at_residual_tol;
  r.residual_tol = scene.residual_tol();
  return r;
}

bool state_finite(const SimState& s) {
  for (std::size_t i = 0; i < s.com_world.size(); ++i) {
    if (!s.com_world[i].allFinite() || !s.vel_world[i].allFinite() ||
        !s.omega_world[i].allFinite() || !s.frames.orient_world[i].coeffs().allFinite()) {
      return false;
    }
  }
  return true;
}

StepObservation observe_step(const Scene& scene, const SimState& s, const StepStats& st) {
  StepObservation o;
  o.step = s.step;
  o.kinetic_energy = st.kinetic_energy;
  o.state_finite = state_finite(s);
  o.passes = st.passes;
  o.joint_separation = st.joint_separation;
  o.limit_violation = max_limit_violation(scene.rig, s.pose);
  for (int left : s.interp_steps_left) o.target_moving = o.target_moving || left > 0;
  o.max_residual = st.max_residual;
  return o;
}

RunMonitor::RunMonitor(const RunRules& rules, std::string reason_prefix)
    : rules_(rules), prefix_(std::move(reason_prefix)) {}

bool RunMonitor::observe(const StepObservation& o) {
  steps_run_ = o.step;
  total_passes_ += o.passes;
  max_passes_ = std::max(max_passes_, o.passes);
  // std::max keeps the old value against a NaN: the peak stays the last finite one
  peak_ke_ = std::max(peak_ke_, o.kinetic_energy);
  max_separation_ = std::max(max_separation_, o.joint_separation);
  max_violation_deg_ = std::max(max_violation_deg_, rad2deg(o.limit_violation));

  // divergence: a non-finite state, or energy past the bound
  if (!std::isfinite(o.kinetic_energy) || !o.state_finite || o.engine_non_finite) {
    diverged_ = true;
    reason_ = prefix_ + "non-finite state at step " + std::to_string(o.step);
  } else if (o.kinetic_energy > rules_.energy_bound) {
    diverged_ = true;
    reason_ = prefix_ + "kinetic energy " + std::to_string(o.kinetic_energy) +
              " J passed the bound " + std::to_string(rules_.energy_bound) + " J at step " +
              std::to_string(o.step);
  }
  if (diverged_) return true;

  // at rest: mass-weighted rms speed below the tolerance, with no target still moving
  const bool targets_still = !o.target_moving && o.step > rules_.last_event;
  const bool at_rest = targets_still &&
                       std::sqrt(2.0 * o.kinetic_energy / rules_.total_mass) < rules_.speed_tol;
  rest_run_ = at_rest ? rest_run_ + 1 : 0;
  if (rules_.stop_at_residual) {
    // IK use: converged = targets met; no progress for a while short of them = stalled
    if (targets_still && o.max_residual < rules_.residual_tol) {
      converged_ = true;
      steps_to_converge_ = o.step;
      return true;
    }
    if (!targets_still || o.max_residual < (1.0 - rules_.stall_fraction) * best_residual_) {
      best_residual_ = std::min(best_residual_, o.max_residual);
      last_improvement_ = o.step;
    }
    return o.step - last_improvement_ >= rules_.stall_steps;
  }
  if (rest_run_ >= rules_.settle_steps) {
    if (!converged_) steps_to_converge_ = o.step - rest_run_ + 1;
    converged_ = true;
    return rules_.stop_when_converged;
  }
  if (rest_run_ == 0) {
    converged_ = false;
    steps_to_converge_ = -1;
  }
  return false;
}

RunSummary RunMonitor::summary() const {
  RunSummary out;
  out.converged = converged_;
  out.diverged = diverged_;
  out.divergence_reason = reason_;
  out.steps_run = steps_run_;
  out.steps_to_converge = steps_to_converge_;
  out.max_joint_separation = max_separation_;
  out.mean_passes_per_step = steps_run_ ? double(total_passes_) / steps_run_ : 0.0;
  out.max_passes_in_a_step = max_passes_;
  out.peak_kinetic_energy = peak_ke_;
  out.max_limit_violation_deg = max_violation_deg_;
  return out;
}

void fill_final_state(const Scene& scene, const SimState& s, RunSummary& out) {
  control_residuals(scene, s, out.final_residuals);
  out.final_kinetic_energy = kinetic_energy(scene.rig, s);
  out.final_pose = s.pose;
  out.final_frames = s.frames;
  out.damping_auto_value = s.damping_auto_value;
  out.damping_auto_updates = s.damping_auto_updates;
}

}  // namespace physik
