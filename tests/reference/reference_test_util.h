// Scenes built in code for the MuJoCo reference tests.
#pragma once

#include "physik/rig_io.h"
#include "physik/scene.h"

namespace physik::test {

inline std::string shipped(const std::string& rel) {
  return std::string(PHYSIK_SOURCE_DIR) + "/models/" + rel;
}

// A straight chain of free bones along +Z (each of length `length`), optionally limited.
inline Rig straight_chain(int nbone, double length = 1.0) { return make_chain_rig(nbone, length); }

inline Scene scene_on(const Rig& rig, const EngineParams& params, int steps) {
  Scene s;
  s.file = "<test>";
  s.rig = rig;
  s.params = params;
  s.steps = steps;
  s.initial_pose = rest_pose(rig);
  return s;
}

inline ControlPoint pull(int bone, double alpha, const Vec3& target, double k,
                         SpringLaw law = SpringLaw::kLinear) {
  ControlPoint c;
  c.bone = bone;
  c.alpha = alpha;
  c.target_world = target;
  c.k = k;
  c.spring = law;
  return c;
}

}  // namespace physik::test
