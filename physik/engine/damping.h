// Damping (paper Sec. 4: c = 20; original fwik.py: c = 3): a force -c v at the head and at the
// tail of every bone, v the velocity of that point:
//   v(p) = v_cm + w x (p - cm)
// c in N s/m. The per-step angular-velocity factor (0.5 in the original) is applied by the
// integrator (integrate.h), not here.
#pragma once

#include "physik/engine/state.h"
#include "physik/model/params.h"
#include "physik/model/rig.h"

namespace physik {

// The damping a step uses (N s/m): params.damping, or the auto value (damping_auto,
// linear_modes.h) kept in the state.
inline double step_damping(const EngineParams& p, const SimState& s) {
  return p.damping_auto ? s.damping_auto_value : p.damping;
}

void apply_damping(const Rig& rig, const EngineParams& params, SimState& state);

}  // namespace physik
