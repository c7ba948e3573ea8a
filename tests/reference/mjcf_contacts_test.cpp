// The MJCF export with contacts (reference/mjcf_export.h mjcf_contacts): MuJoCo, on the exported
// model, finds contacts between exactly the shape pairs PhysIK's detection finds (collision.h):
// parent and child filtered by MuJoCo's filterparent, two children of one parent and the scene's
// excluded pairs by <exclude>, the ground plane and the static boxes where PhysIK has them, and
// the scene's gravity.
#include <algorithm>
#include <cmath>
#include <set>
#include <utility>

#include <gtest/gtest.h>

#include "physik/engine/collision.h"
#include "physik/engine/engine.h"
#include "reference/mjcf_export.h"
#include "reference/mujoco_runner.h"
#include "tests/contact_test_util.h"

namespace physik {
namespace {

using test::bone;

using Pairs = std::set<std::pair<int, int>>;  // (bone, other bone or -1 for the ground)

Pairs physik_pairs(const Scene& s) {
  std::vector<Contact> contacts;
  CollisionWorld world;
  world.detect(s, forward_kinematics(s.rig, s.initial_pose), contacts);
  Pairs out;
  for (const Contact& c : contacts) {
    out.insert(c.other_bone < 0 ? std::make_pair(c.bone, -1)
                                : std::pair<int, int>(std::minmax(c.bone, c.other_bone)));
  }
  return out;
}

Pairs mujoco_pairs(const Scene& s) {
  MjcfOptions o;
  o.joints = JointModel::kBallJoints;
  MjModelPtr m = rig_to_mjmodel(s.rig, mjcf_contacts(s, o));
  MjDataPtr d(mj_makeData(m.get()));
  SimState st;
  init_state(s, st);
  set_mujoco_state(s.rig, st, m.get(), d.get());
  mj_forward(m.get(), d.get());
  Pairs out;
  for (int k = 0; k < d->ncon; ++k) {
    const int a = m->geom_bodyid[d->contact[k].geom1] - 1;  // body b = bone b - 1; world: -1
    const int b = m->geom_bodyid[d->contact[k].geom2] - 1;
    out.insert(a < 0 || b < 0 ? std::make_pair(std::max(a, b), -1)
                              : std::pair<int, int>(std::minmax(a, b)));
  }
  EXPECT_EQ(m->opt.gravity[2], s.gravity_world.z());
  return out;
}

TEST(MjcfContacts, MuJoCoTouchesTheSamePairs) {
  // a U (post and leg 0.1 apart: they overlap) and, on the post's top, a second bar whose
  // sibling overlaps it; the leg's foot sinks into the ground
  const Rig rig = build_rig({bone("post", "", Vec3(0, 0, 0.2), Vec3(0, 0, 1)),
                             bone("bar", "post", Vec3(0, 0, 1), Vec3(0.1, 0, 1)),
                             bone("leg", "bar", Vec3(0.1, 0, 1), Vec3(0.1, 0, 0.03)),
                             bone("twin", "post", Vec3(0, 0, 1), Vec3(0.1, 0, 1.02))},
                            "u", "u");
  Scene s = test::scene_for(rig, EngineParams{}, 1);
  s.gravity_world = Vec3(0, 0, -9.81);
  s.collision.ground = GroundPlane{};
  s.collision.self_collision = true;
  const Pairs expected = {{0, 2}, {2, -1}, {2, 3}};  // post-leg, leg-ground, leg-twin
  EXPECT_EQ(physik_pairs(s), expected);
  EXPECT_EQ(mujoco_pairs(s), expected);
  s.collision.excluded_pairs = {{2, 3}};
  EXPECT_EQ(physik_pairs(s), (Pairs{{0, 2}, {2, -1}}));
  EXPECT_EQ(mujoco_pairs(s), (Pairs{{0, 2}, {2, -1}}));
  s.collision.self_collision = false;  // the ground alone
  s.collision.excluded_pairs.clear();
  EXPECT_EQ(physik_pairs(s), (Pairs{{2, -1}}));
  EXPECT_EQ(mujoco_pairs(s), (Pairs{{2, -1}}));
}

TEST(MjcfContacts, MuJoCoTouchesTheSameBoxAtTheSameDepth) {
  // a rod 0.05 above a turned box's top (radius 0.06: 0.01 deep): MuJoCo's static box geom
  // touches it at the same depth; moved 0.02 higher, neither touches
  Scene s = test::scene_for(test::lying_rod(0.55), EngineParams{}, 1);
  s.collision.obstacles = {BoxObstacle{"seat", Vec3(0.5, 0, 0.25), Vec3(0.75, 0.5, 0.25),
                                       Quat(Eigen::AngleAxisd(0.3, Vec3::UnitZ()))}};
  EXPECT_EQ(physik_pairs(s), (Pairs{{0, -1}}));
  EXPECT_EQ(mujoco_pairs(s), (Pairs{{0, -1}}));
  MjcfOptions o;
  o.joints = JointModel::kBallJoints;
  const std::string xml = rig_to_mjcf(s.rig, mjcf_contacts(s, o));
  EXPECT_NE(xml.find("name=\"obstacle:seat\" type=\"box\" size=\"0.75 0.5 0.25\""),
            std::string::npos)
      << xml;
  MjModelPtr m = rig_to_mjmodel(s.rig, mjcf_contacts(s, o));
  MjDataPtr d(mj_makeData(m.get()));
  SimState st;
  init_state(s, st);
  set_mujoco_state(s.rig, st, m.get(), d.get());
  mj_forward(m.get(), d.get());
  ASSERT_GT(d->ncon, 0);
  for (int k = 0; k < d->ncon; ++k) EXPECT_NEAR(d->contact[k].dist, -0.01, 1e-9);
  s.collision.obstacles[0].center_world.z() -= 0.02;
  EXPECT_TRUE(physik_pairs(s).empty());
  EXPECT_TRUE(mujoco_pairs(s).empty());
}

TEST(MjcfContacts, WithoutContactsTheModelIsAsBefore) {
  const Rig rig = build_rig({bone("a", "", Vec3(0, 0, 0), Vec3(0, 0, 1))}, "a", "a");
  const std::string plain = rig_to_mjcf(rig, MjcfOptions{});
  EXPECT_NE(plain.find("<flag contact=\"disable\"/>"), std::string::npos);
  EXPECT_NE(plain.find("gravity=\"0 0 0\""), std::string::npos);
  EXPECT_EQ(plain.find("plane"), std::string::npos);
}

// MuJoCo's buffers count the boxes a bone can touch at once (mjcf_export.h MjcfSize), not every
// box: a two-bone arm of 1 m bones over 100 boxes of half extent 0.5 in a row 10 apart touches
// one at a time (16 contact rows, where every box counted gave 1,600: njmax 1,617 for the elbow
// and 11,133 for the pinhead, which MuJoCo could not allocate under a 6 GB address space); the
// same boxes at one place, all 100.
TEST(MjcfContacts, BuffersCountTheBoxesABoneCanTouchAtOnce) {
  const Rig rig = build_rig(
      {bone("a", "", Vec3(0, 0, 0), Vec3(0, 0, 1)), bone("b", "a", Vec3(0, 0, 1), Vec3(0, 0, 2))},
      "arm", "arm");
  const auto boxes = [](double spacing, int cluster) {
    MjcfOptions o;
    for (int i = 0; i < 100; ++i) {
      BoxObstacle b;
      b.name = "box" + std::to_string(i);
      b.center_world = Vec3(3.0 + spacing * (i / cluster), 0.0, 0.0);
      b.half_extents = Vec3::Constant(0.5);
      o.collision.obstacles.push_back(b);
    }
    o.joints = JointModel::kBallJoints;
    return o;
  };
  const int n = rig.nbone;
  EXPECT_EQ(mjcf_size(rig, boxes(10.0, 1)).rows_needed, 4 * 2 * n * 1);
  EXPECT_EQ(mjcf_size(rig, boxes(10.0, 10)).rows_needed, 4 * 2 * n * 10);  // 10 piles of 10
  EXPECT_EQ(mjcf_size(rig, boxes(0.0, 1)).rows_needed, 4 * 2 * n * 100);
  // 2 apart: a box's bounding sphere (radius 0.87) reaches its neighbours' within the bones'
  // extent (a bone's length and diameter) on both sides: 2 K + 1 at once, itself among them
  const double extent = 1.0 + 2.0 * rig.bone_collision_radius[0];
  const int k = static_cast<int>((extent + 2.0 * std::sqrt(0.75)) / 2.0);
  ASSERT_GE(k, 1);
  EXPECT_EQ(mjcf_size(rig, boxes(2.0, 1)).rows_needed, 4 * 2 * n * (2 * k + 1));
}

}  // namespace
}  // namespace physik
