// The exact equilibrium solver: reachable targets met to 1e-8, a capped-spring balance in closed
// form, PhysIK's converged pose on a uniquely determined elbow, bad inputs.
#include <cmath>

#include <gtest/gtest.h>

#include "physik/engine/engine.h"
#include "physik/io/rig_io.h"
#include "physik/model/errors.h"
#include "physik/model/rig_generators.h"
#include "tests/engine_test_util.h"
#include "tests/test_util.h"
#include "tune/equilibrium.h"

namespace physik::tune {
namespace {

// the engine tests' helper, under this file's name
ControlPoint point(int bone, double alpha, const Vec3& target, double k,
                   SpringLaw law = SpringLaw::kLinear, double cap = 1.0) {
  return test::control(bone, alpha, target, k, law, cap);
}

Scene scene_of(const Rig& rig, int steps = 400) {
  Scene s;
  s.file = "test";
  s.rig = rig;
  s.params = preset_params("original");
  s.steps = steps;
  s.initial_pose = rest_pose(rig);
  return s;
}

TEST(Equilibrium, TwoBoneChainReachesAReachableTarget) {
  // two unit bones along +z; the root head pinned at the origin, the tip pulled to a point
  // 1.5 from it (reachable: < 2)
  Scene s = scene_of(make_chain_rig(2, 1.0));
  s.control_points = {point(0, 0.0, Vec3::Zero(), 10.0), point(1, 1.0, Vec3(1.2, 0.0, 0.9), 10.0)};
  const EquilibriumResult e = solve_equilibrium(s);
  EXPECT_TRUE(e.converged) << e.ceres_brief;
  for (double d : e.control_distance) EXPECT_LT(d, 1e-8);
  EXPECT_LT((e.frames.tail_world[1] - Vec3(1.2, 0.0, 0.9)).norm(), 1e-8);
  EXPECT_LT(e.frames.head_world[0].norm(), 1e-8);
  EXPECT_NEAR(scene_potential(s, e.pose), e.potential, 1e-12);
  // bone lengths are kept by construction
  EXPECT_NEAR((e.frames.tail_world[1] - e.frames.head_world[1]).norm(), 1.0, 1e-12);
}

TEST(Equilibrium, CappedSpringBalanceInClosedForm) {
  // root pinned by a stiff linear spring k1 at the origin, the tip pulled by a capped spring
  // (k2, cap c) toward a point D = 5 along +x, out of reach: the chain lies along +x and the
  // root moves by delta with k1 delta = k2 c (the capped force), as long as D - 2 - delta > c
  const double k1 = 100.0, k2 = 10.0, c = 1.0;
  Scene s = scene_of(make_chain_rig(2, 1.0));
  s.control_points = {point(0, 0.0, Vec3::Zero(), k1),
                      point(1, 1.0, Vec3(5, 0, 0), k2, SpringLaw::kCapped, c)};
  const EquilibriumResult e = solve_equilibrium(s);
  EXPECT_TRUE(e.converged) << e.ceres_brief;
  EXPECT_TRUE(test::near(e.frames.head_world[0], Vec3(k2 * c / k1, 0, 0), 1e-8));
  EXPECT_TRUE(test::near(e.frames.tail_world[1], Vec3(2 + k2 * c / k1, 0, 0), 1e-8));
  const double d2 = 5.0 - 2.0 - k2 * c / k1;
  EXPECT_NEAR(e.potential, 0.5 * k1 * std::pow(k2 * c / k1, 2) + k2 * c * (d2 - c / 2), 1e-9);
}

TEST(Equilibrium, SpringPotentialsMatchTheForceLaws) {
  // capped: continuous at the cap, slope k c beyond it (the force magnitude)
  EXPECT_DOUBLE_EQ(control_spring_potential(SpringLaw::kCapped, 4.0, 0.5, 0.5),
                   control_spring_potential(SpringLaw::kLinear, 4.0, 0.5, 0.5));
  EXPECT_NEAR(control_spring_potential(SpringLaw::kCapped, 4.0, 0.5, 2.001) -
                  control_spring_potential(SpringLaw::kCapped, 4.0, 0.5, 2.0),
              4.0 * 0.5 * 0.001, 1e-12);
  EXPECT_DOUBLE_EQ(torsion_spring_potential(SpringLaw::kCapped, 10.0, 0.2, -0.6), 10.0 * 0.2 * 0.5);
}

// The elbow (forearm bends about its local x by -90..0 deg, y and z locked) with the upper arm
// pinned at both ends and the forearm tip pulled to a point the 45-degree bend reaches once the
// upper arm rolls 30 degrees: a unique pose with zero potential.
Scene elbow_scene() {
  Scene s = scene_of(load_rig(test::model_path("rigs/elbow.json")), 1500);
  const double b = deg2rad(45.0), roll = deg2rad(30.0);
  const Vec3 tip_unrolled(0.0, 2.0 * std::sin(b), 2.0 + 2.0 * std::cos(b));
  const Vec3 tip = Eigen::AngleAxisd(roll, Vec3::UnitZ()) * tip_unrolled;
  s.control_points = {point(0, 0.0, Vec3(0, 0, 0), 10.0), point(0, 1.0, Vec3(0, 0, 2), 10.0),
                      point(1, 1.0, tip, 10.0)};
  s.params.interpolation = Interpolation::kNone;
  return s;
}

TEST(Equilibrium, PhysikConvergedPoseMatchesTheUniqueEquilibrium) {
  const Scene s = elbow_scene();
  const EquilibriumResult e = solve_equilibrium(s);
  ASSERT_TRUE(e.converged) << e.ceres_brief;
  EXPECT_LT(e.potential, 1e-16);
  for (double d : e.control_distance) EXPECT_LT(d, 1e-8);
  // the bend is -45 deg about x, inside the engaged band [-81, -9] deg
  const Vec3 theta = rotation_vector(e.pose.bone_local_rotation[1]);
  EXPECT_NEAR(rad2deg(theta.x()), -45.0, 1e-6);

  const RunSummary run = run_scene(s);
  ASSERT_TRUE(run.converged);
  ASSERT_FALSE(run.diverged);
  EXPECT_LT(max_pose_distance(run.final_frames, e.frames), s.residual_tol())
      << "PhysIK's final pose vs the exact equilibrium";
  // and PhysIK's pose is itself an equilibrium: Ceres started there does not move it
  EquilibriumOptions from_physik;
  from_physik.start = &run.final_pose;
  const EquilibriumResult polished = solve_equilibrium(s, from_physik);
  EXPECT_LT(max_pose_distance(polished.frames, e.frames), 1e-8);
}

// a welded group stays one body and an anchored root stays put in the exact static pose, which
// Ceres finds from where the implicit scheme settled, at a potential no higher
TEST(Equilibrium, WeldsAndAnAnchoredRootHoldInTheStaticPose) {
  for (const RootJoint root : {RootJoint::kPinned, RootJoint::kFixed}) {
    const Rig rig = test::welded_figure(root);
    Scene s = scene_of(rig);
    s.params.scheme = Scheme::kImplicit;
    s.params.damping_auto = true;
    s.params.torsion_torque = TorsionTorque::kGradient;  // the potential's force (equilibrium.h)
    s.steps = 2000;
    s.convergence.stop_when_converged = true;
    s.control_points.push_back(
        test::control(rig.find_bone("arm.L"), 1.0, Vec3(0.3, -0.4, 1.9), 10.0, SpringLaw::kCapped));
    s.control_points.push_back(
        test::control(rig.find_bone("shin.L"), 1.0, Vec3(0.3, -0.3, 0.3), 10.0));
    const RunSummary run = run_scene(s);
    ASSERT_TRUE(run.converged) << to_string(root);
    EquilibriumOptions from_physik;
    from_physik.start = &run.final_pose;
    const EquilibriumResult e = solve_equilibrium(s, from_physik);
    ASSERT_TRUE(e.converged) << e.ceres_brief;
    EXPECT_LE(e.potential, scene_potential(s, run.final_pose) * (1 + 1e-12)) << to_string(root);
    EXPECT_EQ((e.frames.head_world[0] - rig.bone_rest_head_world[0]).norm(), 0.0);
    for (int i = 0; i < rig.nbone; ++i) {
      const int w = rig.bone_weld[i];
      if (w < 0) continue;
      EXPECT_LT((e.frames.orient_world[w] * rig.bone_rest_orient_weld[i])
                    .angularDistance(e.frames.orient_world[i]),
                1e-12);
    }
  }
}

TEST(Equilibrium, BadInputs) {
  Scene s = scene_of(make_chain_rig(2, 1.0));
  EXPECT_THROW(solve_equilibrium(s), InputError);  // no control point
  s.control_points = {point(1, 1.0, Vec3(1, 0, 1), 10.0)};
  Pose wrong = rest_pose(make_chain_rig(3, 1.0));
  EquilibriumOptions opt;
  opt.start = &wrong;
  EXPECT_THROW(solve_equilibrium(s, opt), InputError);
}

TEST(Equilibrium, FinalTargetsFollowTheSchedule) {
  Scene s = scene_of(make_chain_rig(2, 1.0));
  s.control_points = {point(1, 1.0, Vec3(1, 0, 1), 10.0)};
  s.schedule = {{10, 0, Vec3(0, 1, 1)}, {20, 0, Vec3(0, 0, 1.5)}};
  const auto t = final_targets(s);
  ASSERT_EQ(t.size(), 1u);
  EXPECT_TRUE(test::near(t[0], Vec3(0, 0, 1.5), 0.0));
}

}  // namespace
}  // namespace physik::tune
