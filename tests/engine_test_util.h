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

// The tuning study's scaled scene (experiments/common.cpp scaled_scene): positions, radii, targets
// and caps times s, masses density x length (kg per rig unit), inertias recomputed.
inline Scene scaled_scene(const Scene& base, double s, double density) {
  Json doc = rig_to_json(base.rig);
  for (Json& b : doc["bones"]) {
    for (const char* key : {"head", "tail"}) {
      for (auto& v : b[key]) v = v.get<double>() * s;
    }
    const Vec3 head(b["head"][0], b["head"][1], b["head"][2]);
    const Vec3 tail(b["tail"][0], b["tail"][1], b["tail"][2]);
    b["radius"] = b["radius"].get<double>() * s;
    b["mass"] = density * (tail - head).norm();
    b.erase("inertia_local");
  }
  Scene out = base;
  out.rig = rig_from_json(doc, base.rig_file + " (scaled)");
  for (ControlPoint& cp : out.control_points) {
    cp.target_world *= s;
    if (cp.cap) *cp.cap *= s;
  }
  out.params.control_cap *= s;
  for (TargetChange& t : out.schedule) t.target_world *= s;
  out.initial_pose.root_head_world *= s;
  return out;
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
