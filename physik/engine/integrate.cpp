#include "physik/engine/integrate.h"

#include "physik/engine/newton_euler.h"

namespace physik {

Quat rotate_by(const Quat& q, const Vec3& w, double dt) {
  const double angle = w.norm() * dt;
  if (angle == 0.0) return q;
  return (Quat(Eigen::AngleAxisd(angle, w / w.norm())) * q).normalized();
}

namespace {

void update_angular(const Rig& rig, const EngineParams& params, double dt, SimState& s) {
  const double f = params.angular_velocity_factor;
  for (int i = 0; i < rig.nbone; ++i) {
    s.omega_world[i] = f * s.omega_world[i] + angular_accel(s, i) * dt;
    s.frames.orient_world[i] = rotate_by(s.frames.orient_world[i], s.omega_world[i], dt);
  }
}

// head/tail of bone i from its centre of mass and orientation
void place_from_com(const Rig& rig, SimState& s, int i) {
  const Vec3 half = s.frames.orient_world[i] * Vec3(0, 0.5 * rig.bone_length[i], 0);
  s.frames.head_world[i] = s.com_world[i] - half;
  s.frames.tail_world[i] = s.com_world[i] + half;
}

}  // namespace

void integrate_articulated(const Rig& rig, const EngineParams& params, double dt, SimState& s) {
  // the root translates with its own linear acceleration (read before forces change)
  s.vel_world[0] += linear_accel(rig, s, 0) * dt;
  s.com_world[0] += s.vel_world[0] * dt;
  update_angular(rig, params, dt, s);
  place_from_com(rig, s, 0);
  // the rest follow by forward kinematics; their velocities follow from the chain
  for (int i = 1; i < rig.nbone; ++i) {
    const int p = rig.bone_parent[i];
    s.frames.head_world[i] =
        s.frames.head_world[p] + s.frames.orient_world[p] * rig.bone_head_in_parent[i];
    const Vec3 axis = s.frames.orient_world[i] * Vec3(0, rig.bone_length[i], 0);
    s.frames.tail_world[i] = s.frames.head_world[i] + axis;
    s.com_world[i] = s.frames.head_world[i] + 0.5 * axis;
    const Vec3 v_head =
        s.vel_world[p] + s.omega_world[p].cross(s.frames.head_world[i] - s.com_world[p]);
    s.vel_world[i] = v_head + s.omega_world[i].cross(0.5 * axis);
  }
}

void integrate_free_rods(const Rig& rig, const EngineParams& params, double dt, SimState& s) {
  for (int i = 0; i < rig.nbone; ++i) {
    s.vel_world[i] += linear_accel(rig, s, i) * dt;
    s.com_world[i] += s.vel_world[i] * dt;
  }
  update_angular(rig, params, dt, s);
  for (int i = 0; i < rig.nbone; ++i) place_from_com(rig, s, i);
}

}  // namespace physik
