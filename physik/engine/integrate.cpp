#include "physik/engine/integrate.h"

#include "physik/engine/newton_euler.h"

namespace physik {

double integrated_factor(const EngineParams& params) {
  return params.factor_in_joint_solve ? 1.0 : params.angular_velocity_factor;
}

Quat rotate_by(const Quat& q, const Vec3& w, double dt) {
  const double angle = w.norm() * dt;
  if (angle == 0.0) return q;
  return (Quat(Eigen::AngleAxisd(angle, w / w.norm())) * q).normalized();
}

namespace {

void update_angular(const Rig& rig, const EngineParams& params, double dt, SimState& s) {
  const double f = integrated_factor(params);
  // a fixed root never turns
  for (int i = rig.root_joint == RootJoint::kFixed ? 1 : 0; i < rig.nbone; ++i) {
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

namespace {

// With welds: every body (at its first bone) turns by its own composite Newton-Euler, w <- f w +
// alpha dt; a welded bone takes its weld's w and its rest frame in its weld's. A free root's body
// moves its centre of mass c and turns about it, as a root rod does (docs/engine.md "The paper's
// scheme (gauss-seidel)", its two integration choices): v_c <- v_c + F / m dt, c <- c + v_c dt,
// and the root bone's centre rides on the body, c_0 = c + dR (c_0 - c), v_0 = v_c + w x (c_0 - c)
// (integrate_free_bodies does the same for every body)
void integrate_welded_bodies(const Rig& rig, const EngineParams& params, double dt, SimState& s) {
  GaussSeidelWorkspace& gs = s.gauss_seidel;
  const double f = integrated_factor(params);
  const bool free_root = rig.root_joint == RootJoint::kFree;
  // the root body's centre velocity, from the root bone's and the start-of-step w
  Vec3 v_centre = Vec3::Zero();
  if (free_root) {
    v_centre = s.vel_world[0] -
               s.omega_world[0].cross(Vec3(s.com_world[0] - gs.body_com_world[0])) +
               gs.body_force_world[0] / gs.body_mass[0] * dt;
  }
  for (int i = rig.root_joint == RootJoint::kFixed ? 1 : 0; i < rig.nbone; ++i) {
    const int w = rig.bone_weld[i];
    if (w >= 0) {
      s.omega_world[i] = s.omega_world[w];
      s.frames.orient_world[i] =
          (s.frames.orient_world[w] * rig.bone_rest_orient_weld[i]).normalized();
      continue;
    }
    const Vec3 alpha =
        gs.body_inertia_inv_world[i] * (gs.body_torque_world[i] - gs.body_gyro_world[i]);
    s.omega_world[i] = f * s.omega_world[i] + alpha * dt;
    s.frames.orient_world[i] = rotate_by(s.frames.orient_world[i], s.omega_world[i], dt);
  }
  if (free_root) {
    const Vec3& w = s.omega_world[0];
    const Vec3 r = rotate_by(Quat::Identity(), w, dt) * Vec3(s.com_world[0] - gs.body_com_world[0]);
    s.com_world[0] = gs.body_com_world[0] + v_centre * dt + r;
    s.vel_world[0] = v_centre + w.cross(r);
  }
}

// an anchored root turns about its head, which stays where it is
void place_anchored_root(const Rig& rig, SimState& s) {
  const Vec3 half = s.frames.orient_world[0] * Vec3(0, 0.5 * rig.bone_length[0], 0);
  s.frames.head_world[0] = rig.bone_rest_head_world[0];
  s.com_world[0] = s.frames.head_world[0] + half;
  s.frames.tail_world[0] = s.com_world[0] + half;
  s.vel_world[0] = s.omega_world[0].cross(half);
}

}  // namespace

void integrate_articulated(const Rig& rig, const EngineParams& params, double dt, SimState& s) {
  const bool free_root = rig.root_joint == RootJoint::kFree;
  if (rig.has_welds()) {
    integrate_welded_bodies(rig, params, dt, s);
  } else {
    if (free_root) {
      // the root translates with its own linear acceleration (read before forces change)
      s.vel_world[0] += linear_accel(rig, s, 0) * dt;
      s.com_world[0] += s.vel_world[0] * dt;
    }
    update_angular(rig, params, dt, s);
  }
  if (free_root) {
    place_from_com(rig, s, 0);
  } else {
    place_anchored_root(rig, s);
  }
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

namespace {

// Free rods with welds: every body moves as one rigid body of its own, its centre c by its
// composite force, its turn by its composite Newton-Euler (as integrate_welded_bodies); its bones
// keep their offsets from c, turned with it: c_i = c + dR (c_i - c), R_i = dR R_i,
// v_i = v + w x (c_i - c)
void integrate_free_bodies(const Rig& rig, const EngineParams& params, double dt, SimState& s) {
  GaussSeidelWorkspace& gs = s.gauss_seidel;
  const double f = integrated_factor(params);
  const int first = rig.root_joint == RootJoint::kFixed ? 1 : 0;
  // each body's new w and centre velocity, at its first bone
  for (int b = first; b < rig.nbone; ++b) {
    if (rig.bone_weld[b] >= 0) continue;
    const Vec3 w0 = s.omega_world[b];
    gs.body_vel_world[b] = s.vel_world[b] + w0.cross(Vec3(gs.body_com_world[b] - s.com_world[b])) +
                           gs.body_force_world[b] / gs.body_mass[b] * dt;
    const Vec3 alpha =
        gs.body_inertia_inv_world[b] * (gs.body_torque_world[b] - gs.body_gyro_world[b]);
    s.omega_world[b] = f * w0 + alpha * dt;
  }
  // every bone with its body
  for (int i = first; i < rig.nbone; ++i) {
    const int b = rig.bone_body[i];
    const Vec3& w = s.omega_world[b];
    const Vec3& v = gs.body_vel_world[b];
    const Quat turn = rotate_by(Quat::Identity(), w, dt);
    const Vec3 r = turn * Vec3(s.com_world[i] - gs.body_com_world[b]);
    s.com_world[i] = gs.body_com_world[b] + v * dt + r;
    s.frames.orient_world[i] = (turn * s.frames.orient_world[i]).normalized();
    s.omega_world[i] = w;
    s.vel_world[i] = v + w.cross(r);
    place_from_com(rig, s, i);
  }
}

}  // namespace

void integrate_free_rods(const Rig& rig, const EngineParams& params, double dt, SimState& s) {
  if (rig.has_welds()) {
    integrate_free_bodies(rig, params, dt, s);
    return;
  }
  // a fixed root never moves; a pinned one's head is held by its joint's forces only
  for (int i = rig.root_joint == RootJoint::kFixed ? 1 : 0; i < rig.nbone; ++i) {
    s.vel_world[i] += linear_accel(rig, s, i) * dt;
    s.com_world[i] += s.vel_world[i] * dt;
  }
  update_angular(rig, params, dt, s);
  for (int i = rig.root_joint == RootJoint::kFixed ? 1 : 0; i < rig.nbone; ++i) {
    place_from_com(rig, s, i);
  }
}

}  // namespace physik
