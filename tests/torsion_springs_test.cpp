// Torsion springs: torque only outside the engaged band, pushing back into range, equal and
// opposite on the parent, capped when asked.
#include "physik/torsion_springs.h"

#include <gtest/gtest.h>

#include "physik/engine.h"
#include "physik/newton_euler.h"
#include "tests/engine_test_util.h"
#include "tests/test_util.h"

namespace physik {
namespace {

// the elbow: forearm x in [-90, 0] deg, y and z locked
Scene elbow_scene() {
  const Rig rig = load_rig(test::model_path("rigs/elbow.json"));
  return test::scene_for(rig, test::bare_params(), 400);
}

TEST(TorsionSprings, LocalTorqueFollowsTheBand) {
  EngineParams p = preset_params("original");  // k 10, tolerance 0.1
  std::array<AxisLimit, 3> lim{};
  lim[0] = {true, deg2rad(-90), 0.0};
  // engaged band: [-81, -9] deg; inside it, nothing
  EXPECT_EQ(torsion_torque_local(lim, Vec3(deg2rad(-45), 0, 0), p), Vec3::Zero());
  // past the upper engage point (-9 deg): pushed back down, linear in the excess
  const Vec3 t = torsion_torque_local(lim, Vec3(deg2rad(10), 0, 0), p);
  EXPECT_NEAR(t.x(), -10.0 * deg2rad(19), 1e-12);
  // below the lower one: pushed up
  EXPECT_NEAR(torsion_torque_local(lim, Vec3(deg2rad(-100), 0, 0), p).x(), 10.0 * deg2rad(19),
              1e-12);
  // capped: never more than k * cap
  p.torsion_spring = SpringLaw::kCapped;
  p.torsion_cap = 0.1;
  EXPECT_NEAR(torsion_torque_local(lim, Vec3(deg2rad(10), 0, 0), p).x(), -10.0 * 0.1, 1e-12);
  // a locked axis always pulls to its value; a free axis never
  std::array<AxisLimit, 3> locked{};
  locked[1] = {true, 0.0, 0.0};
  p.torsion_spring = SpringLaw::kLinear;
  EXPECT_NEAR(torsion_torque_local(locked, Vec3(0.3, 0.2, 0.1), p).y(), -10.0 * 0.2, 1e-12);
  EXPECT_EQ(torsion_torque_local(locked, Vec3(0.3, 0.2, 0.1), p).x(), 0.0);
}

TEST(TorsionSprings, EqualAndOppositeTorquesThatPushBackIntoRange) {
  Scene scene = elbow_scene();
  // bend the forearm 30 deg past its limit (-120 deg about x), and twist it a little about y
  scene.initial_pose.bone_local_rotation[1] =
      Quat(Eigen::AngleAxisd(deg2rad(-120), Vec3::UnitX())) *
      Quat(Eigen::AngleAxisd(deg2rad(5), Vec3::UnitY()));
  SimState s;
  init_state(scene, s);
  local_rotations_from_world(scene.rig, s.frames, s.pose);
  prepare_bodies(scene.rig, scene.params, s);
  apply_torsion_springs(scene.rig, scene.params, s);
  EXPECT_LT((s.torque_world[0] + s.torque_world[1]).norm(), 1e-14);
  EXPECT_GT(s.torque_world[1].norm(), 1.0);
  // the torque on the forearm, in its limit axes, opposes the violation about x
  const Quat limit_frame = s.frames.orient_world[0] * scene.rig.bone_rest_orient_parent[1];
  const Vec3 tau_local = limit_frame.conjugate() * s.torque_world[1];
  EXPECT_GT(tau_local.x(), 0.0);

  // left alone (no control points) with the original's damping, the joint returns inside its
  // range and comes to rest
  scene.params = preset_params("original");
  scene.steps = 1000;
  const RunSummary r = run_scene(scene);
  EXPECT_TRUE(r.converged);
  const Vec3 theta = rotation_vector(r.final_pose.bone_local_rotation[1]);
  EXPECT_GE(rad2deg(theta.x()), -90.0 - 0.5);
  EXPECT_LE(rad2deg(theta.x()), 0.5);
  EXPECT_NEAR(rad2deg(theta.y()), 0.0, 0.5);
}

}  // namespace
}  // namespace physik
