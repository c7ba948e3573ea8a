// Forward kinematics: rest pose, rigid subtrees, joints meeting at one point, limits.
#include "physik/model/kinematics.h"
#include "physik/model/joint_angles.h"

#include <gtest/gtest.h>

#include "physik/io/rig_io.h"
#include "physik/model/rig_generators.h"
#include "tests/test_util.h"

namespace physik {
namespace {

class ShippedRigs : public ::testing::TestWithParam<const char*> {};

TEST_P(ShippedRigs, FkAtRestReproducesEveryHeadAndTail) {
  const Rig rig = load_rig(test::model_path(GetParam()));
  const BoneFrames f = forward_kinematics(rig, rest_pose(rig));
  for (int i = 0; i < rig.nbone; ++i) {
    EXPECT_TRUE(test::near(f.head_world[i], rig.bone_rest_head_world[i], 1e-12))
        << rig.bone_name[i];
    EXPECT_TRUE(test::near(f.tail_world[i], rig.bone_rest_tail_world[i], 1e-12))
        << rig.bone_name[i];
    EXPECT_LT(f.orient_world[i].angularDistance(rig.bone_rest_orient_world[i]), 1e-12);
  }
}

TEST_P(ShippedRigs, JointsMeetAtOnePointInAnyPose) {
  const Rig rig = load_rig(test::model_path(GetParam()));
  Pose pose = rest_pose(rig);
  std::srand(7);
  for (Quat& q : pose.bone_local_rotation) q = Quat::UnitRandom();
  pose.root_head_world = Vec3(0.3, -1.0, 2.0);
  const BoneFrames f = forward_kinematics(rig, pose);
  for (const Joint& j : rig.joints) {
    for (int c : j.children) {
      EXPECT_TRUE(test::near(f.head_world[c], f.tail_world[j.parent], 1e-12))
          << rig.bone_name[c] << " at " << rig.bone_name[j.parent];
    }
  }
  // bone lengths are kept
  for (int i = 0; i < rig.nbone; ++i) {
    EXPECT_NEAR((f.tail_world[i] - f.head_world[i]).norm(), rig.bone_length[i], 1e-12);
  }
}

TEST_P(ShippedRigs, LocalRotationsRoundTripThroughWorld) {
  const Rig rig = load_rig(test::model_path(GetParam()));
  Pose pose = rest_pose(rig);
  std::srand(11);
  for (Quat& q : pose.bone_local_rotation) q = Quat::UnitRandom();
  const BoneFrames f = forward_kinematics(rig, pose);
  Pose back;
  local_rotations_from_world(rig, f, back);
  for (int i = 0; i < rig.nbone; ++i) {
    EXPECT_LT(back.bone_local_rotation[i].angularDistance(pose.bone_local_rotation[i]), 1e-9);
  }
}

INSTANTIATE_TEST_SUITE_P(Rigs, ShippedRigs,
                         ::testing::Values("rigs/pinhead.json", "rigs/elbow.json",
                                           "rigs/chain3.json", "rigs/hand.json"));

TEST(Kinematics, RotatingAParentCarriesItsSubtreeRigidly) {
  const Rig rig = load_rig(test::model_path("rigs/pinhead.json"));
  const int upper = rig.find_bone("upper_arm.L");
  const BoneFrames rest = forward_kinematics(rig, rest_pose(rig));
  Pose pose = rest_pose(rig);
  const Quat turn(Eigen::AngleAxisd(0.7, Vec3(0.3, 1.0, -0.2).normalized()));
  pose.bone_local_rotation[upper] = turn;
  const BoneFrames f = forward_kinematics(rig, pose);

  // the same world motion for every bone of the subtree: a rotation about the shoulder
  const Vec3 shoulder = rest.head_world[upper];
  const Quat world_turn = f.orient_world[upper] * rest.orient_world[upper].conjugate();
  for (int i = 0; i < rig.nbone; ++i) {
    bool in_subtree = false;
    for (int a = i; a >= 0; a = rig.bone_parent[a]) in_subtree = in_subtree || a == upper;
    if (in_subtree) {
      EXPECT_TRUE(test::near(f.tail_world[i],
                             shoulder + world_turn * (rest.tail_world[i] - shoulder), 1e-12))
          << rig.bone_name[i];
      EXPECT_LT(f.orient_world[i].angularDistance(world_turn * rest.orient_world[i]), 1e-12);
    } else {
      EXPECT_TRUE(test::near(f.tail_world[i], rest.tail_world[i], 1e-15)) << rig.bone_name[i];
    }
  }
  EXPECT_NEAR(world_turn.angularDistance(Quat::Identity()), 0.7, 1e-12);
}

TEST(Kinematics, RotationVectorAndLimitViolation) {
  const Quat q(Eigen::AngleAxisd(0.5, Vec3::UnitX()));
  EXPECT_TRUE(test::near(rotation_vector(q), Vec3(0.5, 0, 0), 1e-12));
  // the other hemisphere gives the same vector
  const Quat neg(-q.w(), -q.x(), -q.y(), -q.z());
  EXPECT_TRUE(test::near(rotation_vector(neg), Vec3(0.5, 0, 0), 1e-12));

  const Rig rig = load_rig(test::model_path("rigs/elbow.json"));  // forearm x in [-90, 0] deg
  Pose pose = rest_pose(rig);
  EXPECT_DOUBLE_EQ(max_limit_violation(rig, LockedAxes::kSprings, pose), 0.0);
  pose.bone_local_rotation[1] = Quat(Eigen::AngleAxisd(deg2rad(-100), Vec3::UnitX()));
  EXPECT_NEAR(rad2deg(max_limit_violation(rig, LockedAxes::kSprings, pose)), 10.0, 1e-9);
}

TEST(Kinematics, CenterOfMassOfAStraightChain) {
  const Rig rig = make_chain_rig(4, 0.5);
  const BoneFrames f = forward_kinematics(rig, rest_pose(rig));
  EXPECT_TRUE(test::near(center_of_mass(rig, f), Vec3(0, 0, 1.0), 1e-12));
}

}  // namespace
}  // namespace physik
