// Collision detection (physik/engine/collision.h): the ground's contacts and FCL's capsule pairs
// against closed forms; bones sharing a joint and excluded pairs never collide.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "physik/engine/collision.h"
#include "physik/engine/contacts.h"
#include "tests/contact_test_util.h"

namespace physik {
namespace {

using test::bone;
using test::floor_scene;
using test::lying_rod;
using test::u_rig;

TEST(Collision, GroundTouchesAtEachSunkenEnd) {
  Scene s = floor_scene(lying_rod(0.05), Scheme::kImplicit, 0.05);
  std::vector<Contact> c;
  CollisionWorld world;
  world.detect(s, forward_kinematics(s.rig, s.initial_pose), c);
  ASSERT_EQ(c.size(), 2u);
  for (const Contact& k : c) {
    EXPECT_NEAR(k.depth, 0.06 - 0.05, 1e-12);
    EXPECT_NEAR((k.normal_world - Vec3::UnitZ()).norm(), 0.0, 1e-12);
    EXPECT_NEAR(k.point_world.z(), -0.005, 1e-12);  // midway between the sphere's bottom and 0
    EXPECT_EQ(k.other_bone, -1);
  }
  // a tilted plane through the origin: n = (0, 1, 1)/sqrt2, the ends at n . e = 0.05 / sqrt2
  s.collision.ground->normal_world = Vec3(0, 1, 1).normalized();
  world.detect(s, forward_kinematics(s.rig, s.initial_pose), c);
  ASSERT_EQ(c.size(), 2u);
  EXPECT_NEAR(c[0].depth, 0.06 - 0.05 / std::sqrt(2.0), 1e-12);
}

TEST(Collision, CapsulePairsByFclSkipSharedJointsAndExclusions) {
  // post and leg 0.1 apart with radii 0.06: they overlap by 0.02, normal from leg to post (-x)
  Scene s = floor_scene(u_rig(0.1, 0.0, 0.06), Scheme::kImplicit, 0.05);
  s.collision.ground.reset();
  s.collision.self_collision = true;
  const BoneFrames f = forward_kinematics(s.rig, s.initial_pose);
  std::vector<Contact> c;
  CollisionWorld world;
  world.detect(s, f, c);
  ASSERT_EQ(c.size(), 1u);  // post-bar and bar-leg share a joint: only post-leg
  EXPECT_EQ(c[0].bone, 0);
  EXPECT_EQ(c[0].other_bone, 2);
  EXPECT_NEAR(c[0].depth, 0.02, 1e-12);
  EXPECT_NEAR((c[0].normal_world - Vec3(-1, 0, 0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(c[0].point_world.x(), 0.05, 1e-12);
  EXPECT_NEAR(penetration(s, c).max_depth_fraction, 0.02 / 0.06, 1e-12);
  s.collision.excluded_pairs = {{0, 2}};
  world.detect(s, f, c);
  EXPECT_TRUE(c.empty());
  s.collision.excluded_pairs.clear();
  s.collision.self_collision = false;
  world.detect(s, f, c);
  EXPECT_TRUE(c.empty());
}

TEST(Collision, SiblingsShareAJoint) {
  const Rig rig = build_rig({bone("root", "", Vec3(0, 0, 0), Vec3(0, 0, 1)),
                             bone("a", "root", Vec3(0, 0, 1), Vec3(1, 0, 1.01)),
                             bone("b", "root", Vec3(0, 0, 1), Vec3(1, 0, 0.99))},
                            "v", "v");
  EXPECT_TRUE(rig.bones_share_joint(1, 2));
  EXPECT_TRUE(rig.bones_share_joint(0, 2));
  Scene s = test::scene_for(rig, EngineParams{}, 1);
  s.collision.self_collision = true;
  std::vector<Contact> c;
  CollisionWorld world;
  world.detect(s, forward_kinematics(rig, s.initial_pose), c);
  EXPECT_TRUE(c.empty());
}

}  // namespace
}  // namespace physik
