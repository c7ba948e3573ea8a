// What a run reports: per step (StepStats, given to a StepObserver after every step) and for the
// whole run (RunSummary, filled by the run monitor, physik/engine/run_monitor.h, and the final
// state). Written to files by physik/io/summary_io.h.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "physik/engine/state.h"

namespace physik {

struct StepStats {
  int passes = 0;               // joint passes this step (gauss-seidel; 1 for the exact solve)
  int substeps = 0;             // the implicit step's substeps (1 unless the energy guard split it)
  double mismatch = 0.0;        // largest joint-point acceleration difference left, rig units/s^2
  double kinetic_energy = 0.0;  // J, after the step
  bool energy_measured = false;   // the step measured kinetic_energy and U after the step itself
                                  // (the implicit step's energy guard)
  double potential_energy = 0.0;  // J, U after the step (potential.h), when energy_measured
  double max_residual = 0.0;      // rig units, the goal residual (measures.h): the largest
                                  // control-point distance to its goal, or turning target's arc
  double joint_separation = 0.0;  // rig units, largest parent-tail to child-head gap
  double joint_solve_s = 0.0;     // s, wall time of the inter-joint force solve (profiling)

  // The solver's count of the step, whatever the scheme: the joint passes, or the implicit step's
  // substeps (the trajectory table's `passes` column, the summary's passes per step).
  int iterations() const { return substeps > 0 ? substeps : passes; }
};

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
  double peak_kinetic_energy = 0.0;      // J
  double final_kinetic_energy = 0.0;     // J
  double max_limit_violation_deg = 0.0;  // over the run
  // the energy ledger (run_monitor.h): the energy given to the rig, E_0 + W at the last step (J),
  // and the largest E_k / (max(E_in,k, 0) + E_floor) seen (1)
  double energy_given = 0.0;
  double peak_energy_ratio = 0.0;
  // the joint solve (joint_forces.h): steps whose solve stopped before its forces reached every
  // joint (kUnreachedFraction), the most joints left unreached in one step, and a one-line
  // warning for the user when there were any ("" otherwise); the engine never prints it
  int joint_unpropagated_steps = 0;
  int max_unreached_joints = 0;
  std::string joint_solve_warning;
  double wall_time_s = 0.0;
  // the last state the run reached, or, when it went non-finite, the last finite one (its step in
  // final_pose_step, its KE in final_kinetic_energy, its residuals in final_residuals)
  int final_pose_step = 0;
  double damping_auto_value = 0.0;  // N s/m, damping_auto's last choice (params.damping_auto)
  int damping_auto_updates = 0;     // how often it was chosen (start + target changes)
  int implicit_split_steps = 0;     // scheme implicit: steps the energy guard split in
  int implicit_max_substeps = 0;    //   halves, and the most substeps of one (implicit_advance.h);
  int implicit_retaken_steps = 0;   //   (sub)steps retaken with the contacts they reached, kept
  int implicit_unresolved_steps = 0;    //   where halving did not help, and steps
  int implicit_deepest_steps = 0;       //   with substeps taken unchecked (depth or check cap)
  int implicit_gauss_newton_steps = 0;  // implicit_linearisation full: (sub)steps retaken as
                                        //   Gauss-Newton (implicit_step.h)
  Pose final_pose;
  BoneFrames final_frames;
};

// Called after every step with the state and that step's stats (for CSV output, progress).
using StepObserver = std::function<void(const SimState&, const StepStats&)>;

}  // namespace physik
