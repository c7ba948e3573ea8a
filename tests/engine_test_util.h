// Scenes built in code for the engine tests.
#pragma once

#include "physik/io/rig_io.h"
#include "physik/model/scene.h"

namespace physik::test {

// A single free bone of length L along +Z with its head at the origin.
inline Rig one_rod(double length = 1.0, double mass = 1.0, double radius = 0.5) {
  BoneSpec b;
  b.name = "rod";
  b.head_world = Vec3(0, 0, 0);
  b.tail_world = Vec3(0, 0, length);
  b.rest_frame_world = rest_frame_from_roll(b.head_world, b.tail_world, 0.0);
  b.mass = mass;
  b.radius = radius;
  return build_rig({b}, "one_rod", "one_rod");
}

inline Scene scene_for(const Rig& rig, const EngineParams& params, int steps = 100) {
  Scene s;
  s.file = "<test>";
  s.rig = rig;
  s.params = params;
  s.steps = steps;
  s.initial_pose = rest_pose(rig);
  return s;
}

inline ControlPoint control(int bone, double alpha, const Vec3& target, double k,
                            SpringLaw law = SpringLaw::kLinear, double cap = 1.0) {
  ControlPoint c;
  c.bone = bone;
  c.alpha = alpha;
  c.target_world = target;
  c.k = k;
  c.spring = law;
  c.cap = cap;
  return c;
}

// Parameters with nothing but the dynamics: no damping, no velocity factor, no interpolation.
inline EngineParams bare_params(double dt = 0.05) {
  EngineParams p = preset_params("original");
  p.dt = dt;
  p.damping = 0.0;
  p.angular_velocity_factor = 1.0;
  p.interpolation = Interpolation::kNone;
  return p;
}

}  // namespace physik::test
