// Newton-Euler dynamics of one rigid rod (paper eq. 1-5).
//
// Per bone i, with the origin at its centre of mass, world axes:
//   a_cm  = F / m                                            (eq. 1)
//   alpha = I^-1 (tau - w x I w)            I = R diag(I_local) R^T, world axes
// The acceleration of a point p = cm + r fixed on the bone (eq. 2, plus the centripetal term the
// paper and the original omit, optional):
//   a_r = a_cm + alpha x r  [+ w x (w x r)]
// An extra force G applied at p changes it affinely (eq. 3-5):
//   a_r(G) = a_r + M G,   M = m^-1 I3 + [r]x^T I^-1 [r]x     (N -> rig units/s^2)
// Units: N, N m, kg, kg m^2, rig units, s.
#pragma once

#include "physik/engine/state.h"
#include "physik/model/params.h"
#include "physik/model/rig.h"

namespace physik {

// Start of a step: clear the force/torque accumulators, refresh I^-1 (world) and w x I w (with
// the exact and implicit schemes only the clearing: nothing reads the other two).
void prepare_bodies(const Rig& rig, const EngineParams& params, SimState& state);

// With params.factor_in_joint_solve, the angular-velocity factor f as a torque on every bone,
// after the force stages and before the joint solve:
//   tau_i += I_i (f - 1) w_i / dt          (I_i the bone's own inertia about its centre, world)
// as the exact scheme and the MuJoCo reference apply it (articulated_body.h), so the joint forces
// carry it and the integration then takes f = 1 (integrate.h). On a rod alone it is the same
// w <- f w; on a chain it is no longer each body's w halved on its own, after the joint forces:
// a welded group's sum of its rods' torques, about its centre. (docs/engine.md "Welded bones and
// anchored roots" measures what that changes.)
void apply_factor_torque(const Rig& rig, const EngineParams& params, SimState& state);

// On a rig with welds (rig.h "Welds"), the scheme gauss-seidel's bodies after the force stages:
// per welded group (at its first bone's index) its mass, centre of mass, the net force, the
// torque about that centre (sum tau_i + (c_i - c) x F_i), the inverse of its world inertia
// (parallel axes: sum R_i I_i R_i^T + m_i (|r_i|^2 1 - r_i r_i^T)) and w x I w; a body of one bone
// copies the bone's. The joint solve and the integration move these bodies.
void prepare_welded_bodies(const Rig& rig, const EngineParams& params, SimState& state);

// Add a force applied at a world point to bone i (force, and torque about its centre of mass).
inline void apply_force_at(SimState& s, int bone, const Vec3& force_world,
                           const Vec3& point_world) {
  s.force_world[bone] += force_world;
  s.torque_world[bone] += (point_world - s.com_world[bone]).cross(force_world);
}

// The velocity of bone i's material point at p, world (rig units/s): v_cm + w x (p - cm).
inline Vec3 point_velocity(const SimState& s, int bone, const Vec3& point_world) {
  return s.vel_world[bone] + s.omega_world[bone].cross(point_world - s.com_world[bone]);
}

inline Vec3 linear_accel(const Rig& rig, const SimState& s, int bone) {
  return s.force_world[bone] / rig.bone_mass[bone];
}

inline Vec3 angular_accel(const SimState& s, int bone) {
  return s.inertia_inv_world[bone] * (s.torque_world[bone] - s.gyro_world[bone]);
}

// Acceleration of the bone-fixed point at offset r from the centre of mass (eq. 2).
inline Vec3 point_accel(const Rig& rig, const SimState& s, int bone, const Vec3& r_world,
                        bool centripetal) {
  Vec3 a = linear_accel(rig, s, bone) + angular_accel(s, bone).cross(r_world);
  if (centripetal) {
    const Vec3& w = s.omega_world[bone];
    a += w.cross(w.cross(r_world));
  }
  return a;
}

// M of eq. 5: how a force at offset r accelerates that point.
inline Mat3 force_to_accel(double mass, const Mat3& inertia_inv_world, const Vec3& r_world) {
  const Mat3 rx = skew(r_world);
  return Mat3::Identity() / mass + rx.transpose() * inertia_inv_world * rx;
}

// Inertia tensor of bone i in world axes (kg m^2).
Mat3 inertia_world(const Rig& rig, const Quat& orient_world, int bone);

}  // namespace physik
