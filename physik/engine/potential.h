// The potential energy of a state, summed once over the force list (forces.h): every element's
// own (its file states its law), for the run monitor's energy ledger (run_monitor.h), the implicit
// step's energy guard (implicit_advance.h) and the exact equilibrium's report (tune/equilibrium.h,
// whose residuals are the springs' potentials' square roots). A state's contacts are detected at
// its frames once (state.contact.at_frames) for the contact elements. Energies in J.
#pragma once

#include "physik/engine/control_springs.h"
#include "physik/engine/state.h"
#include "physik/engine/torsion_springs.h"
#include "physik/model/scene.h"

namespace physik {

// Which elements' potentials: all, or all but the springs toward targets (forces.h
// toward_targets: the control springs, whose energy the run monitor's ledger counts as the
// targets' work instead: run_monitor.h; the bone targets hold still through a run, so their
// potential at the start is counted as the rig's, as the torsion springs' is).
enum class PotentialOf { kAll, kAllButTargetSprings };

// U of the state: its control springs toward their effective targets, its torsion springs,
// gravity and contacts (the elements the scene has). Allocates nothing once the state's contact
// data is prepared (contact_data.h).
double potential_energy(const Scene& scene, SimState& state, PotentialOf which = PotentialOf::kAll);

// A state of `pose` at rest whose control springs pull toward `targets_world` (one per control
// point), its contact data prepared: a pose's potential outside a run (the run monitor's start,
// the exact equilibrium's report: tune/equilibrium.h) is this state's potential_energy.
// Allocates: once per query, never in a step.
SimState state_at_pose(const Scene& scene, const Pose& pose,
                       const std::vector<Vec3>& targets_world);

// U of the scene's initial pose before a run (the run monitor's start, run_monitor.h): the same
// sum on state_at_pose, without the control springs, which init_state starts at rest (every
// target at its attachment point).
double initial_potential_energy(const Scene& scene);

}  // namespace physik
