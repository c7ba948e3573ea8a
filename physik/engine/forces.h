// Every force of PhysIK, listed once. Each force is an element in its own file that owns its law,
// its potential and its implicit terms (as Box2D keeps each joint type's stages in its own file,
// and MuJoCo pairs mj_passive with mjd_passive_vel); every caller walks this list:
//   the force stage        apply_forces (every scheme; the MuJoCo reference, by its side below)
//   the potential          potential_energy (potential.h): the run monitor's ledger, the
//                          implicit step's energy guard, the exact equilibrium's report
//   the implicit step      the elements' -h K v (rate) and h D + h^2 K (augment): implicit_step.h
//   damping auto's modes   the elements' stiffness K (mode_stiffness): linear_modes.h, dense and
//                          O(n)
//   the pose terms         the elements' forces at rest, held while the pose moves (pose_forces):
//                          implicit_pose_terms.h, under implicit_linearisation full
// A force that leaves a stage out has a null entry there, and its header says why.
//
// The list and what each element supplies: forces.cpp, one row each.
//
// Adding a force: one file with its stage functions and its row in the list (forces.cpp), then
// the docs (docs/DESIGN.md "Adding things").
// Result of the force stage: state.force_world (N, at the centre of mass) and state.torque_world
// (N m, about it), world axes, per bone. The inter-joint forces are not among them: they are the
// joint solve's.
#pragma once

#include <vector>

#include "physik/engine/force_stages.h"
#include "physik/engine/state.h"
#include "physik/model/scene.h"

namespace physik {

struct ForceElement {
  const char* name;
  void (*apply)(const Scene&, SimState&, const ForceStage&);
  double (*potential)(const Scene&, const SimState&);              // J; null: none
  void (*rate)(const Scene&, const ImplicitStage&, SimState&);     // null: none
  void (*augment)(const Scene&, const ImplicitStage&, SimState&);  // null: none
  void (*mode_stiffness)(const Scene&, const SimState&, const std::vector<Vec3>& targets,
                         ModeStiffness&);                           // null: none
  void (*pose_forces)(const Scene&, const SimState&, PoseForces&);  // null: no pose terms
  MujocoSide mujoco;
  bool toward_targets;  // a spring toward targets that move during a run (the control points'
                        // schedule): the run monitor's ledger leaves its potential out and counts
                        // the targets' work instead (potential.h)
  bool rate_first;      // implicit_rates takes this element's rate before the others' (forces.cpp)
};

// The list, in the order every stage walks it (implicit_rates alone takes the rows marked
// rate_first first: forces.cpp says why); a fixed array, so walking it allocates nothing, the
// first walk included.
struct ForceList {
  const ForceElement* first;
  const ForceElement* last;  // one past the end
  const ForceElement* begin() const { return first; }
  const ForceElement* end() const { return last; }
  int size() const { return static_cast<int>(last - first); }
};
ForceList force_elements();

// The force stage: the bodies' accumulators cleared (prepare_bodies), the contacts at the state
// detected (contact_data.h) when the scene has any, then every element's force that `stage` is for.
void apply_forces(const Scene& scene, SimState& state, const ForceStage& stage = {});

// The pose-terms step's forces of every element (implicit_pose_terms.h), into `out`, in the
// list's order.
void pose_forces(const Scene& scene, const SimState& state, PoseForces& out);

// The implicit step's terms of every element: -h K v into the state's forces (before the
// recursion's velocity pass), h D + h^2 K into its augmented inertias and joint blocks (after).
void implicit_rates(const Scene& scene, const ImplicitStage& stage, SimState& state);
void implicit_augment(const Scene& scene, const ImplicitStage& stage, SimState& state);

// The stiffness of every element at the state's pose, its control springs pulling toward
// `targets` (one per control point), into `out` (cleared first; no allocation once it has room).
void mode_stiffness(const Scene& scene, const SimState& state, const std::vector<Vec3>& targets,
                    ModeStiffness& out);

}  // namespace physik
