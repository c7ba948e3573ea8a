// Collision detection (physik/engine/collision.h): the ground's contacts and FCL's capsule pairs
// against closed forms; bones sharing a joint and excluded pairs never collide.
#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <fcl/geometry/shape/capsule.h>
#include <fcl/narrowphase/distance.h>
#include <gtest/gtest.h>

#include "physik/engine/collision.h"
#include "physik/engine/contact_data.h"
#include "physik/engine/gravity.h"
#include "physik/engine/ground_contacts.h"
#include "physik/engine/self_contacts.h"
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

// a 1 m rod along +x at height z (radius 0.06) and one box, no ground
Scene box_scene(double z, const BoxObstacle& box) {
  Scene s = floor_scene(lying_rod(z), Scheme::kImplicit, 0.05);
  s.collision.ground.reset();
  s.collision.obstacles = {box};
  return s;
}

std::vector<Contact> contacts_of(const Scene& s) {
  std::vector<Contact> c;
  CollisionWorld world;
  world.detect(s, forward_kinematics(s.rig, s.initial_pose), c);
  return c;
}

TEST(Collision, RodOnABoxTopTouchesAtBothEnds) {
  // the box's top at z = 0.5, the rod's centre line 0.05 above it: d = 0.06 - 0.05 at each end
  BoxObstacle box{"seat", Vec3(0.5, 0, 0.25), Vec3(1, 0.5, 0.25), Quat::Identity()};
  const std::vector<Contact> c = contacts_of(box_scene(0.55, box));
  ASSERT_EQ(c.size(), 2u);
  for (const Contact& k : c) {
    EXPECT_EQ(k.other_bone, -1);
    EXPECT_EQ(k.obstacle, 0);
    EXPECT_NEAR(k.depth, 0.01, 1e-12);
    EXPECT_NEAR((k.normal_world - Vec3::UnitZ()).norm(), 0.0, 1e-12);
    EXPECT_NEAR(k.point_world.z(), 0.495, 1e-12);  // midway: the sphere's bottom to the face
  }
  EXPECT_NEAR(c[0].point_world.x(), 0.0, 1e-12);
  EXPECT_NEAR(c[1].point_world.x(), 1.0, 1e-12);
  // lifted clear of the box (0.07 above): nothing; the box moved off to the side: nothing
  EXPECT_TRUE(contacts_of(box_scene(0.57, box)).empty());
  box.center_world.y() = 0.6;
  EXPECT_TRUE(contacts_of(box_scene(0.55, box)).empty());
}

TEST(Collision, RodAcrossARidgeTouchesAtItsDeepestPoint) {
  // a narrow box under the rod's middle: its ends hang off, one contact at x = 0.5
  const BoxObstacle narrow{"beam", Vec3(0.5, 0, 0.25), Vec3(0.2, 1, 0.25), Quat::Identity()};
  std::vector<Contact> c = contacts_of(box_scene(0.55, narrow));
  ASSERT_EQ(c.size(), 1u);
  EXPECT_NEAR(c[0].depth, 0.01, 1e-9);
  EXPECT_NEAR((c[0].normal_world - Vec3::UnitZ()).norm(), 0.0, 1e-6);
  EXPECT_GE(c[0].point_world.x(), 0.3 - 1e-9);
  EXPECT_LE(c[0].point_world.x(), 0.7 + 1e-9);
  // a box turned 45 degrees about y, its ridge (an edge along y) at z = 0.25 sqrt 2 under x = 0.5:
  // the rod 0.05 above the ridge touches it there, the normal straight up
  const double ridge = 0.25 * std::sqrt(2.0);
  BoxObstacle turned{"ridge", Vec3(0.5, 0, 0), Vec3(0.25, 1, 0.25),
                     Quat(Eigen::AngleAxisd(kPi / 4, Vec3::UnitY()))};
  c = contacts_of(box_scene(ridge + 0.05, turned));
  ASSERT_EQ(c.size(), 1u);
  EXPECT_NEAR(c[0].depth, 0.01, 1e-9);
  EXPECT_NEAR((c[0].normal_world - Vec3::UnitZ()).norm(), 0.0, 1e-6);
  EXPECT_NEAR(c[0].point_world.x(), 0.5, 1e-6);
  EXPECT_NEAR(c[0].point_world.z(), ridge - 0.005, 1e-9);  // midway: sphere bottom to ridge
}

