// Rig construction: DFS order, joints, closed-form masses and inertias, the shipped rigs.
#include "physik/model/rig.h"

#include <limits>

#include <gtest/gtest.h>

#include "physik/io/rig_io.h"
#include "physik/model/errors.h"
#include "physik/model/rig_generators.h"
#include "tests/test_util.h"

namespace physik {
namespace {

TEST(Rig, PinheadCountsMatchThePaper) {
  const Rig rig = load_rig(test::model_path("rigs/pinhead.json"));
  EXPECT_EQ(rig.nbone, 18);
  EXPECT_EQ(rig.joints.size(), 14u);        // paper Sec. 4: 14 joints
  EXPECT_EQ(rig.max_bones_per_joint(), 4);  // at most 4 bones around a joint
  EXPECT_EQ(rig.bone_name[0], "head");      // the file roots the hierarchy at the head
}

TEST(Rig, PinheadLimbDegreesOfFreedom) {
  const Rig rig = load_rig(test::model_path("rigs/pinhead.json"));
  // paper: elbows and knees 1 DOF, collars and hips welded (0 DOF), shoulders/hips 3 DOF
  for (const char* b : {"forearm.L", "forearm.R", "shin.L", "shin.R"}) {
    EXPECT_EQ(rig.bone_dof(rig.find_bone(b)), 1) << b;
  }
  for (const char* b : {"collar.L", "collar.R", "hip.L", "hip.R"}) {
    EXPECT_EQ(rig.bone_dof(rig.find_bone(b)), 0) << b;
  }
  for (const char* b : {"upper_arm.L", "upper_arm.R", "thigh.L", "thigh.R"}) {
    EXPECT_EQ(rig.bone_dof(rig.find_bone(b)), 3) << b;
  }
}

TEST(Rig, ParentsComeBeforeChildren) {
  for (const char* f :
       {"rigs/pinhead.json", "rigs/hand.json", "rigs/elbow.json", "rigs/chain3.json"}) {
    const Rig rig = load_rig(test::model_path(f));
    EXPECT_EQ(rig.bone_parent[0], -1) << f;
    for (int i = 1; i < rig.nbone; ++i) {
      EXPECT_GE(rig.bone_parent[i], 0) << f;
      EXPECT_LT(rig.bone_parent[i], i) << f << " bone " << rig.bone_name[i];
    }
  }
}

TEST(Rig, DfsOrderIsRestoredFromAShuffledFile) {
  const Rig rig = rig_from_json_text(R"({"bones": [
    {"name": "c", "parent": "b", "head": [0,0,2], "tail": [0,0,3]},
    {"name": "a", "parent": null, "head": [0,0,0], "tail": [0,0,1]},
    {"name": "d", "parent": "a", "head": [0,0,1], "tail": [1,0,1]},
    {"name": "b", "parent": "a", "head": [0,0,1], "tail": [0,0,2]}]})",
                                     "shuffled.json");
  ASSERT_EQ(rig.nbone, 4);
  EXPECT_EQ(rig.bone_name[0], "a");
  // children keep file order: d before b, and c follows b in depth-first order
  EXPECT_EQ(rig.bone_name[1], "d");
  EXPECT_EQ(rig.bone_name[2], "b");
  EXPECT_EQ(rig.bone_name[3], "c");
  ASSERT_EQ(rig.joints.size(), 2u);
  EXPECT_EQ(rig.joints[0].nbone(), 3);  // a's tail with d and b
}

TEST(Rig, MassAndInertiaMatchClosedForms) {
  const Rig rig = load_rig(test::model_path("rigs/pinhead.json"));
  double total = 0.0;
  for (int i = 0; i < rig.nbone; ++i) {
    const double L = (rig.bone_rest_tail_world[i] - rig.bone_rest_head_world[i]).norm();
    const double m = 1.0 * L;  // mass_per_length 1
    const double r = 0.5;
    EXPECT_NEAR(rig.bone_mass[i], m, 1e-12);
    EXPECT_NEAR(rig.bone_inertia_local[i].x(), m * (3 * r * r + L * L) / 12.0, 1e-12);
    EXPECT_NEAR(rig.bone_inertia_local[i].y(), 0.5 * m * r * r, 1e-12);
    EXPECT_NEAR(rig.bone_inertia_local[i].z(), rig.bone_inertia_local[i].x(), 1e-15);
    total += m;
  }
  EXPECT_NEAR(rig.total_mass(), total, 1e-12);
}

