#include "physik/engine/joint_forces.h"

#include <algorithm>

#include "physik/engine/newton_euler.h"

namespace physik {

namespace {

// The bodies the joint solve moves: the bones themselves, or, on a rig with welds, the welded
// groups' composite bodies (prepare_welded_bodies), indexed by the body's first bone
struct SolveBodies {
  const double* mass;
  const Vec3* com_world;
  const Mat3* inertia_inv_world;
  const Vec3* gyro_world;
  Vec3* force_world;
  Vec3* torque_world;
};

SolveBodies solve_bodies(const Rig& rig, SimState& s) {
  GaussSeidelWorkspace& gs = s.gauss_seidel;
  if (!rig.has_welds()) {
    return {rig.bone_mass.data(), s.com_world.data(),   s.inertia_inv_world.data(),
            s.gyro_world.data(),  s.force_world.data(), s.torque_world.data()};
  }
  return {gs.body_mass.data(),       gs.body_com_world.data(),   gs.body_inertia_inv_world.data(),
          gs.body_gyro_world.data(), gs.body_force_world.data(), gs.body_torque_world.data()};
}

// the acceleration of the point at offset r from body b's centre (newton_euler.h, eq. 2); a
// body turns with its first bone's w
inline Vec3 body_point_accel(const SolveBodies& bodies, const SimState& s, int b, const Vec3& r,
                             bool centripetal) {
  const Vec3 alpha = bodies.inertia_inv_world[b] * (bodies.torque_world[b] - bodies.gyro_world[b]);
  Vec3 a = bodies.force_world[b] / bodies.mass[b] + alpha.cross(r);
  if (centripetal) {
    const Vec3& w = s.omega_world[b];
    a += w.cross(w.cross(r));
  }
  return a;
}

}  // namespace

void prepare_joint_solve(const Rig& rig, SimState& s) {
  GaussSeidelWorkspace& gs = s.gauss_seidel;
  const SolveBodies bodies = solve_bodies(rig, s);
  const int njoint = static_cast<int>(rig.joints.size());
  for (int j = 0; j < njoint; ++j) {
    Mat3 sum = Mat3::Zero();
    for (int m = rig.joint_first_member[j]; m < rig.joint_first_member[j + 1]; ++m) {
      const int b = rig.joint_member_bone[m], body = rig.joint_member_body[m];
      const Vec3& point =
          rig.joint_member_at_tail[m] ? s.frames.tail_world[b] : s.frames.head_world[b];
      gs.member_r_world[m] = point - bodies.com_world[body];
      gs.member_Minv[m] =
          force_to_accel(bodies.mass[body], bodies.inertia_inv_world[body], gs.member_r_world[m])
              .inverse();
      sum += gs.member_Minv[m];
    }
    // an anchored joint's point does not accelerate: v = 0, no average to take
    gs.joint_Sinv[j] = rig.joint_anchored[j] ? Mat3::Zero() : Mat3(sum.inverse());
  }
}

namespace {

// accelerations of joint j's points, into s.gauss_seidel.member_accel; returns their largest
// pairwise gap and, in `size`, the largest of them
double measure_joint(const Rig& rig, const EngineParams& params, const SolveBodies& bodies,
                     SimState& s, int j, double* size = nullptr) {
  GaussSeidelWorkspace& gs = s.gauss_seidel;
  const int first = rig.joint_first_member[j], last = rig.joint_first_member[j + 1];
  for (int m = first; m < last; ++m) {
    gs.member_accel[m] = body_point_accel(bodies, s, rig.joint_member_body[m], gs.member_r_world[m],
                                          params.centripetal);
  }
  double gap = 0.0, largest = 0.0;
  for (int m = first; m < last; ++m) {
    largest = std::max(largest, gs.member_accel[m].norm());
    for (int n = m + 1; n < last; ++n) {
      gap = std::max(gap, (gs.member_accel[m] - gs.member_accel[n]).norm());
    }
  }
  // the world's point at an anchored joint does not accelerate
  if (rig.joint_anchored[j]) gap = std::max(gap, largest);
  if (size) *size = largest;
  return gap;
}

}  // namespace

double joint_accel_mismatch(const Rig& rig, const EngineParams& params, SimState& s) {
  const SolveBodies bodies = solve_bodies(rig, s);
  double worst = 0.0;
  for (int j = 0; j < static_cast<int>(rig.joints.size()); ++j) {
    worst = std::max(worst, measure_joint(rig, params, bodies, s, j));
  }
  return worst;
}

JointSolveStats solve_joint_forces(const Rig& rig, const EngineParams& params, SimState& s) {
  GaussSeidelWorkspace& gs = s.gauss_seidel;
  JointSolveStats stats;
  const int njoint = static_cast<int>(rig.joints.size());
  if (njoint == 0) return stats;
  prepare_joint_solve(rig, s);
  const SolveBodies bodies = solve_bodies(rig, s);
  const bool welds = rig.has_welds();
  for (Vec3& f : gs.member_force_world) f.setZero();
  const int cap = params.passes_cap(rig.nbone);
  const double rel = params.joint_eps_relative, floor = 1e-9 * params.joint_eps;
  for (int pass = 0; pass < cap; ++pass) {
    double pass_mismatch = 0.0;
    bool relative_ok = true;  // every gap below rel x its joint's largest acceleration
    for (int j = 0; j < njoint; ++j) {
      double size = 0.0;
      const double gap = measure_joint(rig, params, bodies, s, j, &size);
      pass_mismatch = std::max(pass_mismatch, gap);
      if (rel > 0.0 && gap > std::max(rel * size, floor)) relative_ok = false;
      const int first = rig.joint_first_member[j], last = rig.joint_first_member[j + 1];
      // v = (sum M^-1)^-1 sum M^-1 a   (corrected eq. 11); 0 where the world holds the joint
      Vec3 v = Vec3::Zero();
      if (!rig.joint_anchored[j]) {
        Vec3 rhs = Vec3::Zero();
        for (int m = first; m < last; ++m) rhs += gs.member_Minv[m] * gs.member_accel[m];
        v = gs.joint_Sinv[j] * rhs;
      }
      // F_i = M_i^-1 (v - a_i), applied at the joint point; sum_i F_i = 0 up to round-off
      for (int m = first; m < last; ++m) {
        const int b = rig.joint_member_bone[m], body = rig.joint_member_body[m];
        const Vec3 f = gs.member_Minv[m] * (v - gs.member_accel[m]);
        const Vec3 tau = gs.member_r_world[m].cross(f);
        bodies.force_world[body] += f;
        bodies.torque_world[body] += tau;
        // the bone's own record: the force at the joint point, its torque about the bone's centre
        s.joint_force_world[b] += f;
        s.joint_torque_world[b] +=
            welds ? Vec3((gs.member_r_world[m] + bodies.com_world[body] - s.com_world[b]).cross(f))
                  : tau;
        gs.member_force_world[m] += f;
      }
    }
    stats.passes = pass + 1;
    if (pass_mismatch < params.joint_eps && relative_ok) break;
  }
  stats.mismatch = joint_accel_mismatch(rig, params, s);
  return stats;
}

int unreached_joints(const Rig& rig, const SimState& s) {
  const int njoint = static_cast<int>(rig.joints.size());
  // the largest point acceleration of each joint lands in the first pass; the count in the second
  double largest = 0.0;
  for (int m = 0; m < static_cast<int>(rig.joint_member_bone.size()); ++m) {
    largest = std::max(largest, s.gauss_seidel.member_accel[m].norm());
  }
  if (!(largest > 0.0)) return 0;
  int count = 0;
  for (int j = 0; j < njoint; ++j) {
    double size = 0.0;
    for (int m = rig.joint_first_member[j]; m < rig.joint_first_member[j + 1]; ++m) {
      size = std::max(size, s.gauss_seidel.member_accel[m].norm());
    }
    if (size < kUnreachedFraction * largest) ++count;
  }
  return count;
}

}  // namespace physik
