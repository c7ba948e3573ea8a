// The PhysIK engine: one step, and a whole run of a scene with convergence and divergence
// detection. The step reads like a table of contents (MuJoCo's mj_step, Box2D's solver stages):
//
//   update_targets        schedule + interpolation           interpolation.h
//   prepare_bodies        forces cleared, I^-1, w x I w       newton_euler.h
//   apply_damping         -c v at head and tail               damping.h
//   apply_control_springs linear / capped springs             control_springs.h
//   apply_torsion_springs joint-limit springs, +-tau           torsion_springs.h
//   solve_joint_forces    Gauss-Seidel, corrected eq. 11      joint_forces.h
//   integrate             semi-implicit Euler, articulated or free rods   integrate.h
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "physik/state.h"

namespace physik {

struct StepStats {
  int passes = 0;            // joint passes used this step
  double mismatch = 0.0;     // largest joint-point acceleration difference left, rig units/s^2
  double kinetic_energy = 0.0;  // J, after the step
  double max_residual = 0.0;    // rig units, largest control-point distance to its goal target
  double joint_separation = 0.0;  // rig units, largest parent-tail to child-head gap
  double joint_solve_s = 0.0;     // s, wall time of the inter-joint force solve (profiling)
};

StepStats step(const Scene& scene, SimState& state);

// Diagnostics over a state.
double kinetic_energy(const Rig& rig, const SimState& state);
double max_joint_separation(const Rig& rig, const BoneFrames& frames);
// Distance of every control point's attachment to its goal target (not the interpolated one).
void control_residuals(const Scene& scene, const SimState& state, std::vector<double>& out);

struct RunSummary {
  bool converged = false;
  bool diverged = false;
  std::string divergence_reason;
  int steps_run = 0;
  int steps_to_converge = -1;           // first step of the settled window; -1 if never
  std::vector<double> final_residuals;  // rig units, one per control point
  double max_joint_separation = 0.0;    // rig units over the run
  double mean_passes_per_step = 0.0;
  int max_passes_in_a_step = 0;
  double peak_kinetic_energy = 0.0;     // J
  double final_kinetic_energy = 0.0;    // J
  double max_limit_violation_deg = 0.0; // over the run
  double wall_time_s = 0.0;
  Pose final_pose;
  BoneFrames final_frames;
};

// Called after every step with the state and that step's stats (for CSV output, progress).
using StepObserver = std::function<void(const SimState&, const StepStats&)>;

// Run the scene from its initial pose for scene.steps steps (or until converged when the scene
// says so). Never throws on divergence: it is reported in the summary. The convergence and
// divergence rules are RunMonitor's (run_monitor.h), shared with the MuJoCo reference.
RunSummary run_scene(const Scene& scene, const StepObserver& observer = nullptr);

nlohmann::json summary_to_json(const Scene& scene, const RunSummary& s);

// FNV-1a over the bit patterns of every final head, tail and orientation: equal hashes mean
// bit-identical runs (determinism made visible, as Jolt prints a state hash).
std::uint64_t state_hash(const BoneFrames& frames);

}  // namespace physik
