// The bookkeeping of a run, shared by every engine that runs a scene (physik::run_scene, the
// MuJoCo reference run_mujoco): it sees one observation per step and owns the rules that turn
// them into a RunSummary.
//
// Per step k (k = state.step after the step, 1 for the first), with KE in J and M the rig's mass:
//   diverged   if KE, a residual or the state is not finite, or the engine flagged a non-finite
//              value of its own (MuJoCo's bad qacc/qvel/qpos warnings); else by the energy rule
//              below (or, when the scene gives convergence.divergence_energy, if KE passes that
//              fixed bound). The run stops at that step.
//   at rest    if no target is still interpolating, k > the last schedule event, and the
//              mass-weighted rms speed v = sqrt(2 KE / M) is below speed_tol (rig units/s;
//              default 1e-3 of the rig's mean bone length per second, Scene::speed_tol).
//   converged  once settle_steps consecutive steps are at rest; steps_to_converge is the first
//              step of that window (k - settle_steps + 1 when it is reached). One step not at
//              rest clears both (motion resumed); the window then starts over.
// Over the run it keeps the peak KE, the largest joint separation (rig units), the largest limit
// violation (deg), steps_run and the joint passes (mean and max per step).
//
// The energy rule. The rig's mechanical energy is E = KE + U, with U the potential
// (physik/engine/potential.h potential_energy: control springs toward the targets of the step,
// torsion springs of the pose, and gravity and the contact springs where the scene has them,
// ground_contacts.h, self_contacts.h). The only forces that can add energy are the springs' targets
// when they move: damping (-c v), the angular-velocity factor (w <- f w), the contacts' dampers and
// friction only remove it, gravity and the contact springs are in U, and the joint forces do no
// work on a rigid, connected rig. So along the exact motion
//     E_k <= E_in,k = E_0 + W_k,    W_k = sum_{j<=k} [U_c(a_{j-1}, t_j) - U_c(a_{j-1}, t_{j-1})]
// where E_0 = KE_0 + U_0 is the initial state's energy (the initial targets count as a jump from
// the attachment points, so they enter through W_1) and W_k is the work of the targets'
// moves, each taken at the pose before the step (a target change at fixed pose changes U). The
// step is explicit, so the discrete E_k may exceed E_in,k; the monitor calls a run diverged when
//     E_k > kEnergyMultiple * (max(E_in,k, 0) + E_floor),     E_floor = M speed_tol^2 / 2.
//   kEnergyMultiple = 4: semi-implicit Euler on a spring of frequency w conserves the shadow
//     energy E~ = E - (w dt / 2) p.x; the true energy oscillates within E~ / (1 +- w dt / 2), so a
//     step stable by a margin of 2 (w dt <= 1, half its limit 2) stays within 1 / (1 - 1/2) = 2 of
//     the energy it was given; the Gauss-Seidel joint solve (stopping at an absolute eps) and
//     the torsion torque (the gradient in theta, not in the rotation) add errors of their own,
//     which we allow another factor 2 for. On the damping sweep grid runs that settle peak well
//     under 4 and the unstable ones pass it within a few steps of leaving the stable region
//     (experiment damping_sweep; tests/run_verdicts_test.cpp).
//   E_floor: the kinetic energy of a rig moving at the rest speed, so a rig at rest is never
//     diverged, whatever its energy (a flat rig whose target is met from the start has E_in = 0).
#pragma once

#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "physik/engine/run_summary.h"

namespace physik {

constexpr double kEnergyMultiple = 4.0;  // 1, see the energy rule above

// What the monitor needs to know about the scene.
struct RunRules {
  double speed_tol = 0.0;       // rig units/s, at rest below it
  double energy_bound = 0.0;    // J; > 0: diverged when KE passes it (a fixed bound, the scene's
                                //    convergence.divergence_energy); 0: the energy rule
  double initial_energy = 0.0;  // J, E_0 = KE_0 + U_0 of the initial state (energy rule)
  double energy_floor = 0.0;    // J, E_floor = M speed_tol^2 / 2 (energy rule)
  double energy_multiple = kEnergyMultiple;  // 1 (energy rule)
  double total_mass = 1.0;                   // kg
  int last_event = 0;     // last step at which the schedule changes a target (0 = none)
  int settle_steps = 10;  // consecutive steps at rest to call the run converged
  bool stop_when_converged = false;
  // IK use (scene convergence.stop_at_residual_tol): converged means every control point within
  // residual_tol of its goal, and every orientation target and aim within it as an arc
  // (measures.h, the goal residual); the run stops there, or when it stalls short of it (then not
  // converged): the largest residual has not improved by stall_fraction of itself over
  // stall_steps steps (the classic solvers' stall window; speed alone is no test here, since an
  // exponentially settling rig slows down long before its residual is small)
  bool stop_at_residual = false;
  double residual_tol = 0.0;     // rig units
  int stall_steps = 50;          // steps
  double stall_fraction = 0.01;  // 1
};
// The scene's rules; its initial energy is initial_energy's (which allocates: once per run).
RunRules run_rules(const Scene& scene);

// One step as the monitor sees it.
struct StepObservation {
  int step = 0;                 // steps taken after this one (state.step)
  double kinetic_energy = 0.0;  // J, after the step
  bool state_finite = true;     // positions, velocities, orientations all finite
  bool engine_non_finite =
      false;       // the engine's own non-finite flag (MuJoCo bad qacc); false if none
  int passes = 0;  // solver passes (iterations) this step
  double joint_separation = 0.0;    // rig units, largest parent-tail to child-head gap
  double limit_violation = 0.0;     // rad, largest joint-limit violation of the pose
  bool target_moving = false;       // some target still interpolating toward its goal
  double max_residual = 0.0;        // rig units, the goal residual (measures.h)
  double potential_energy = 0.0;    // J, U after the step: control springs toward this step's
                                    //    targets, torsion springs of the pose
  double target_work = 0.0;         // J, W of this step's target change (used when state is null)
  const SimState* state = nullptr;  // the state after the step: the monitor then measures the
                                    // target work itself (it keeps the step before's targets)
  int unreached_joints = 0;  // joints the joint solve's forces did not reach (joint_forces.h)
};

// Every position, velocity and orientation of the state is finite.
bool state_finite(const SimState& state);
// The observation of a state after a step with stats `st` (engine_non_finite left false):
// also U, the joints the joint solve did not reach, and `state` itself for the target work.
StepObservation observe_step(const Scene& scene, SimState& state, const StepStats& st);

// E_0 = KE_0 + U_0 of the scene's initial state (init_state): the rigid initial velocity, and
// the force list's potential of the initial pose (potential.h initial_potential_energy; the
// control springs start at their attachments; the bone targets' springs, whose targets hold still,
// count from where they start).
double initial_energy(const Scene& scene);

class RunMonitor {
 public:
  // reason_prefix starts every divergence reason (e.g. "MuJoCo: ").
  explicit RunMonitor(const RunRules& rules, std::string reason_prefix = "");
  // with the scene, observations that carry a state get their target work measured; the scene
  // must outlive the monitor
  explicit RunMonitor(const Scene& scene, std::string reason_prefix = "");

