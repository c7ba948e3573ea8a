#include "physik/engine/joint_forces.h"

#include <algorithm>

#include "physik/engine/newton_euler.h"

namespace physik {

void prepare_joint_solve(const Rig& rig, SimState& s) {
  const int njoint = static_cast<int>(rig.joints.size());
  for (int j = 0; j < njoint; ++j) {
    Mat3 sum = Mat3::Zero();
    for (int m = rig.joint_first_member[j]; m < rig.joint_first_member[j + 1]; ++m) {
      const int b = rig.joint_member_bone[m];
      const Vec3& point =
          rig.joint_member_at_tail[m] ? s.frames.tail_world[b] : s.frames.head_world[b];
      s.member_r_world[m] = point - s.com_world[b];
      s.member_Minv[m] =
          force_to_accel(rig.bone_mass[b], s.inertia_inv_world[b], s.member_r_world[m]).inverse();
      sum += s.member_Minv[m];
    }
    s.joint_Sinv[j] = sum.inverse();
  }
}

namespace {

// accelerations of joint j's points, into s.member_accel; returns their largest pairwise gap
double measure_joint(const Rig& rig, const EngineParams& params, SimState& s, int j) {
  const int first = rig.joint_first_member[j], last = rig.joint_first_member[j + 1];
  for (int m = first; m < last; ++m) {
    s.member_accel[m] =
        point_accel(rig, s, rig.joint_member_bone[m], s.member_r_world[m], params.centripetal);
  }
  double gap = 0.0;
  for (int m = first; m < last; ++m) {
    for (int n = m + 1; n < last; ++n) {
      gap = std::max(gap, (s.member_accel[m] - s.member_accel[n]).norm());
    }
  }
  return gap;
}

}  // namespace

double joint_accel_mismatch(const Rig& rig, const EngineParams& params, SimState& s) {
  double worst = 0.0;
  for (int j = 0; j < static_cast<int>(rig.joints.size()); ++j) {
    worst = std::max(worst, measure_joint(rig, params, s, j));
  }
  return worst;
}

JointSolveStats solve_joint_forces(const Rig& rig, const EngineParams& params, SimState& s) {
  JointSolveStats stats;
  const int njoint = static_cast<int>(rig.joints.size());
  if (njoint == 0) return stats;
  prepare_joint_solve(rig, s);
  for (Vec3& f : s.member_force_world) f.setZero();
  const int cap = params.passes_cap(rig.nbone);
  for (int pass = 0; pass < cap; ++pass) {
    double pass_mismatch = 0.0;
    for (int j = 0; j < njoint; ++j) {
      pass_mismatch = std::max(pass_mismatch, measure_joint(rig, params, s, j));
      const int first = rig.joint_first_member[j], last = rig.joint_first_member[j + 1];
      // v = (sum M^-1)^-1 sum M^-1 a   (corrected eq. 11)
      Vec3 rhs = Vec3::Zero();
      for (int m = first; m < last; ++m) rhs += s.member_Minv[m] * s.member_accel[m];
      const Vec3 v = s.joint_Sinv[j] * rhs;
      // F_i = M_i^-1 (v - a_i), applied at the joint point; sum_i F_i = 0 up to round-off
      for (int m = first; m < last; ++m) {
        const int b = rig.joint_member_bone[m];
        const Vec3 f = s.member_Minv[m] * (v - s.member_accel[m]);
        const Vec3 tau = s.member_r_world[m].cross(f);
        s.force_world[b] += f;
        s.torque_world[b] += tau;
        s.joint_force_world[b] += f;
        s.joint_torque_world[b] += tau;
        s.member_force_world[m] += f;
      }
    }
    stats.passes = pass + 1;
    if (pass_mismatch < params.joint_eps) break;
  }
  stats.mismatch = joint_accel_mismatch(rig, params, s);
  return stats;
}

}  // namespace physik