TEST(Rig, TotalMassOverridesMassPerLength) {
  const Rig rig = rig_from_json_text(R"({"bones": [
    {"name": "a", "parent": null, "head": [0,0,0], "tail": [0,0,2], "mass": 3.0, "radius": 0.1}]})",
                                     "m.json");
  EXPECT_DOUBLE_EQ(rig.bone_mass[0], 3.0);
  EXPECT_NEAR(rig.bone_inertia_local[0].x(), 3.0 * (3 * 0.01 + 4.0) / 12.0, 1e-12);
  EXPECT_NEAR(rig.bone_inertia_local[0].y(), 0.5 * 3.0 * 0.01, 1e-12);
}

TEST(Rig, RollFrameFollowsBlender) {
  // +Y needs no turn; roll turns x and z about the bone
  const Mat3 f = rest_frame_from_roll(Vec3(0, 0, 0), Vec3(0, 2, 0), kPi / 2);
  EXPECT_TRUE(test::near(f.col(1), Vec3(0, 1, 0), 1e-12));
  EXPECT_TRUE(test::near(f.col(0), Vec3(0, 0, -1), 1e-12));
  // a bone along -Y turns 180 deg about Z, as Blender does
  const Mat3 g = rest_frame_from_roll(Vec3(0, 0, 0), Vec3(0, -1, 0), 0.0);
  EXPECT_TRUE(test::near(g.col(0), Vec3(-1, 0, 0), 1e-12));
  EXPECT_TRUE(test::near(g.col(1), Vec3(0, -1, 0), 1e-12));
}

TEST(Rig, ChainGenerator) {
  const Rig rig = make_chain_rig(50, 0.2);
  EXPECT_EQ(rig.nbone, 50);
  EXPECT_EQ(rig.joints.size(), 49u);
  EXPECT_EQ(rig.max_bones_per_joint(), 2);
  EXPECT_NEAR(rig.bone_rest_tail_world[49].z(), 10.0, 1e-12);
}

// ---------------------------------------------------------------- robustness

TEST(Rig, DepthIsTheInputsNotTheStacks) {
  // build_rig's DFS recursed once per level: a 300,000-bone chain overflowed the stack
  const Rig rig = make_chain_rig(300000, 1.0 / 1024);
  ASSERT_EQ(rig.nbone, 300000);
  EXPECT_EQ(rig.bone_parent[299999], 299998);
  EXPECT_EQ(static_cast<int>(rig.joints.size()), 299999);
  // a shuffled file still comes out parents first (the explicit stack keeps file order)
  std::vector<BoneSpec> specs;
  for (int i = 0; i < 5; ++i) {
    BoneSpec b;
    b.name = "b" + std::to_string(i);
    b.parent = i == 0 ? "" : i < 3 ? "b0" : "b1";  // b0 -> b1 (-> b3, b4), b2
    const Vec3 head = i == 0 ? Vec3(0, 0, 0) : i < 3 ? Vec3(0, 0, 1) : Vec3(0, i - 2.0, 2);
    b.head_world = head;
    b.tail_world = i == 0 ? Vec3(0, 0, 1) : i == 1 ? Vec3(0, 0, 2) : head + Vec3(1, 0, 0);
    b.rest_frame_world = rest_frame_from_roll(b.head_world, b.tail_world, 0.0);
    specs.push_back(b);
  }
  specs[3].head_world = Vec3(0, 0, 2);
  specs[4].head_world = Vec3(0, 0, 2);
  for (int i : {3, 4})
    specs[i].rest_frame_world = rest_frame_from_roll(specs[i].head_world, specs[i].tail_world, 0.0);
  const Rig r = build_rig({specs[4], specs[2], specs[3], specs[1], specs[0]}, "shuffled");
  const std::vector<std::string> want = {"b0", "b2", "b1", "b4", "b3"};  // children in file order
  EXPECT_EQ(r.bone_name, want);
}

TEST(Rig, AbsurdSizesFailBeforeAllocating) {
  // 2^31 - 1 bones asked for about 600 GB before bad_alloc
  try {
    make_chain_rig(2147483647);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("field 'N'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("kMaxBones"), std::string::npos) << e.what();
  }
  EXPECT_THROW(make_chain_rig(3, std::numeric_limits<double>::infinity()), InputError);
  EXPECT_THROW(make_chain_rig(1000, 1e7), InputError);  // reaches past kMaxCoordinate
}

TEST(Rig, LengthScaleIsTheMeanBoneLength) {
  EXPECT_DOUBLE_EQ(make_chain_rig(300).length_scale(), 1.0);
  EXPECT_DOUBLE_EQ(make_chain_rig(3, 0.25).length_scale(), 0.25);
  const Rig pinhead = load_rig(test::model_path("rigs/pinhead.json"));
  double sum = 0.0;
  for (double l : pinhead.bone_length) sum += l;
  EXPECT_DOUBLE_EQ(pinhead.length_scale(), sum / pinhead.nbone);
}

}  // namespace
}  // namespace physik
