// The equilibrium solve (physik/engine/equilibrium_solve.h) against `physik equilibrium` (Ceres,
// tune/equilibrium.h) where the minimum is unique: the solve run to a stationary point (no stall
// rule) lands on Ceres' pose within 1e-6 of the rig's height, with the gradient torsion torque
// (the potential's own force, which both minimise).
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "physik/io/rig_io.h"
#include "physik/io/scene_io.h"
#include "physik/posing/posing_session.h"
#include "tests/engine_test_util.h"
#include "tests/test_util.h"
#include "tune/equilibrium.h"

namespace physik::tune {
namespace {

// the solve to its stationary point: every goal at 1e-12, any improvement goes on
double distance_to_ceres(const Scene& scene, const char* name) {
  Scene solve = scene;
  use_solve_mode(solve.params);
  PosingSession session(solve);
  SolveRule rule;
  rule.tolerance = 1e-12 * goals_reach(scene);
  rule.tolerance_angle = 1e-12;
  rule.stall_fraction = 0.0;
  rule.max_steps = 1000;
  const SolveResult r = session.solve(rule);
  EXPECT_FALSE(r.diverged);
  Scene gradient = solve;  // Ceres in the joints the solve solved in (the implicit scheme's)
  gradient.params.torsion_torque = TorsionTorque::kGradient;
  const EquilibriumResult e = solve_equilibrium(gradient);
  EXPECT_TRUE(e.converged) << name << ": " << e.ceres_brief;
  const double d = max_pose_distance(session.frames(), e.frames) / scene.rig.height();
  std::cout << name << ": " << r.steps << " iterations, " << d << " of the height from Ceres, U "
            << scene_potential(gradient, session.pose()) << " vs " << e.potential << "\n";
  return d;
}

// a chain pinned at its root's head, pulled out of reach: the minimum is the chain straight
// toward the target, unique
TEST(EquilibriumSolveCeres, APinnedChainOutOfReachIsCeresPose) {
  std::vector<BoneSpec> specs(3);
  for (int i = 0; i < 3; ++i) {
    specs[i].name = "b" + std::to_string(i);
    specs[i].parent = i == 0 ? "" : "b" + std::to_string(i - 1);
    specs[i].head_world = Vec3(0, 0, i);
    specs[i].tail_world = Vec3(0, 0, i + 1);
    specs[i].rest_frame_world = rest_frame_from_roll(specs[i].head_world, specs[i].tail_world, 0.0);
  }
  Scene s = test::scene_for(build_rig(specs, "pinned", "pinned", RootJoint::kPinned),
                            preset_params("original"));
  s.control_points = {test::control(2, 1.0, Vec3(4.0, 2.0, 3.0), 10.0)};
  EXPECT_LT(distance_to_ceres(s, "pinned chain3"), 1e-6);
}

// Fig 6's elbows: three points fix the arm and pull the elbow past its band (limits engaged)
TEST(EquilibriumSolveCeres, TheElbowsPastTheirLimitAreCeresPose) {
  for (const char* name : {"fig6_elbow_linear", "fig6_elbow_capped"}) {
    const Scene s = load_scene(test::model_path(std::string("scenes/") + name + ".json"));
    EXPECT_LT(distance_to_ceres(s, name), 1e-6) << name;
  }
}

}  // namespace
}  // namespace physik::tune
