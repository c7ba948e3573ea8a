// The columns several experiments' tables share: the same quantity under the same name, declared
// once here (table.h). A column only one table has is declared beside that table.
// Run measures follow the engine's run summary (physik/engine/run_monitor.h): "converged" is at
// rest for 10 steps, "diverged" a non-finite state or kinetic energy past the scene's bound.
#pragma once

#include "experiments/table.h"

namespace physik::experiments::columns {

inline const Column kScene = text("scene", "the scene, models/scenes/<scene>.json");
inline const Column kScheme =
    text("scheme", "the step: explicit (the paper's, as shipped) or implicit (scheme implicit)");
inline const Column kConverged = flag("converged", "the run came to rest (the run monitor's test)");
inline const Column kDiverged =
    flag("diverged", "the run diverged (non-finite state or kinetic energy past the bound)");
inline const Column kStepsToConverge =
    integer("steps_to_converge", "steps", "steps until the run converged (-1: not within the run)");
inline const Column kStepsRun = integer("steps_run", "steps", "steps the run took");
inline const Column kPeakKineticEnergy =
    real("peak_kinetic_energy", "J", "the largest kinetic energy over the run");
inline const Column kFinalKineticEnergy =
    real("final_kinetic_energy", "J", "the kinetic energy after the last step");
inline const Column kMaxFinalResidual = real(
    "max_final_residual", "rig units", "the largest control-point residual after the last step");
inline const Column kDamping = real("damping", "N s/m", "the damping coefficient c");
inline const Column kDt = real("dt", "s", "the time step");
inline const Column kTorsionK = real("torsion_k", "N m/rad", "the torsion springs' stiffness");
inline const Column kAngularVelocityFactor =
    real("angular_velocity_factor", "", "the angular-velocity factor f");
inline const Column kOutcome = text("outcome", "how the run ended: settled, diverged, or neither");
inline const Column kMaxLimitViolationDeg = real(
    "max_limit_violation_deg", "deg", "the largest excursion of a limited axis past its range");
inline const Column kStep = integer("step", "", "the step (1: the first)");

}  // namespace physik::experiments::columns
