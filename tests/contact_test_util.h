// Rigs and scenes built in code for the contact tests (collision_test, contacts_test).
#pragma once

#include <string>

#include "physik/model/scene.h"
#include "tests/engine_test_util.h"

namespace physik::test {

inline BoneSpec bone(const std::string& name, const std::string& parent, const Vec3& head,
                     const Vec3& tail, double collision_radius = 0.0) {
  BoneSpec b;
  b.name = name;
  b.parent = parent;
  b.head_world = head;
  b.tail_world = tail;
  b.rest_frame_world = rest_frame_from_roll(head, tail, 0.0);
  b.mass = (tail - head).norm();  // 1 kg per rig unit
  b.radius = 0.5;
  b.collision_radius = collision_radius;
  return b;
}

// a 1 m, 1 kg rod along +x at height z (default collision radius 0.06)
inline Rig lying_rod(double z) {
  return build_rig({bone("rod", "", Vec3(0, 0, z), Vec3(1, 0, z))}, "rod", "rod");
}

// bone0 up the z axis, bone1 across to x = gap, bone2 back down: 0 and 2 share no joint
inline Rig u_rig(double gap, double bottom, double radius) {
  return build_rig({bone("post", "", Vec3(0, 0, bottom), Vec3(0, 0, 1), radius),
                    bone("bar", "post", Vec3(0, 0, 1), Vec3(gap, 0, 1), radius),
                    bone("leg", "bar", Vec3(gap, 0, 1), Vec3(gap, 0, 0), radius)},
                   "u", "u");
}

inline Scene floor_scene(const Rig& rig, Scheme scheme, double dt) {
  EngineParams p = preset_params("robust");
  p.scheme = scheme;
  p.dt = dt;
  p.damping_auto = false;
  p.damping = 0.0;
  Scene s = scene_for(rig, p, 1);
  s.gravity_world = Vec3(0, 0, -9.81);
  s.collision.ground = GroundPlane{};
  return s;
}

}  // namespace physik::test