TEST(Collision, RodSunkInABoxIsPushedOutOfTheNearestFace) {
  // the rod's centre line 0.1 below the top (0.5), far from the other faces: d = r + 0.1 at each
  // end, pushed up; the contact midway between the sphere's lowest point and the face
  const BoxObstacle box{"block", Vec3(0.5, 0, 0), Vec3(2, 2, 0.5), Quat::Identity()};
  const std::vector<Contact> c = contacts_of(box_scene(0.4, box));
  ASSERT_EQ(c.size(), 2u);
  for (const Contact& k : c) {
    EXPECT_NEAR(k.depth, 0.16, 1e-12);
    EXPECT_NEAR((k.normal_world - Vec3::UnitZ()).norm(), 0.0, 1e-12);
    EXPECT_NEAR(k.point_world.z(), 0.5 - 0.08, 1e-12);
  }
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

// a chain of `n` bones of length 0.1 and collision radius 0.04 on a random walk folded into a
// box of side 0.3: many bones overlap, turned every way
Rig crumpled_chain(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g;
  std::vector<BoneSpec> specs;
  Vec3 p = Vec3::Zero();
  for (int i = 0; i < n; ++i) {
    Vec3 q;
    do {
      q = p + 0.1 * Vec3(g(rng), g(rng), g(rng)).normalized();
    } while (q.cwiseAbs().maxCoeff() > 0.15);
    specs.push_back(bone("b" + std::to_string(i), i ? "b" + std::to_string(i - 1) : "", p, q));
    specs.back().collision_radius = 0.04;
    p = q;
  }
  return build_rig(specs, "crumpled", "crumpled");
}

// every overlapping pair by FCL's capsule distance over all pairs (no broad phase), (a, b) a < b
std::vector<std::pair<int, int>> overlapping_pairs(const Rig& rig, const BoneFrames& f) {
  std::vector<std::unique_ptr<fcl::CollisionObjectd>> o;
  for (int i = 0; i < rig.nbone; ++i) {
    auto shape = std::make_shared<fcl::Capsuled>(rig.bone_collision_radius[i], rig.bone_length[i]);
    fcl::Transform3d tf = fcl::Transform3d::Identity();
    // FCL's capsule axis is local z; the bone's is local y
    tf.linear() = f.orient_world[i].toRotationMatrix() *
                  Eigen::AngleAxisd(-0.5 * kPi, Vec3::UnitX()).toRotationMatrix();
    tf.translation() = 0.5 * (f.head_world[i] + f.tail_world[i]);
    o.push_back(std::make_unique<fcl::CollisionObjectd>(shape, tf));
  }
  std::vector<std::pair<int, int>> out;
  for (int a = 0; a < rig.nbone; ++a) {
    for (int b = a + 1; b < rig.nbone; ++b) {
      if (rig.bones_share_joint(a, b)) continue;
      fcl::DistanceResultd res;
      fcl::distance(o[a].get(), o[b].get(), fcl::DistanceRequestd(true), res);
      if (res.min_distance < -1e-12 * (rig.bone_collision_radius[a] + rig.bone_collision_radius[b]))
        out.emplace_back(a, b);
    }
  }
  return out;
}

std::vector<std::pair<int, int>> pairs_of(const std::vector<Contact>& c) {
  std::vector<std::pair<int, int>> out;
  for (const Contact& k : c) out.emplace_back(k.bone, k.other_bone);
  return out;
}

// the broad phase (the capsules' own boxes) finds every overlap that all pairs find, in order of
// (a, b), and a world asked again about a pose, or about another pose and back, answers as a new
// world does
TEST(Collision, BroadPhaseFindsEveryOverlapOfACrumpledChain) {
  for (unsigned seed : {1u, 2u, 3u}) {
    const Rig rig = crumpled_chain(80, seed);
    Scene s = test::scene_for(rig, EngineParams{}, 1);
    s.collision.self_collision = true;
    const BoneFrames f = forward_kinematics(rig, s.initial_pose);
    CollisionWorld world;
    std::vector<Contact> c;
    world.detect(s, f, c);
    const std::vector<std::pair<int, int>> all = overlapping_pairs(rig, f);
    EXPECT_GT(all.size(), 40u) << seed;  // the case is a crowded one
    EXPECT_EQ(pairs_of(c), all) << seed;
    // another pose (the chain turned 0.3 rad about y at its root), then the first again
    Pose turned = s.initial_pose;
    turned.bone_local_rotation[0] = Quat(Eigen::AngleAxisd(0.3, Vec3::UnitY()));
    const BoneFrames g = forward_kinematics(rig, turned);
    std::vector<Contact> c_turned, c_again, c_fresh;
    world.detect(s, g, c_turned);
    CollisionWorld().detect(s, g, c_fresh);
    EXPECT_EQ(pairs_of(c_turned), pairs_of(c_fresh)) << seed;
    world.detect(s, f, c_again);
    world.detect(s, f, c_fresh);
    ASSERT_EQ(c_again.size(), c.size());
    for (std::size_t i = 0; i < c.size(); ++i) {
      EXPECT_EQ(c_again[i].depth, c[i].depth);
      EXPECT_EQ(c_fresh[i].point_world, c[i].point_world);
    }
    // an exclusion changes the answer at the same pose
    s.collision.excluded_pairs = {all.front()};
    world.detect(s, f, c_again);
    EXPECT_EQ(c_again.size(), c.size() - 1) << seed;
  }
}

}  // namespace
}  // namespace physik
