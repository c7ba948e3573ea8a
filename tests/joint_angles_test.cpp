// Joint angles and their excess past the limits (physik/model/joint_angles.h): analytic cases on
// the elbow, and on random poses of the pinhead rig the torsion springs' own measure (the torque
// each bone's spring applies, recovered from apply_torsion_springs' world torques, is
// -k * excess with no engage band) and the run monitor's max_limit_violation; in the exact and
// implicit schemes' joints (LockedAxes::kRemoved) a hinge's and a universal joint's own angles,
// where the rotation vector reads a locked axis wrong.
#include "physik/model/joint_angles.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "physik/engine/engine.h"
#include "physik/engine/newton_euler.h"
#include "physik/engine/torsion_springs.h"
#include "physik/io/rig_io.h"
#include "physik/model/joint_coordinates.h"
#include "tests/engine_test_util.h"
#include "tests/test_util.h"

namespace physik {
namespace {

Quat about(double deg, const Vec3& axis) {
  return Quat(Eigen::AngleAxisd(deg2rad(deg), axis.normalized()));
}

// the elbow's forearm: x in [-90, 0] deg, y and z locked at 0
struct ElbowCase {
  Quat rotation;
  Vec3 angle_deg, excess_deg;
};

TEST(JointAngles, AnalyticOnTheElbow) {
  const Rig rig = load_rig(test::model_path("rigs/elbow.json"));
  const ElbowCase cases[] = {
      {Quat::Identity(), {0, 0, 0}, {0, 0, 0}},
      {about(-45, Vec3::UnitX()), {-45, 0, 0}, {0, 0, 0}},      // within the range
      {about(-120, Vec3::UnitX()), {-120, 0, 0}, {-30, 0, 0}},  // 30 deg below the min
      {about(20, Vec3::UnitX()), {20, 0, 0}, {20, 0, 0}},       // 20 deg above the max
      {about(15, Vec3::UnitY()), {0, 15, 0}, {0, 15, 0}},       // a locked axis
      // about an oblique axis the rotation vector is the angle times the axis
      {about(60, Vec3(-1, 0, 1)),
       {-60 / std::sqrt(2.0), 0, 60 / std::sqrt(2.0)},
       {0, 0, 60 / std::sqrt(2.0)}},
      // past half a turn the log map takes the short way: 260 deg about x is -100 deg
      {about(260, Vec3::UnitX()), {-100, 0, 0}, {-10, 0, 0}},
  };
  for (const ElbowCase& c : cases) {
    Pose pose = rest_pose(rig);
    pose.bone_local_rotation[0] = about(70, Vec3(1, 2, 3));  // the root: measured, never limited
    pose.bone_local_rotation[1] = c.rotation;
    std::vector<Vec3> angles, excess;
    joint_angles_and_excess(rig, LockedAxes::kSprings, pose, angles, excess);
    ASSERT_EQ(angles.size(), 2u);
    ASSERT_EQ(excess.size(), 2u);
    EXPECT_TRUE(test::near(angles[0], deg2rad(70) * Vec3(1, 2, 3).normalized(), 1e-12));
    EXPECT_EQ(excess[0], Vec3::Zero());
    const Vec3 expected_angle = deg2rad(1.0) * c.angle_deg;
    const Vec3 expected_excess = deg2rad(1.0) * c.excess_deg;
    EXPECT_TRUE(test::near(angles[1], expected_angle, 1e-12)) << c.angle_deg.transpose();
    EXPECT_TRUE(test::near(excess[1], expected_excess, 1e-12)) << c.angle_deg.transpose();
  }
}

TEST(JointAngles, LimitExcessPerAxis) {
  const AxisLimit free{}, range{true, -0.5, 0.25}, locked{true, 0.1, 0.1};
  EXPECT_EQ(limit_excess(free, 3.0), 0.0);
  EXPECT_EQ(limit_excess(range, 0.0), 0.0);
  EXPECT_EQ(limit_excess(range, 0.25), 0.0);  // on the limit is within it
  EXPECT_DOUBLE_EQ(limit_excess(range, 0.75), 0.5);
  EXPECT_DOUBLE_EQ(limit_excess(range, -1.5), -1.0);
  EXPECT_DOUBLE_EQ(limit_excess(locked, 0.4), 0.3);
  EXPECT_DOUBLE_EQ(limit_excess(locked, -0.4), -0.5);
}

// The elbow's forearm is a hinge about x in the exact and implicit schemes: its angle is the
// hinge's, and a turn off the hinge (about y) is read on the locked axis it turns, as a ball's
// rotation vector reads it.
TEST(JointAngles, AHingeReadsItsAngleAndItsTurnOffTheHinge) {
  const Rig rig = load_rig(test::model_path("rigs/elbow.json"));
  ASSERT_EQ(rig.bone_joint_type[1], JointType::kHinge);
  Pose pose = rest_pose(rig);
  std::vector<Vec3> angles, excess;
  pose.bone_local_rotation[1] = about(-120, Vec3::UnitX());
  joint_angles_and_excess(rig, LockedAxes::kRemoved, pose, angles, excess);
  EXPECT_TRUE(test::near(angles[1], deg2rad(1.0) * Vec3(-120, 0, 0), 1e-12));
  EXPECT_TRUE(test::near(excess[1], deg2rad(1.0) * Vec3(-30, 0, 0), 1e-12));
  // bent 45 deg, then turned 15 deg about its own y: 15 deg past the locked y
  pose.bone_local_rotation[1] = about(-45, Vec3::UnitX()) * about(15, Vec3::UnitY());
  joint_angles_and_excess(rig, LockedAxes::kRemoved, pose, angles, excess);
  EXPECT_TRUE(test::near(angles[1], deg2rad(1.0) * Vec3(-45, 15, 0), 1e-12));
  EXPECT_NEAR(rad2deg(max_limit_violation(rig, LockedAxes::kRemoved, pose)), 15.0, 1e-9);
  EXPECT_NEAR(max_limit_violation(rig, LockedAxes::kRemoved, pose),
              off_joint_set(rig, 1, pose.bone_local_rotation[1]), 1e-12);
}

// A wrist: a universal joint (x then y free, z locked at 0). Bent and turned on its own two axes
// it is on its set, and its angles are its coordinates, with no excess on the locked z; the
// rotation vector of the same rotation has a z component of several degrees, which the paper's
// scheme's springs (kSprings, a ball) do read and pull on. Turned off its set about its own z
// by c, the locked axis reads c.
TEST(JointAngles, AUniversalJointIsOnItsSetWhereTheRotationVectorSaysNot) {
  Rig rig = load_rig(test::model_path("rigs/elbow.json"));
  rig.bone_limit[1][1] = AxisLimit{true, deg2rad(-60), deg2rad(60)};
  refresh_joint_model(rig);
  ASSERT_EQ(rig.bone_joint_type[1], JointType::kUniversal);
  const auto& axes = rig.bone_joint_axes[1];
  Vec3 e[3] = {Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitZ()};
  const Vec3 expected(-50, 40, 0);  // deg, x within [-90, 0], y within [-60, 60]
  const double t0 = expected[axes[0]], t1 = expected[axes[1]];
  Pose pose = rest_pose(rig);
  pose.bone_local_rotation[1] = about(t0, e[axes[0]]) * about(t1, e[axes[1]]);
  std::vector<Vec3> angles, excess;
  joint_angles_and_excess(rig, LockedAxes::kRemoved, pose, angles, excess);
  EXPECT_TRUE(test::near(angles[1], deg2rad(1.0) * expected, 1e-12)) << angles[1].transpose();
  EXPECT_EQ(max_limit_violation(rig, LockedAxes::kRemoved, pose), 0.0);
  EXPECT_GT(rad2deg(max_limit_violation(rig, LockedAxes::kSprings, pose)), 5.0);
  for (const double c : {-7.0, 3.0}) {
    pose.bone_local_rotation[1] = about(t0, e[axes[0]]) * about(t1, e[axes[1]]) * about(c, e[2]);
    joint_angles_and_excess(rig, LockedAxes::kRemoved, pose, angles, excess);
    EXPECT_TRUE(test::near(angles[1], deg2rad(1.0) * Vec3(expected.x(), expected.y(), c), 1e-12))
        << angles[1].transpose();
    EXPECT_NEAR(excess[1].z(), deg2rad(c), 1e-12);
  }
}

// A random pose: every bone turned about a random axis by up to 2.5 rad.
Pose random_pose(const Rig& rig, std::mt19937& rng) {
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> angle(0.0, 2.5);
  Pose pose = rest_pose(rig);
  for (Quat& q : pose.bone_local_rotation) {
    const Vec3 axis(normal(rng), normal(rng), normal(rng));
    q = Quat(Eigen::AngleAxisd(angle(rng), axis.normalized()));
  }
  return pose;
}

// Each bone's own spring torque in its limit axes, from the world torques apply_torsion_springs
// leaves: bone i's total is its own spring's torque minus those of its children's springs.
std::vector<Vec3> spring_torques_local(const Rig& rig, const SimState& s) {
  std::vector<Vec3> own = s.torque_world;
  // DFS order: every child comes after its parent, so backwards each own torque is complete
  for (int i = rig.nbone - 1; i >= 1; --i) own[rig.bone_parent[i]] += own[i];
  std::vector<Vec3> local(rig.nbone, Vec3::Zero());
  for (int i = 1; i < rig.nbone; ++i) {
    const Quat frame = s.frames.orient_world[rig.bone_parent[i]] * rig.bone_rest_orient_parent[i];
    local[i] = frame.conjugate() * own[i];
  }
  return local;
}

TEST(JointAngles, ExcessIsWhatTheTorsionSpringsMeasure) {
  const Rig rig = load_rig(test::model_path("rigs/pinhead.json"));
  EngineParams params = test::bare_params();
  params.torsion_k = 7.0;
  params.torsion_tolerance = 0.0;  // no engage band: the spring starts at the limit
  params.torsion_spring = SpringLaw::kLinear;
  params.torsion_torque = TorsionTorque::kAxes;  // the per-axis torque, not its gradient
  Scene scene = test::scene_for(rig, params);
  std::mt19937 rng(31);
  int outside = 0;
  for (int trial = 0; trial < 50; ++trial) {
    scene.initial_pose = random_pose(rig, rng);
    SimState s;
    init_state(scene, s);
    prepare_bodies(rig, params, s);  // clears the torques
    apply_torsion_springs(rig, params, s);
    const std::vector<Vec3> tau = spring_torques_local(rig, s);
    std::vector<Vec3> angles, excess;
    joint_angles_and_excess(rig, params.locked_axes(), s.pose, angles, excess);
    double largest = 0.0;
    for (int i = 0; i < rig.nbone; ++i) {
      EXPECT_TRUE(test::near(tau[i], -params.torsion_k * excess[i], 1e-9)) << "bone " << i;
      EXPECT_TRUE(test::near(angles[i], rotation_vector(s.pose.bone_local_rotation[i]), 0.0));
      largest = std::max(largest, excess[i].cwiseAbs().maxCoeff());
      outside += excess[i] != Vec3::Zero();
    }
    EXPECT_EQ(largest, max_limit_violation(rig, params.locked_axes(), s.pose));
  }
  EXPECT_GT(outside, 100);  // the random poses do pass limits (the comparison is not all zeros)
}

}  // namespace
}  // namespace physik
