// The PhysIK engine: one step, and a whole run of a scene with convergence and divergence
// detection. The step reads like a table of contents (MuJoCo's mj_step, Box2D's solver stages):
//
//   update_targets        schedule + interpolation                          interpolation.h
//   apply_forces          every force of the step, shared with the MuJoCo    forces.h
//                         reference: bodies prepared (I^-1, w x I w), damping -c v at head and
//                         tail, control springs, torsion springs +-tau
//   solve_joint_forces    Gauss-Seidel, corrected eq. 11                     joint_forces.h
//   integrate             semi-implicit Euler, articulated or free rods      integrate.h
// With joint_solve exact the last two are solve_articulated (Featherstone's articulated-body
// algorithm) and integrate_joint_space (MuJoCo's Euler in joint space), integrate_joint_space.h;
// with integration implicit, the last three are advance_implicit (implicit_advance.h):
// apply_forces, solve_implicit (linearised backward Euler, implicit_step.h) and
// integrate_joint_space, the step taken again in halves where it adds energy.
#pragma once

#include <cstdint>

#include "physik/engine/run_summary.h"
#include "physik/engine/state.h"

namespace physik {

// The scene's initial state: every buffer sized (size_state), the initial pose and velocity, and
// the initial targets, which count as a jump from where each attachment point starts.
void init_state(const Scene& scene, SimState& state);

StepStats step(const Scene& scene, SimState& state);
// One step of length h (s) of the scene's equations of motion, integration implicit only (the
// explicit schemes' angular-velocity factor is per step of params.dt): its damping, the factor's
// damper (1 - f) / params.dt I and every spring are the scene's; only the step is longer or
// shorter. The solve mode (physik/posing) lengthens it as the motion settles. InputError when
// the integration is not implicit, or h is not positive and finite.
StepStats step(const Scene& scene, SimState& state, double h);

// Diagnostics over a state.
double kinetic_energy(const Rig& rig, const SimState& state);
double max_joint_separation(const Rig& rig, const BoneFrames& frames);
// Distance of every control point's attachment to its goal target (not the interpolated one).
void control_residuals(const Scene& scene, const SimState& state, std::vector<double>& out);

// The stats of a state no step has produced yet (the initial one): its kinetic energy, residuals
// and joint separation; no passes, no mismatch.
StepStats initial_stats(const Scene& scene, const SimState& state);

// Run the scene from its initial pose for scene.steps steps (or until converged when the scene
// says so). Never throws on divergence: it is reported in the summary. The convergence and
// divergence rules are RunMonitor's (run_monitor.h), shared with the MuJoCo reference. The
// observer sees every step's state; with observe_initial also the initial state first (step 0,
// initial_stats).
RunSummary run_scene(const Scene& scene, const StepObserver& observer = nullptr,
                     bool observe_initial = false);

// FNV-1a over the bit patterns of every final head, tail and orientation: equal hashes mean
// bit-identical runs (determinism made visible, as Jolt prints a state hash).
std::uint64_t state_hash(const BoneFrames& frames);

}  // namespace physik
