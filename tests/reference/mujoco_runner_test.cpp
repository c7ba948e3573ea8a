// The MuJoCo reference runner (reference/mujoco_runner.h): with no joints both engines integrate
// the same equations, so they must agree to round-off; with joints, MuJoCo's limits hold up to the
// soft-constraint slack the header states.
#include "reference/mujoco_runner.h"
#include "physik/engine/engine.h"

#include <cmath>

#include <gtest/gtest.h>

#include "physik/io/rig_io.h"
#include "physik/model/joint_angles.h"
#include "physik/model/kinematics.h"
#include "tests/engine_test_util.h"
#include "tests/test_util.h"

namespace physik {
namespace {

// one free rod of length 1.5 along +Z, its tail pulled sideways and up by one spring
Scene free_rod_scene(SpringLaw law) {
  BoneSpec b;
  b.name = "rod";
  b.head_world = Vec3(0.2, -0.1, 0.0);
  b.tail_world = Vec3(0.2, -0.1, 1.5);
  b.rest_frame_world = rest_frame_from_roll(b.head_world, b.tail_world, 0.3);
  b.mass = 1.5;
  b.radius = 0.5;
  const Rig rig = build_rig({b}, "<test>", "rod");
  Scene s = test::scene_for(rig, preset_params("original"), 300);  // damping 3, w x 0.5, gyro on
  s.control_points.push_back(test::control(0, 0.8, Vec3(1.3, 0.7, 1.9), 10.0, law));
  s.schedule.push_back(TargetChange{150, 0, Vec3(-0.8, 0.4, 0.5)});  // a second jump mid-run
  return s;
}

void expect_same_trajectory(const Scene& scene) {
  SimState p;
  init_state(scene, p);
  MujocoReference ref(scene, ReferenceMode::kSameForces);
  double worst_pos = 0.0, worst_vel = 0.0, travel = 0.0;
  for (int k = 0; k < scene.steps; ++k) {
    step(scene, p);
    ref.step();
    const SimState& m = ref.state();
    worst_pos = std::max({worst_pos, (p.frames.head_world[0] - m.frames.head_world[0]).norm(),
                          (p.frames.tail_world[0] - m.frames.tail_world[0]).norm()});
    worst_vel = std::max({worst_vel, (p.vel_world[0] - m.vel_world[0]).norm(),
                          (p.omega_world[0] - m.omega_world[0]).norm()});
    travel = std::max(travel, (p.frames.tail_world[0] - Vec3(0.2, -0.1, 1.5)).norm());
  }
  EXPECT_LT(worst_pos, 1e-9);
  EXPECT_LT(worst_vel, 1e-9);
  EXPECT_GT(travel, 0.5);  // the rod really moved (and turned: the spring acts off its centre)
}

TEST(MujocoReference, FreeRodWithOneSpringFollowsTheSameTrajectory) {
  expect_same_trajectory(free_rod_scene(SpringLaw::kLinear));
  expect_same_trajectory(free_rod_scene(SpringLaw::kCapped));
}

TEST(MujocoReference, FreeRodWithoutGyroscopicTermStillMatches) {
  Scene s = free_rod_scene(SpringLaw::kLinear);
  s.params.gyroscopic = false;  // MuJoCo's own w x I w is cancelled by an equal torque
  expect_same_trajectory(s);
}

TEST(MujocoReference, AngularVelocityFactorAsATorqueHalvesASpinningRod) {
  // no forces: w_{k+1} = f w_k exactly, as PhysIK's integrator does (spin about the rod's axis,
  // a principal axis, so the gyroscopic term is zero)
  Scene s = free_rod_scene(SpringLaw::kLinear);
  s.control_points.clear();
  s.schedule.clear();
  s.params.damping = 0.0;
  SimState init;
  init_state(s, init);
  MujocoReference ref(s, ReferenceMode::kSameForces);
  const Vec3 axis = init.frames.orient_world[0] * Vec3(0, 1, 0);
  init.omega_world[0] = 2.0 * axis;
  ref.set_state(init);
  ASSERT_NEAR(ref.state().omega_world[0].dot(axis), 2.0, 1e-14);
  for (int k = 1; k <= 5; ++k) {
    ref.step();
    EXPECT_NEAR(ref.state().omega_world[0].dot(axis), 2.0 * std::pow(0.5, k), 1e-12);
  }
}

TEST(MujocoReference, ExactConstraintsKeepTheHingeInRangeUpToTheSoftLimitSlack) {
  // elbow: the forearm may bend 0..90 deg one way (x in [-90, 0] deg); its tip is pulled hard the
  // other way while the upper arm is held by two springs at rest
  const Rig rig = load_rig(test::model_path("rigs/elbow.json"));
  Scene s = test::scene_for(rig, preset_params("original"), 400);
  s.control_points.push_back(test::control(0, 0.0, Vec3(0, 0, 0), 30.0));
  s.control_points.push_back(test::control(0, 1.0, Vec3(0, 0, 2), 30.0));
  s.control_points.push_back(
      test::control(1, 1.0, Vec3(0, -2.0, 2.5), 30.0));  // toward +x rotation
  MujocoReference ref(s, ReferenceMode::kExactConstraints);
  const mjModel* m = ref.model();
  ASSERT_EQ(m->njnt, 2);  // free root + the elbow hinge
  const int j = 1, qa = m->jnt_qposadr[j], va = m->jnt_dofadr[j];
  const double hi = m->jnt_range[2 * j + 1];
  double worst = 0.0, worst_load = 0.0;
  for (int k = 0; k < s.steps; ++k) {
    ref.step();
    worst = std::max(worst, ref.data()->qpos[qa] - hi);
    worst_load = std::max(worst_load, ref.data()->qacc_smooth[va]);
  }
  // the load drives the hinge past its limit: it is pressed against it, and held there softly
  const double violation = ref.data()->qpos[qa] - hi;
  const double a0 = ref.data()->qacc_smooth[va];  // unconstrained acceleration of the hinge
  EXPECT_GT(a0, 1.0);
  EXPECT_GT(violation, 0.0);
  // at rest: r = (1 - d) tau^2 a0 with d = 0.95, tau = 2 dt (mujoco_runner.h); MuJoCo's
  // regularizer uses an approximate diagonal, so allow 25%
  const double tau = 2.0 * s.params.dt;
  const double predicted = 0.05 * tau * tau * a0;
  EXPECT_NEAR(violation, predicted, 0.25 * predicted);
  // over the run, transients included
  EXPECT_LT(worst, 2.0 * 0.05 * tau * tau * worst_load);
  RecordProperty("final_violation_deg", std::to_string(rad2deg(violation)));
  RecordProperty("predicted_violation_deg", std::to_string(rad2deg(predicted)));
  RecordProperty("worst_violation_deg", std::to_string(rad2deg(worst)));
  std::cout << "elbow limit: final violation " << rad2deg(violation) << " deg (predicted "
            << rad2deg(predicted) << " deg, a0 " << a0 << " rad/s^2), worst over the run "
            << rad2deg(worst) << " deg\n";

  // the same pull in same-forces mode (torsion springs) bends much further past the limit
  const RunSummary soft = run_mujoco(s, ReferenceMode::kSameForces);
  EXPECT_GT(soft.max_limit_violation_deg, 5.0 * rad2deg(worst));
}

// In exact-constraints mode MuJoCo's universal joint is two hinges (mjcf_export.h), whatever the
// scene's scheme, and its run is measured in their coordinates (joint_angles.h kRemoved): bent
// -50 deg about x and 40 about z (the bone lies along its local y), within both ranges, it is
// within its limits. The paper's scheme's own measure, the rotation vector, puts a second-order
// turn on the locked y.
TEST(MujocoReference, ExactConstraintsMeasureAUniversalJointInItsTwoHinges) {
  Rig rig = load_rig(test::model_path("rigs/elbow.json"));
  rig.bone_limit[1][2] = AxisLimit{true, deg2rad(-60), deg2rad(60)};
  refresh_joint_model(rig);
  ASSERT_EQ(rig.bone_joint_type[1], JointType::kUniversal);
  Scene s = test::scene_for(rig, preset_params("original"), 400);
  ASSERT_EQ(s.params.locked_axes(), LockedAxes::kSprings);
  Pose goal = rest_pose(rig);
  goal.bone_local_rotation[1] = Quat(Eigen::AngleAxisd(deg2rad(-50.0), Vec3::UnitX())) *
                                Quat(Eigen::AngleAxisd(deg2rad(40.0), Vec3::UnitZ()));
  const Vec3 tip = forward_kinematics(rig, goal).tail_world[1];
  s.control_points.push_back(test::control(0, 0.0, Vec3(0, 0, 0), 30.0));
  s.control_points.push_back(test::control(0, 1.0, Vec3(0, 0, 2), 30.0));
  s.control_points.push_back(test::control(1, 1.0, tip, 30.0));
  const RunSummary run = run_mujoco(s, ReferenceMode::kExactConstraints);
  const Pose& end = run.final_pose;
  std::vector<Vec3> angles, excess;
  joint_angles_and_excess(rig, LockedAxes::kRemoved, end, angles, excess);
  EXPECT_LT(angles[1].x(), deg2rad(-20.0));  // it bent on both hinges
  EXPECT_GT(angles[1].z(), deg2rad(15.0));
  EXPECT_LT(run.max_limit_violation_deg, 1e-9);
  EXPECT_GT(rad2deg(max_limit_violation(rig, LockedAxes::kSprings, end)), 3.0);
}

TEST(MujocoReference, RunReportsConvergenceLikeTheEngine) {
  Scene s = free_rod_scene(SpringLaw::kCapped);
  s.steps = 600;
  const RunSummary a = run_scene(s);
  const RunSummary b = run_mujoco(s, ReferenceMode::kSameForces);
  ASSERT_TRUE(a.converged);
  EXPECT_EQ(a.steps_to_converge, b.steps_to_converge);
  EXPECT_EQ(a.steps_run, b.steps_run);
  EXPECT_FALSE(b.diverged);
}

// A bundle: n bones zig-zagging along one unit segment, each a little beside the last (0.002
// apart, within their 0.06 collision radius of each other), lying on the ground with
// self-collision: every pair of bones that share no joint overlaps, some 2 n^2 MuJoCo contacts,
// more than the export sizes the buffers for (mjcf_export.h mjcf_size: one pair per bone).
Scene bundle_scene(int n) {
  std::vector<BoneSpec> specs;
  for (int i = 0; i < n; ++i) {
    BoneSpec b;
    b.name = "b" + std::to_string(i);
    b.parent = i ? "b" + std::to_string(i - 1) : "";
    b.head_world = Vec3(i % 2, 0.002 * i, 0.06);
    b.tail_world = Vec3((i + 1) % 2, 0.002 * (i + 1), 0.06);
    b.rest_frame_world = rest_frame_from_roll(b.head_world, b.tail_world, 0.0);
    b.mass = 1.0;
    b.radius = 0.06;
    b.collision_radius = 0.06;
    specs.push_back(b);
  }
  Scene s = test::scene_for(build_rig(specs, "<test>", "bundle"), preset_params("robust"), 5);
  s.collision.ground = GroundPlane{};
  s.collision.self_collision = true;
  return s;
}

TEST(MujocoReference, AFullContactBufferEndsTheRunAsNotComparableNamingTheWarning) {
  const Scene s = bundle_scene(40);
  const RunSummary run = run_mujoco(s, ReferenceMode::kSameForces);
  EXPECT_TRUE(run.diverged);
  EXPECT_FALSE(run.converged);
  EXPECT_EQ(run.steps_run, 1);
  EXPECT_NE(run.divergence_reason.find("MuJoCo raised mjWARN_CONTACTFULL (its contact list "
                                       "(nconmax "),
            std::string::npos)
      << run.divergence_reason;
  EXPECT_NE(run.divergence_reason.find("at step 1: not comparable"), std::string::npos);
  EXPECT_TRUE(mujoco_buffer_full(run.divergence_reason));
  // what to try names the buffers, not the step
  EXPECT_EQ(mujoco_hint(s, run.divergence_reason).find("dt"), std::string::npos);
  EXPECT_NE(mujoco_hint(s, "MuJoCo: non-finite state").find("--set dt=0.005"), std::string::npos);
  // the helper reads MuJoCo's own counters: none on a fresh model, each by name once raised
  MujocoReference ref(free_rod_scene(SpringLaw::kLinear), ReferenceMode::kSameForces);
  EXPECT_EQ(mujoco_warning(ref.model(), ref.data()), "");
  ref.data()->warning[mjWARN_CNSTRFULL].number = 1;
  EXPECT_EQ(mujoco_warning(ref.model(), ref.data())
                .rfind("mjWARN_CNSTRFULL (its constraint rows "
                       "(njmax ",
                       0),
            0u);
  ref.data()->warning[mjWARN_CNSTRFULL].number = 0;
  ref.data()->warning[mjWARN_BADQACC].number = 1;
  EXPECT_EQ(mujoco_warning(ref.model(), ref.data()),
            "mjWARN_BADQACC (a non-finite acceleration: it reset its state)");
}

}  // namespace
}  // namespace physik
