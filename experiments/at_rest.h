// A rig at rest, with no targets and no gravity: how much it moves by itself (the outside_rigs
// experiment's rest check, and the tests of converted and shipped rigs). Uses the core alone, so
// the core's tests include it too.
#pragma once

#include "physik/engine/engine.h"
#include "physik/engine/measures.h"
#include "physik/engine/state.h"
#include "physik/model/params.h"
#include "physik/model/scene.h"

namespace physik::experiments {

enum class RestScheme { kGaussSeidel, kExact, kImplicit };

inline const char* to_string(RestScheme s) {
  return s == RestScheme::kGaussSeidel ? "gauss-seidel"
                                       : (s == RestScheme::kExact ? "exact" : "implicit");
}

// The parameters a user meets: the paper's scheme as the `original` preset runs it, the same
// with the exact step, and the default (`robust`: implicit, damping auto).
inline EngineParams rest_params(RestScheme s) {
  if (s == RestScheme::kImplicit) return preset_params("robust");
  EngineParams p = preset_params("original");
  if (s == RestScheme::kExact) p.scheme = Scheme::kExact;
  return p;
}

// The largest kinetic energy (J) over `steps` steps of the rig started at rest, no control
// points, no gravity, with or without self-collision.
inline double rest_kinetic_energy(const Rig& rig, RestScheme scheme, bool self_collision,
                                  int steps = 100) {
  Scene s;
  s.file = "<rest>";
  s.rig = rig;
  s.params = rest_params(scheme);
  s.steps = steps;
  s.initial_pose = rest_pose(rig);
  s.collision.self_collision = self_collision;
  SimState state;
  init_state(s, state);
  double most = kinetic_energy(s.rig, state);
  for (int k = 0; k < steps; ++k) {
    step(s, state);
    most = std::max(most, kinetic_energy(s.rig, state));
  }
  return most;
}

}  // namespace physik::experiments
