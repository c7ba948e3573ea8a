// The contract every classic IK solver is held to (ik_solver.h), as reusable checks called from
// each solver's test file: reaches reachable goals within tolerance, respects its limits,
// stretches toward an unreachable goal without claiming convergence or producing NaN.
#pragma once

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "physik/ik/ik_solver.h"
#include "physik/io/rig_io.h"
#include "physik/model/joint_angles.h"
#include "physik/model/rig_generators.h"
#include "tests/test_util.h"

namespace physik::test {

inline bool pose_is_finite(const Pose& p) {
  if (!p.root_head_world.allFinite()) return false;
  for (const Quat& q : p.bone_local_rotation) {
    if (!q.coeffs().allFinite()) return false;
  }
  return true;
}

// A random pose within the rig's limits (free axes: components in [-spread, spread] rad).
inline Pose random_pose(const Rig& rig, std::mt19937& rng, double spread) {
  Pose p = rest_pose(rig);
  for (int i = 0; i < rig.nbone; ++i) {
    Vec3 v;
    for (int k = 0; k < 3; ++k) {
      const AxisLimit& l = rig.bone_limit[i][k];
      const bool lim = l.limited;  // the root's too (a pinned root's)
      std::uniform_real_distribution<double> d(lim ? l.min : -spread, lim ? l.max : spread);
      v[k] = d(rng);
    }
    p.bone_local_rotation[i] = quat_from_rotation_vector(v);
  }
  return p;
}

// Goals reached from random poses: every solve converges and its residual meets the tolerance.
inline void expect_reaches_random_targets(IkMethod m, const Rig& rig, int bone, int count,
                                          const IkOptions& opt = {}) {
  std::mt19937 rng(1234);
  for (int t = 0; t < count; ++t) {
    const Vec3 target = forward_kinematics(rig, random_pose(rig, rng, 1.0)).tail_world[bone];
    Pose pose = rest_pose(rig);
    const IkReport rep = solve_ik(m, rig, {{bone, 1.0, target}}, pose, opt);
    EXPECT_TRUE(rep.converged) << to_string(m) << " target " << t << " (" << target.transpose()
                               << "): residual " << rep.residual << " after " << rep.iterations;
    const Vec3 tip = forward_kinematics(rig, pose).tail_world[bone];
    EXPECT_LE((tip - target).norm(), rep.tolerance + 1e-12);
    EXPECT_NEAR(rep.tolerance, 1e-4 * chain_reach(rig, {{bone, 1.0, target}}), 1e-15);
  }
}

// Every returned pose lies within the rig's limits (clamping), on random goals for `bone`.
inline void expect_respects_limits(IkMethod m, const Rig& rig, int bone, int count,
                                   const IkOptions& opt = {}) {
  std::mt19937 rng(99);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double reach = chain_reach(rig, {{bone, 1.0, Vec3::Zero()}});
  for (int t = 0; t < count; ++t) {
    const Vec3 target = rig.bone_rest_head_world[0] + reach * Vec3(u(rng), u(rng), u(rng));
    Pose pose = rest_pose(rig);
    solve_ik(m, rig, {{bone, 1.0, target}}, pose, opt);
    EXPECT_LE(max_limit_violation(rig, LockedAxes::kSprings, pose), 1e-9)
        << to_string(m) << " target " << t;
  }
}

// The elbow rig (forearm bends 0..90 deg): a target 1 unit from the shoulder needs an interior
// angle below 90 deg. The closest legal tip is at 2 sqrt(2) from the shoulder.
inline void expect_elbow_limit_holds(IkMethod m, const IkOptions& opt = {}) {
  const Rig rig = load_rig(model_path("rigs/elbow.json"));
  const Vec3 target(0.0, 0.6, 0.8);
  Pose pose = rest_pose(rig);
  const IkReport rep = solve_ik(m, rig, {{1, 1.0, target}}, pose, opt);
  EXPECT_TRUE(pose_is_finite(pose));
  EXPECT_FALSE(rep.converged);
  EXPECT_LE(max_limit_violation(rig, LockedAxes::kSprings, pose), 1e-9) << to_string(m);
  EXPECT_GE(rep.residual, 2.0 * std::sqrt(2.0) - 1.0 - 1e-9) << to_string(m);
}

// chain3 pulled toward a point 5.66 units away (reach 3): no convergence, finite, and the chain
// stretched toward it: the tip lies close to the nearest reachable point 3 t / |t|.
inline void expect_stretches_toward_unreachable(IkMethod m, const IkOptions& opt = {},
                                                double slack = 0.02) {
  const Rig rig = make_chain_rig(3);
  const Vec3 target(0.0, 4.0, 4.0);
  Pose pose = rest_pose(rig);
  const IkReport rep = solve_ik(m, rig, {{2, 1.0, target}}, pose, opt);
  EXPECT_FALSE(rep.converged) << to_string(m);
  EXPECT_TRUE(pose_is_finite(pose)) << to_string(m);
  EXPECT_TRUE(std::isfinite(rep.residual));
  const Vec3 tip = forward_kinematics(rig, pose).tail_world[2];
  EXPECT_TRUE(near(tip, 3.0 * target.normalized(), slack * 3.0)) << to_string(m);
  EXPECT_NEAR(rep.residual, target.norm() - 3.0, slack * 3.0) << to_string(m);
}

// An arm held by the world at its root (rig.h, the root's joint): three bones up +Z, each a hinge
// about its local x (two locked axes); the root "pinned" (its hinge against its rest frame in the
// world, as MuJoCo's arm26 shoulder) or "fixed" (it never turns: no limits allowed). Every pose
// within the limits keeps the arm in the plane through the origin normal to the hinges' axis.
inline Rig anchored_arm(RootJoint root) {
  std::vector<BoneSpec> bones;
  const char* names[] = {"upper", "lower", "hand"};
  const double z[] = {0.0, 1.0, 2.0, 2.5};
  for (int i = 0; i < 3; ++i) {
    BoneSpec b;
    b.name = names[i];
    if (i > 0) b.parent = names[i - 1];
    b.head_world = Vec3(0, 0, z[i]);
    b.tail_world = Vec3(0, 0, z[i + 1]);
    b.rest_frame_world = rest_frame_from_roll(b.head_world, b.tail_world, 0.0);
    if (i > 0 || root == RootJoint::kPinned) {
      b.limit = {AxisLimit{true, -1.5, 1.5}, AxisLimit{true, 0.0, 0.0}, AxisLimit{true, 0.0, 0.0}};
    }
    bones.push_back(b);
  }
  return build_rig(bones, "anchored_arm", "anchored_arm", root);
}

// The root's limits are a joint's like any other (ik_solver.h): a pinned hinge root pulled out of
// its plane stays on its hinge, the violation measure counts it (a pose turned off the hinge
// reads as such), the solve does not claim to converge, and its residual is at least the
// target's distance from the plane. A fixed root never turns, and an in-plane target is still
// pulled toward.
inline void expect_honours_anchored_root(IkMethod m, const IkOptions& opt = {}) {
  const Rig pinned = anchored_arm(RootJoint::kPinned);
  const Vec3 normal = pinned.bone_rest_orient_world[0] * Vec3::UnitX();  // the hinges' axis
  // the measure: the root turned 0.3 rad about a locked axis
  Pose off = rest_pose(pinned);
  off.bone_local_rotation[0] = Quat(Eigen::AngleAxisd(0.3, Vec3::UnitZ()));
  EXPECT_NEAR(max_limit_violation(pinned, LockedAxes::kSprings, off), 0.3, 1e-12);
  // 0.8 out of the plane, in reach of the arm (2.5) from its pinned head
  const Vec3 target =
      Vec3(0, 0, 1.2) + (Vec3::UnitZ().cross(normal)).normalized() * 1.0 + 0.8 * normal;
  Pose pose = rest_pose(pinned);
  const IkReport rep = solve_ik(m, pinned, {{2, 1.0, target}}, pose, opt);
  EXPECT_TRUE(pose_is_finite(pose)) << to_string(m);
  EXPECT_LE(max_limit_violation(pinned, LockedAxes::kSprings, pose), 1e-9) << to_string(m);
  EXPECT_FALSE(rep.converged) << to_string(m);
  EXPECT_GE(rep.residual, 0.8 - 1e-9) << to_string(m);
  // fixed: the root keeps its rest frame exactly; the arm below it still turns toward the target
  const Rig fixed = anchored_arm(RootJoint::kFixed);
  const Vec3 in_plane = forward_kinematics(fixed,
                                           [&] {
                                             Pose p = rest_pose(fixed);
                                             p.bone_local_rotation[1] =
                                                 Quat(Eigen::AngleAxisd(0.9, Vec3::UnitX()));
                                             return p;
                                           }())
                            .tail_world[2];
  Pose still = rest_pose(fixed);
  const double start = (forward_kinematics(fixed, still).tail_world[2] - in_plane).norm();
  const IkReport fixed_rep = solve_ik(m, fixed, {{2, 1.0, in_plane}}, still, opt);
  EXPECT_EQ(still.bone_local_rotation[0].coeffs(), Quat::Identity().coeffs()) << to_string(m);
  EXPECT_LT(fixed_rep.residual, 0.5 * start) << to_string(m);
}

// The standard contract, for one solver.
inline void expect_solver_contract(IkMethod m, const IkOptions& opt = {}) {
  expect_reaches_random_targets(m, make_chain_rig(3), 2, 20, opt);
  expect_reaches_random_targets(m, make_chain_rig(10), 9, 10, opt);
  expect_elbow_limit_holds(m, opt);
  const Rig pinhead = load_rig(model_path("rigs/pinhead.json"));
  expect_respects_limits(m, pinhead, pinhead.find_bone("hand.L"), 10, opt);
  expect_stretches_toward_unreachable(m, opt);
  expect_honours_anchored_root(m, opt);
}

}  // namespace physik::test
