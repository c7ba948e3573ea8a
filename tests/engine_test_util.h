// Scenes built in code for the engine tests.
#pragma once

#include <string>
#include <vector>

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

// A small figure with welds (rig.h "Welds"), Z up: a pelvis root, and at its tail one source
// joint's three segments, spine (its ball, limited) with hip.L and hip.R welded to it as
// siblings; chest welded to spine (its parent); legs and an arm that turn. 10 bones, 3 welded.
inline Rig welded_figure(RootJoint root = RootJoint::kFree) {
  std::vector<BoneSpec> bones;
  const auto add = [&](const std::string& name, const std::string& parent, const Vec3& head,
                       const Vec3& tail, const std::string& weld = "") {
    BoneSpec b;
    b.name = name;
    b.parent = parent;
    b.head_world = head;
    b.tail_world = tail;
    b.rest_frame_world = rest_frame_from_roll(head, tail, 0.0);
    b.mass = 10.0 * (tail - head).norm();  // heavy and wide enough for the explicit schemes'
    b.radius = 0.3;                        // damping bound with the original's damping
    b.weld = weld;
    bones.push_back(b);
    return &bones.back();
  };
  add("pelvis", "", Vec3(0, 0, 0.9), Vec3(0, 0, 1.0));
  add("spine", "pelvis", Vec3(0, 0, 1.0), Vec3(0, 0.02, 1.4))->limit = {
      AxisLimit{true, -0.5, 0.5}, AxisLimit{true, -0.3, 0.3}, AxisLimit{true, -0.4, 0.4}};
  add("hip.L", "pelvis", Vec3(0, 0, 1.0), Vec3(0.15, 0, 0.95), "spine");
  add("hip.R", "pelvis", Vec3(0, 0, 1.0), Vec3(-0.15, 0, 0.95), "spine");
  add("chest", "spine", Vec3(0, 0.02, 1.4), Vec3(0, 0.02, 1.6), "spine");
  add("arm.L", "chest", Vec3(0, 0.02, 1.6), Vec3(0.35, 0.02, 1.55));
  for (const char* side : {"L", "R"}) {
    const double x = side[0] == 'L' ? 0.15 : -0.15;
    const std::string s(side);
    add("thigh." + s, "hip." + s, Vec3(x, 0, 0.95), Vec3(x, 0.01, 0.5));
    add("shin." + s, "thigh." + s, Vec3(x, 0.01, 0.5), Vec3(x, 0, 0.1))->limit[0] =
        AxisLimit{true, -2.0, 0.3};
  }
  if (root == RootJoint::kPinned) {  // a hinge to the world about the pelvis's local x
    bones[0].limit = {AxisLimit{true, -1.0, 1.0}, AxisLimit{true, 0.0, 0.0},
                      AxisLimit{true, 0.0, 0.0}};
  }
  return build_rig(bones, "welded_figure", "welded_figure", root);
}

