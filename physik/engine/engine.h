// The PhysIK engine: one step, and a whole run of a scene with convergence and divergence
// detection. The step reads like a table of contents (MuJoCo's mj_step, Box2D's solver stages):
// it moves the targets, then switches once on params.scheme (MuJoCo's switch on opt.integrator),
// and each scheme is a short list of stages:
//
//   update_targets        schedule + interpolation (eq. 12)                   interpolation.h
//   damping auto          chosen again when the targets change                 linear_modes.h
//   gauss-seidel          the paper's scheme:
//     apply_forces          bodies prepared (I^-1, w x I w), damping -c v at    forces.h
//                           head and tail, control springs, torsion springs
//     solve_joint_forces    Gauss-Seidel passes, corrected eq. 11              joint_forces.h
//     integrate_*           semi-implicit Euler, articulated or free rods      integrate.h
//   exact:
//     apply_forces          the same forces
//     solve_articulated     Featherstone's articulated-body algorithm integrate_joint_space.h
//     integrate_joint_space MuJoCo's Euler in joint space
//   implicit:
//     advance_implicit      apply_forces, solve_implicit (linearised backward   implicit_advance.h
//                           Euler), integrate_joint_space; a step that adds
//                           energy is taken again in halves
//
// Measures of a state (kinetic energy, residuals, separation, hash) are in measures.h.
#pragma once

#include "physik/engine/measures.h"
#include "physik/engine/run_summary.h"
#include "physik/engine/state.h"

namespace physik {

// The scene's initial state: every buffer sized (size_state), the initial pose and velocity, and
// the initial targets, which count as a jump from where each attachment point starts.
void init_state(const Scene& scene, SimState& state);

// Put a pose in (frames, centres of mass, the pose, and the joint-space state the exact and
// implicit schemes integrate), every bone moving with `velocity_world` (rig units/s) and not
// turning; the targets are untouched. init_state and the posing session put poses with it.
void set_pose(const Scene& scene, SimState& state, const Pose& pose,
              const Vec3& velocity_world = Vec3::Zero());

// One step of params.dt.
StepStats step(const Scene& scene, SimState& state);
// One step of length h (s), scheme implicit only (the explicit schemes' angular-velocity factor is
// per step of params.dt): its damping, the factor's damper (1 - f) / params.dt I and every spring
// are the scene's; only the step is longer or shorter. The solve mode (physik/posing) lengthens
// it as the motion settles. InputError when the scheme is not implicit, or h is not positive and
// finite.
StepStats step(const Scene& scene, SimState& state, double h);

// Run the scene from its initial pose for scene.steps steps (or until converged when the scene
// says so). Never throws on divergence: it is reported in the summary. The convergence and
// divergence rules are RunMonitor's (run_monitor.h), shared with the MuJoCo reference. The
// observer sees every step's state; with observe_initial also the initial state first (step 0,
// initial_stats).
RunSummary run_scene(const Scene& scene, const StepObserver& observer = nullptr,
                     bool observe_initial = false);

}  // namespace physik
