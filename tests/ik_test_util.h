// The contract every classic IK solver is held to (ik_solver.h), as reusable checks called from
// each solver's test file: reaches reachable goals within tolerance, respects its limits,
// stretches toward an unreachable goal without claiming convergence or producing NaN.
#pragma once

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "physik/ik/ik_solver.h"
#include "physik/io/rig_io.h"
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
      const bool lim = l.limited && i > 0;
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
    EXPECT_LE(max_limit_violation(rig, pose), 1e-9) << to_string(m) << " target " << t;
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
  EXPECT_LE(max_limit_violation(rig, pose), 1e-9) << to_string(m);
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

// The standard contract, for one solver.
inline void expect_solver_contract(IkMethod m, const IkOptions& opt = {}) {
  expect_reaches_random_targets(m, make_chain_rig(3), 2, 20, opt);
  expect_reaches_random_targets(m, make_chain_rig(10), 9, 10, opt);
  expect_elbow_limit_holds(m, opt);
  const Rig pinhead = load_rig(model_path("rigs/pinhead.json"));
  expect_respects_limits(m, pinhead, pinhead.find_bone("hand.L"), 10, opt);
  expect_stretches_toward_unreachable(m, opt);
}

}  // namespace physik::test