  // Start over for a run that continues from `state` (physik/posing: a solve after live steps
  // and target moves): the ledger's E_0 is the state's own KE + U toward its current targets,
  // its attachments and targets are the state's, every count is reset (the summary's steps are
  // this run's: from the state's step at the restart). The buffers are reused:
  // no allocation after the first restart. `scene` must outlive the monitor.
  void restart(const Scene& scene, SimState& state, const RunRules& rules);

  // Record one step; true when the run should stop here (diverged, or converged and the rules
  // say stop). Observations after that are not meant to be fed.
  bool observe(const StepObservation& obs);

  bool converged() const { return converged_; }
  bool diverged() const { return diverged_; }
  int rest_run() const { return rest_run_; }  // consecutive steps at rest so far
  double energy_given() const { return rules_.initial_energy + target_work_; }  // J, E_in,k

  // The fields the monitor owns: converged, diverged, divergence_reason, steps_run,
  // steps_to_converge, max_joint_separation, mean/max passes, peak KE, max limit violation, the
  // energy ledger (energy given, peak ratio) and the joint solve's unpropagated steps.
  // The rest (final residuals, final KE, pose, frames, wall time) is left default.
  RunSummary summary() const;
  // The final-state fields of a summary from the state the run stopped in; when that state is
  // not finite, from the last finite one the monitor saw (needs observations with a state).
  void fill_final(const Scene& scene, const SimState& state, RunSummary& out) const;

 private:
  double step_target_work(const StepObservation& o);
  bool check_divergence(const StepObservation& o);

  const Scene* scene_ = nullptr;
  std::vector<Vec3> prev_attach_world_;   // (ncontrol) attachment points before the step
  std::vector<Vec3> prev_targets_world_;  // (ncontrol) targets of the step before
  double target_work_ = 0.0;              // J, W_k so far
  double peak_energy_ratio_ = 0.0;        // max_k E_k / (max(E_in,k, 0) + E_floor)
  int unpropagated_steps_ = 0;
  Pose last_finite_pose_;  // the last observed finite state's pose, its step and KE (J)
  int last_finite_step_ = -1;
  double last_finite_ke_ = 0.0;
  int max_unreached_ = 0;
  RunRules rules_;
  std::string prefix_;
  bool converged_ = false;
  bool diverged_ = false;
  std::string reason_;
  int first_step_ = 0;          // the state's step at the (re)start: counts are of this run
  int steps_run_ = 0;           // the state's step at the last observation
  int steps_to_converge_ = -1;  // the state's step
  int rest_run_ = 0;
  long total_passes_ = 0;
  int max_passes_ = 0;
  double peak_ke_ = 0.0;
  double max_separation_ = 0.0;
  double max_violation_deg_ = 0.0;
  double best_residual_ = std::numeric_limits<double>::infinity();  // IK use
  int last_improvement_ = 0;                                        // IK use: step
};

// The final-state fields of a summary: residuals to the goal targets, KE, pose and frames.
void fill_final_state(const Scene& scene, const SimState& state, RunSummary& out);

// What to try after the scene's run diverged, in one line: the robust preset where the scheme
// is explicit, less damping where it passes the explicit step's bound for translation
// (c dt / m < 1 at a bone's end, summed over both ends: 2 c dt / m < 2), a smaller dt otherwise;
// under the implicit scheme a smaller dt, and more implicit_max_splits only while the parameter's
// range has more (it never suggests a value past a parameter's range).
std::string divergence_hint(const Scene& scene);

// What the implicit step's energy guard could not hold in a run (implicit_advance.h), in one line
// for the user, or "": the steps split implicit_max_splits deep (taken unchecked there) and those
// kept where halving did not help (implicit_advance.h), and what to try (a smaller dt, and more
// implicit_max_splits only while its range has more).
std::string energy_guard_warning(const Scene& scene, const RunSummary& run);

// What to try after the scene's run ended short of convergence without diverging, in one line:
// more steps (twice this run's), more damping where it would take (a fixed damping above damping
// auto's last choice; under an explicit scheme only below the bound above), and the robust preset
// where the scheme is explicit.
std::string not_converged_hint(const Scene& scene, const RunSummary& run);

}  // namespace physik
