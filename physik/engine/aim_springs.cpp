#include "physik/engine/aim_springs.h"

#include <cmath>

#include "physik/engine/control_springs.h"
#include "physik/engine/implicit_elements.h"
#include "physik/engine/newton_euler.h"

namespace physik {

AimTurn aim_turn(const SimState& s, const AimTarget& t) {
  AimTurn out;
  out.axis_world = s.frames.orient_world[t.bone] * t.axis_bone;
  const Vec3 to = t.point_world - s.frames.head_world[t.bone];
  out.distance = to.norm();
  if (!(out.distance > 0.0)) return out;  // the head on the point: no direction, no pull
  out.direction_world = to / out.distance;
  const Vec3& u = out.axis_world;
  const Vec3& d = out.direction_world;
  const Vec3 cross = u.cross(d);
  const double sin = cross.norm();
  const double theta = std::atan2(sin, u.dot(d));
  if (sin > 1e-12) {
    out.turn = (theta / sin) * cross;
  } else if (u.dot(d) < 0.0) {  // opposite: any axis across u
    Vec3 across = u.cross(Vec3::UnitX());
    if (across.norm() < 0.5) across = u.cross(Vec3::UnitY());
    out.turn = theta * across.normalized();
  }
  return out;
}

namespace {

struct Aim {
  AimTurn at;
  SpringLaw law;
  double k, cap;
};

Aim aim_of(const Scene& scene, const SimState& s, const AimTarget& t) {
  return {aim_turn(s, t), t.spring_in(scene.params), t.k_in(scene.params, scene.rig),
          t.cap_in(scene.params, scene.rig)};
}

// the head's force: -(|tau| / L) w, w the unit vector across d toward u
Vec3 head_force(const Aim& a, const Vec3& tau) {
  const Vec3& u = a.at.axis_world;
  const Vec3& d = a.at.direction_world;
  const Vec3 across = u - u.dot(d) * d;
  const double len = across.norm();
  if (len < 1e-12 || a.at.distance <= 0.0) return Vec3::Zero();
  return -(tau.norm() / a.at.distance) * (across / len);
}

// the step stiffness's scale on the turn: k, or the secant k c / theta beyond the cap
double step_scale(const Aim& a) {
  const double theta = a.at.turn.norm();
  if (a.law == SpringLaw::kLinear || theta <= a.cap) return a.k;
  return a.k * a.cap / theta;
}

Mat3 couple_stiffness(const Aim& a) {
  const Vec3& u = a.at.axis_world;
  return step_scale(a) * (Mat3::Identity() - u * u.transpose());
}

Mat3 head_stiffness(const Aim& a) {
  if (a.at.distance <= 0.0) return Mat3::Zero();
  const Vec3& d = a.at.direction_world;
  return (step_scale(a) / (a.at.distance * a.at.distance)) * (Mat3::Identity() - d * d.transpose());
}

}  // namespace

void apply_aim_springs(const Scene& scene, SimState& s) {
  for (const AimTarget& t : scene.aim_targets) {
    const Aim a = aim_of(scene, s, t);
    const Vec3 tau = spring_force(a.law, a.k, a.cap, a.at.turn);
    s.torque_world[t.bone] += tau;
    apply_force_at(s, t.bone, head_force(a, tau), s.frames.head_world[t.bone]);
  }
}

double aim_springs_potential(const Scene& scene, const SimState& s) {
  double u = 0.0;
  for (const AimTarget& t : scene.aim_targets) {
    const Aim a = aim_of(scene, s, t);
    u += control_spring_potential(a.law, a.k, a.cap, a.at.turn.norm());
  }
  return u;
}

void aim_springs_rate(const Scene& scene, const ImplicitStage& stage, SimState& s) {
  for (const AimTarget& t : scene.aim_targets) {
    const Aim a = aim_of(scene, s, t);
    s.torque_world[t.bone] -= stage.h * (couple_stiffness(a) * s.omega_world[t.bone]);
    const Vec3& head = s.frames.head_world[t.bone];
    const Vec3 v = point_velocity(s, t.bone, head);
    apply_force_at(s, t.bone, -stage.h * (head_stiffness(a) * v), head);
  }
}

void aim_springs_augment(const Scene& scene, const ImplicitStage& stage, SimState& s) {
  ArticulatedBodyData& d = s.joint_space.articulated;
  const double h2 = stage.h * stage.h;
  for (const AimTarget& t : scene.aim_targets) {
    const Aim a = aim_of(scene, s, t);
    const int b = t.bone;
    add_couple_element(h2 * couple_stiffness(a), s.implicit.accel_bias[b], d.inertia_art[b],
                       d.bias_force[b]);
    add_point_element(h2 * head_stiffness(a), s.frames.head_world[b] - d.point_world[b],
                      s.implicit.accel_bias[b], d.inertia_art[b], d.bias_force[b]);
  }
}

void aim_springs_mode_stiffness(const Scene& scene, const SimState& s, const std::vector<Vec3>&,
                                ModeStiffness& out) {
  for (const AimTarget& t : scene.aim_targets) {
    const Aim a = aim_of(scene, s, t);
    out.couples.push_back({t.bone, couple_stiffness(a)});
    const Mat3 Ka = head_stiffness(a);
    if (!Ka.isZero(0.0)) out.points.push_back({t.bone, s.frames.head_world[t.bone], Ka});
  }
}

}  // namespace physik
