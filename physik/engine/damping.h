// Damping (paper Sec. 4: c = 20; original fwik.py: c = 3): a force -c v at the head and at the
// tail of every bone, v the velocity of that point:
//   v(p) = v_cm + w x (p - cm)
// c in N s/m. The per-step angular-velocity factor f (0.5 in the original) is the damping's too:
// the explicit schemes apply it in their integrators (integrate.h) or as the torque
// I (f - 1) w / dt (articulated_body.h, the MuJoCo reference), not here.
// No potential: a damper only removes energy.
// Implicit step (implicit_step.h): each end damper a point element h c 1 at its point, and the
// factor a rotational damper h (1 - f) / dt I_com on the body's angular block; no -h K v term.
// Damping auto (linear_modes.h) chooses c: the end dampers' unit matrix D1 and the factor's Dr
// are its own terms there (mode_operators.h, linear_modes_dense.h), not a stiffness.
#pragma once

#include "physik/engine/force_stages.h"
#include "physik/engine/state.h"
#include "physik/model/params.h"
#include "physik/model/rig.h"
#include "physik/model/scene.h"

namespace physik {

// The damping a step uses (N s/m): params.damping, or the auto value (damping_auto,
// linear_modes.h) kept in the state.
inline double step_damping(const EngineParams& p, const SimState& s) {
  return p.damping_auto ? s.damping_auto_value : p.damping;
}

void apply_damping(const Rig& rig, const EngineParams& params, SimState& state);

// The implicit step's h D of the end dampers and of the factor, into every body's articulated
// inertia and bias force (augment).
void damping_augment(const Scene& scene, const ImplicitStage& stage, SimState& state);

}  // namespace physik
