// The bookkeeping of a run, shared by every engine that runs a scene (physik::run_scene, the
// MuJoCo reference run_mujoco): it sees one observation per step and owns the rules that turn
// them into a RunSummary.
//
// Per step k (k = state.step after the step, 1 for the first), with KE in J and M the rig's mass:
//   diverged   if KE is not finite, the state is not finite, or the engine flagged a non-finite
//              value of its own (MuJoCo's bad qacc/qvel/qpos warnings); else if KE > E_bound
//              (scene.divergence_energy()). The run stops at that step.
//   at rest    if no target is still interpolating, k > the last schedule event, and the
//              mass-weighted rms speed v = sqrt(2 KE / M) is below speed_tol (rig units/s).
//   converged  once settle_steps consecutive steps are at rest; steps_to_converge is the first
//              step of that window (k - settle_steps + 1 when it is reached). One step not at
//              rest clears both (motion resumed); the window then starts over.
// Over the run it keeps the peak KE, the largest joint separation (rig units), the largest limit
// violation (deg), steps_run and the joint passes (mean and max per step).
#pragma once

#include <limits>
#include <string>
#include <utility>

#include "physik/engine/run_summary.h"

namespace physik {

// What the monitor needs to know about the scene.
struct RunRules {
  double speed_tol = 0.0;      // rig units/s, at rest below it
  double energy_bound = 0.0;   // J, diverged above it
  double total_mass = 1.0;     // kg
  int last_event = 0;          // last step at which the schedule changes a target (0 = none)
  int settle_steps = 10;       // consecutive steps at rest to call the run converged
  bool stop_when_converged = false;
  // IK use (scene convergence.stop_at_residual_tol): converged means every control point within
  // residual_tol of its goal; the run stops there, or when it stalls short of it (then not
  // converged): the largest residual has not improved by stall_fraction of itself over
  // stall_steps steps (the classic solvers' stall window; speed alone is no test here, since an
  // exponentially settling rig slows down long before its residual is small)
  bool stop_at_residual = false;
  double residual_tol = 0.0;     // rig units
  int stall_steps = 50;          // steps
  double stall_fraction = 0.01;  // 1
};
RunRules run_rules(const Scene& scene);

// One step as the monitor sees it.
struct StepObservation {
  int step = 0;                   // steps taken after this one (state.step)
  double kinetic_energy = 0.0;    // J, after the step
  bool state_finite = true;       // positions, velocities, orientations all finite
  bool engine_non_finite = false; // the engine's own non-finite flag (MuJoCo bad qacc); false if none
  int passes = 0;                 // solver passes (iterations) this step
  double joint_separation = 0.0;  // rig units, largest parent-tail to child-head gap
  double limit_violation = 0.0;   // rad, largest joint-limit violation of the pose
  bool target_moving = false;     // some target still interpolating toward its goal
  double max_residual = 0.0;      // rig units, largest control-point distance to its goal
};

// Every position, velocity and orientation of the state is finite.
bool state_finite(const SimState& state);
// The observation of a state after a step with stats `st` (engine_non_finite left false).
StepObservation observe_step(const Scene& scene, const SimState& state, const StepStats& st);

class RunMonitor {
 public:
  // reason_prefix starts every divergence reason (e.g. "MuJoCo: ").
  explicit RunMonitor(const RunRules& rules, std::string reason_prefix = "");
  explicit RunMonitor(const Scene& scene, std::string reason_prefix = "")
      : RunMonitor(run_rules(scene), std::move(reason_prefix)) {}

  // Record one step; true when the run should stop here (diverged, or converged and the rules
  // say stop). Observations after that are not meant to be fed.
  bool observe(const StepObservation& obs);

  bool converged() const { return converged_; }
  bool diverged() const { return diverged_; }
  int rest_run() const { return rest_run_; }  // consecutive steps at rest so far

  // The fields the monitor owns: converged, diverged, divergence_reason, steps_run,
  // steps_to_converge, max_joint_separation, mean/max passes, peak KE, max limit violation.
  // The rest (final residuals, final KE, pose, frames, wall time) is left default.
  RunSummary summary() const;

 private:
  RunRules rules_;
  std::string prefix_;
  bool converged_ = false;
  bool diverged_ = false;
  std::string reason_;
  int steps_run_ = 0;
  int steps_to_converge_ = -1;
  int rest_run_ = 0;
  long total_passes_ = 0;
  int max_passes_ = 0;
  double peak_ke_ = 0.0;
  double max_separation_ = 0.0;
  double max_violation_deg_ = 0.0;
  double best_residual_ = std::numeric_limits<double>::infinity();  // IK use
  int last_improvement_ = 0;                                         // IK use: step
};

// The final-state fields of a summary: residuals to the goal targets, KE, pose and frames.
void fill_final_state(const Scene& scene, const SimState& state, RunSummary& out);

}  // namespace physik
