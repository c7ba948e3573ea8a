#include "physik/engine/aim_springs.h"

#include <cmath>

#include "physik/engine/control_springs.h"
#include "physik/engine/implicit_elements.h"
#include "physik/engine/newton_euler.h"

namespace physik {

AimTurn aim_turn(const BoneFrames& f, const AimTarget& t) {
  AimTurn out;
  out.axis_world = f.orient_world[t.bone] * t.axis_bone;
  const Vec3 to = t.point_world - f.head_world[t.bone];
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
  return {aim_turn(s.frames, t), t.spring_in(scene.params), t.k_in(scene.params, scene.rig),
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

// U's Hessian in the bone's turn dr and its head's move da (world axes), the aim's tangent:
//   K_rr = -k (phi [d]x [u]x + phi' m m^T)
//   K_ra = (k / L) (phi [u]x P + phi' m a^T)            (K_ar = K_ra^T)
//   K_aa = (k / L^2) (phi (c P + d a^T + a d^T) - phi' a a^T)
// with c = u.d, s = sin(theta), m = u x d, a = u - c d, P = 1 - d d^T, phi = theta / s and
// phi' = dphi/dc = (theta c - s) / s^3 (-1/3 - 2 theta^2 / 15 near 0), from U = k theta^2 / 2,
// the gradient (-k phi m, k phi a / L) and du = dr x u, dd = -P da / L, dL = -d.da. At theta = 0
// the diagonal blocks are the step stiffness's below; K_ra = (k / L) [u]x is their coupling.
struct AimTangent {
  Mat3 turn, cross, head;  // K_rr (N m/rad), K_ra (N/rad), K_aa (N/m)
};

// The tangent serves the pose terms' Newton step (implicit_linearisation full) where it exists:
// the linear law or within the cap, the point off the head, and u not (nearly) opposite d, where
// phi grows without bound
bool has_tangent(const Aim& a, bool full) {
  const double theta = a.at.turn.norm();
  return full && a.at.distance > 0.0 && (a.law == SpringLaw::kLinear || theta <= a.cap) &&
         a.at.axis_world.dot(a.at.direction_world) > -0.999;
}

AimTangent aim_tangent(const Aim& a) {
  const Vec3& u = a.at.axis_world;
  const Vec3& d = a.at.direction_world;
  const double L = a.at.distance, theta = a.at.turn.norm();
  const double c = u.dot(d);
  const Vec3 m = u.cross(d), across = u - c * d;
  const double s = m.norm();
  const double phi = theta < 1e-8 ? 1.0 : theta / s;
  const double dphi =
      theta < 1e-3 ? -1.0 / 3.0 - 2.0 * theta * theta / 15.0 : (theta * c - s) / (s * s * s);
  const Mat3 P = Mat3::Identity() - d * d.transpose();
  const double k = a.k;
  AimTangent t;
  t.turn = -k * (phi * skew(d) * skew(u) + dphi * m * m.transpose());
  t.cross = (k / L) * (phi * skew(u) * P + dphi * m * across.transpose());
  t.head = (k / (L * L)) * (phi * (c * P + d * across.transpose() + across * d.transpose()) -
                            dphi * across * across.transpose());
  return t;
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
    const Vec3& w = s.omega_world[t.bone];
    const Vec3& head = s.frames.head_world[t.bone];
    const Vec3 v = point_velocity(s, t.bone, head);
    if (has_tangent(a, stage.full)) {
      const AimTangent K = aim_tangent(a);
      s.torque_world[t.bone] -= stage.h * (K.turn * w + K.cross * v);
      apply_force_at(s, t.bone, -stage.h * (K.cross.transpose() * w + K.head * v), head);
      continue;
    }
    s.torque_world[t.bone] -= stage.h * (couple_stiffness(a) * w);
    apply_force_at(s, t.bone, -stage.h * (head_stiffness(a) * v), head);
  }
}

void aim_springs_augment(const Scene& scene, const ImplicitStage& stage, SimState& s) {
  ArticulatedBodyData& d = s.joint_space.articulated;
  const double h2 = stage.h * stage.h;
  for (const AimTarget& t : scene.aim_targets) {
    const Aim a = aim_of(scene, s, t);
    const int b = t.bone;
    const Vec3 r = s.frames.head_world[b] - d.point_world[b];
    const Vec6& a0 = s.implicit.accel_bias[b];
    if (has_tangent(a, stage.full)) {
      const AimTangent K = aim_tangent(a);
      add_couple_element(h2 * K.turn, a0, d.inertia_art[b], d.bias_force[b]);
      add_point_element(h2 * K.head, r, a0, d.inertia_art[b], d.bias_force[b]);
      add_couple_point_element(h2 * K.cross, r, a0, d.inertia_art[b], d.bias_force[b]);
      continue;
    }
    add_couple_element(h2 * couple_stiffness(a), a0, d.inertia_art[b], d.bias_force[b]);
    add_point_element(h2 * head_stiffness(a), r, a0, d.inertia_art[b], d.bias_force[b]);
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

void aim_springs_pose_forces(const Scene& scene, const SimState& s, PoseForces& out) {
  for (const AimTarget& t : scene.aim_targets) {
    const Aim a = aim_of(scene, s, t);
    const Vec3 tau = spring_force(a.law, a.k, a.cap, a.at.turn);
    out.couple(t.bone, tau);
    out.point(t.bone, s.frames.head_world[t.bone], head_force(a, tau));
  }
}

}  // namespace physik