// A human-like figure whose joints lock axes (rig.h "Locked axes"), Z up, facing -Y, .L at +X:
// a pelvis (the root), a spine (a ball with ranges), a head, and per side an upper arm and a
// thigh (balls), an elbow and a knee (hinges about x, y and z locked at 0), a wrist and an ankle
// (universal joints: x then z, the twist about the bone's y locked; the left wrist's at 0.2 rad,
// off zero), a collarbone locked on every axis at (0.1, 0, -0.15) rad and a hip at zero (welds
// by locks). 19 bones. With `root` pinned the pelvis is a hinge to the world about its local x.
inline Rig hinged_figure(RootJoint root = RootJoint::kFree) {
  std::vector<BoneSpec> bones;
  const auto add = [&](const std::string& name, const std::string& parent, const Vec3& head,
                       const Vec3& tail) -> BoneSpec& {
    BoneSpec b;
    b.name = name;
    b.parent = parent;
    b.head_world = head;
    b.tail_world = tail;
    b.rest_frame_world = rest_frame_from_roll(head, tail, 0.0);
    b.mass = 8.0 * (tail - head).norm();
    b.radius = 0.06;
    bones.push_back(b);
    return bones.back();
  };
  const AxisLimit zero{true, 0.0, 0.0};
  add("pelvis", "", Vec3(0, 0, 1.0), Vec3(0, 0, 1.1));
  add("spine", "pelvis", Vec3(0, 0, 1.1), Vec3(0, 0.01, 1.5)).limit = {
      AxisLimit{true, -0.4, 0.6}, AxisLimit{true, -0.3, 0.3}, AxisLimit{true, -0.3, 0.3}};
  add("head", "spine", Vec3(0, 0.01, 1.5), Vec3(0, 0.0, 1.75));
  for (const char* side : {"L", "R"}) {
    const std::string s(side);
    const double x = s == "L" ? 1.0 : -1.0;
    add("collar." + s, "spine", Vec3(0, 0.01, 1.5), Vec3(0.18 * x, 0.02, 1.45)).limit = {
        AxisLimit{true, 0.1, 0.1}, zero, AxisLimit{true, -0.15, -0.15}};
    add("upper_arm." + s, "collar." + s, Vec3(0.18 * x, 0.02, 1.45), Vec3(0.45 * x, 0.02, 1.4));
    add("forearm." + s, "upper_arm." + s, Vec3(0.45 * x, 0.02, 1.4), Vec3(0.7 * x, -0.03, 1.38))
        .limit = {AxisLimit{true, -0.1, 2.4}, zero, zero};
    add("hand." + s, "forearm." + s, Vec3(0.7 * x, -0.03, 1.38), Vec3(0.82 * x, -0.05, 1.37))
        .limit = {AxisLimit{true, -1.0, 1.2}, s == "L" ? AxisLimit{true, 0.2, 0.2} : zero,
                  AxisLimit{true, -0.3, 0.5}};
    add("hip." + s, "pelvis", Vec3(0, 0, 1.1), Vec3(0.1 * x, 0, 1.0)).limit = {zero, zero, zero};
    add("thigh." + s, "hip." + s, Vec3(0.1 * x, 0, 1.0), Vec3(0.1 * x, 0.01, 0.55));
    add("shin." + s, "thigh." + s, Vec3(0.1 * x, 0.01, 0.55), Vec3(0.1 * x, 0.03, 0.1)).limit = {
        AxisLimit{true, -2.4, 0.05}, zero, zero};
    add("foot." + s, "shin." + s, Vec3(0.1 * x, 0.03, 0.1), Vec3(0.1 * x, -0.12, 0.02)).limit = {
        AxisLimit{true, -0.6, 0.4}, zero, AxisLimit{true, -0.3, 0.3}};
  }
  if (root == RootJoint::kPinned) bones[0].limit = {AxisLimit{true, -1.0, 1.0}, zero, zero};
  return build_rig(bones, "hinged_figure", "hinged_figure", root);
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

// The rig's joint model before hinges, for the tests whose case is a behaviour of torsion springs
// on locked axes (the 0.1x pinhead whose bare implicit step gains energy; feet that reach a floor;
// a long step's Newton convergence): every locked axis's range [m, m] becomes [m - 1e-12,
// m + 1e-12] rad, so that no joint has an axis removed and the exact and implicit schemes hold
// each lock with its torsion spring. The spring is the lock's to 1e-12 rad: slack at m (a lock's
// excess is 0 there too, and so its tangent), pulling toward m beyond the dead zone's 2e-12.
inline Rig with_spring_locks(Rig rig) {
  for (auto& limits : rig.bone_limit)
    for (AxisLimit& a : limits)
      if (a.locked()) {
        a.min -= 1e-12;
        a.max += 1e-12;
      }
  refresh_joint_model(rig);
  return rig;
}

}  // namespace physik::test
