// BVH / qBVH: Euler orders against hand-computed rotations, export -> import round trips, the
// BVH -> rig mapping reproducing the file's joint positions, and every malformed-input case.
#include "physik/io/bvh.h"

#include <limits>
#include <random>
#include <sstream>

#include <gtest/gtest.h>

#include "physik/io/rig_io.h"
#include "physik/model/errors.h"
#include "physik/model/rig_generators.h"
#include "test_util.h"

namespace physik {
namespace {

using test::near;

// a one-joint file: ROOT at the origin, rotation channels only, an End Site at (1, 2, 3)
std::string one_joint(const std::string& channels, const std::string& values) {
  return "HIERARCHY\nROOT A\n{\n  OFFSET 0 0 0\n  CHANNELS 3 " + channels +
         "\n  End Site\n  {\n    OFFSET 1 2 3\n  }\n}\nMOTION\nFrames: 1\nFrame Time: 0.04\n" +
         values + "\n";
}

// Channel values 90, 90, 180 (deg) in file order; R = R_first(90) R_second(90) R_third(180)
// applied to v = (1, 2, 3), worked by hand with Rx90 (x, -z, y), Ry90 (z, y, -x), Rz90 (-y, x, z)
// and R*180 negating the two other components.
TEST(BvhEuler, EachChannelOrderMatchesHandComputedRotation) {
  const struct {
    const char* channels;
    Vec3 tail;
  } cases[] = {
      {"Xrotation Yrotation Zrotation", Vec3(3, -1, -2)},
      {"Xrotation Zrotation Yrotation", Vec3(-2, 3, -1)},
      {"Yrotation Xrotation Zrotation", Vec3(-2, -3, 1)},
      {"Yrotation Zrotation Xrotation", Vec3(-3, 1, -2)},
      {"Zrotation Xrotation Yrotation", Vec3(-3, -1, 2)},
      {"Zrotation Yrotation Xrotation", Vec3(2, -3, -1)},
  };
  BvhImportOptions opt;
  opt.axes = BvhAxes::kZUp;
  for (const auto& c : cases) {
    SCOPED_TRACE(c.channels);
    const BvhAnimation anim =
        bvh_to_rig(parse_bvh(one_joint(c.channels, "90 90 180"), "t.bvh"), "t.bvh", opt);
    ASSERT_EQ(anim.rig().nbone, 1);
    ASSERT_EQ(anim.poses.size(), 1u);
    EXPECT_EQ(anim.rig().bone_name[0], "A");
    EXPECT_TRUE(near(anim.rig().bone_rest_tail_world[0], Vec3(1, 2, 3), 1e-12));
    const BoneFrames f = forward_kinematics(anim.rig(), anim.poses[0]);
    EXPECT_TRUE(near(f.head_world[0], Vec3::Zero(), 1e-12));
    EXPECT_TRUE(near(f.tail_world[0], c.tail, 1e-9));
  }
}

TEST(BvhEuler, DecompositionRecomposesForEveryOrderIncludingGimbalLock) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-kPi, kPi);
  for (const char* order : {"XYZ", "XZY", "YXZ", "YZX", "ZXY", "ZYX"}) {
    SCOPED_TRACE(order);
    for (int k = 0; k < 200; ++k) {
      Vec3 e(u(rng), u(rng) / 2, u(rng));
      if (k % 10 == 0) e[1] = (k % 20 == 0 ? 1 : -1) * kPi / 2;  // gimbal lock
      const Quat q = rotation_from_euler(e, order);
      const Vec3 back = euler_from_rotation(q, order);
      EXPECT_LE(std::abs(back[1]), kPi / 2 + 1e-12);
      EXPECT_LT(rotation_from_euler(back, order).angularDistance(q), 1e-9);
    }
  }
  EXPECT_THROW(euler_from_rotation(Quat::Identity(), "XXY"), InputError);
}

// random poses of a rig: every bone turned by up to ~100 deg, the root moved
std::vector<Pose> random_poses(const Rig& rig, int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<Pose> poses;
  for (int f = 0; f < n; ++f) {
    Pose p = rest_pose(rig);
    p.root_head_world += Vec3(g(rng), g(rng), g(rng));
    for (Quat& q : p.bone_local_rotation) {
      const Vec3 v(g(rng), g(rng), g(rng));
      q = Quat(Eigen::AngleAxisd(v.norm(), v.normalized()));
    }
    poses.push_back(p);
  }
  return poses;
}

void expect_same_world_positions(const Rig& a, const std::vector<Pose>& pa, const Rig& b,
                                 const std::vector<Pose>& pb, double tol) {
  ASSERT_EQ(pa.size(), pb.size());
  ASSERT_EQ(a.nbone, b.nbone);
  for (std::size_t f = 0; f < pa.size(); ++f) {
    const BoneFrames fa = forward_kinematics(a, pa[f]);
    const BoneFrames fb = forward_kinematics(b, pb[f]);
    for (int i = 0; i < a.nbone; ++i) {
      const int j = b.find_bone(a.bone_name[i]);
      ASSERT_GE(j, 0) << a.bone_name[i];
      EXPECT_TRUE(near(fa.head_world[i], fb.head_world[j], tol))
          << a.bone_name[i] << " frame " << f;
      EXPECT_TRUE(near(fa.tail_world[i], fb.tail_world[j], tol))
          << a.bone_name[i] << " frame " << f;
    }
  }
}

class BvhRoundTrip : public ::testing::TestWithParam<std::tuple<bool, BvhAxes, const char*>> {};

TEST_P(BvhRoundTrip, ExportThenImportGivesTheSameWorldPositions) {
  const auto [quaternion, axes, order] = GetParam();
  const Rig rig = load_rig(test::model_path("rigs/pinhead.json"));
  const std::vector<Pose> poses = random_poses(rig, 12, 3);
  BvhExportOptions eo;
  eo.quaternion = quaternion;
  eo.axes = axes;
  eo.euler_order = order;
  eo.frame_time = 0.05;
  std::ostringstream out;
  write_bvh(rig, poses, eo, out);
  BvhImportOptions io;
  io.axes = axes;
  const BvhAnimation anim = bvh_to_rig(parse_bvh(out.str(), "mem.bvh"), "mem.bvh", io);
  EXPECT_NEAR(anim.frame_time, 0.05, 1e-12);
  EXPECT_LT(anim.max_position_error, 1e-9);
  // same bones, same parents, same rest positions
  ASSERT_EQ(anim.rig().nbone, rig.nbone);
  for (int i = 0; i < rig.nbone; ++i) {
    const int j = anim.rig().find_bone(rig.bone_name[i]);
    ASSERT_GE(j, 0);
    const int p = anim.rig().bone_parent[j];
    EXPECT_EQ(p < 0 ? "" : anim.rig().bone_name[p],
              rig.bone_parent[i] < 0 ? "" : rig.bone_name[rig.bone_parent[i]]);
    EXPECT_TRUE(near(anim.rig().bone_rest_tail_world[j], rig.bone_rest_tail_world[i], 1e-9));
  }
  expect_same_world_positions(rig, poses, anim.rig(), anim.poses, 1e-6);
}

INSTANTIATE_TEST_SUITE_P(Formats, BvhRoundTrip,
                         ::testing::Values(std::make_tuple(false, BvhAxes::kYUp, "ZXY"),
                                           std::make_tuple(false, BvhAxes::kZUp, "XYZ"),
                                           std::make_tuple(false, BvhAxes::kYUp, "YZX"),
                                           std::make_tuple(true, BvhAxes::kYUp, "ZXY"),
                                           std::make_tuple(true, BvhAxes::kZUp, "ZXY")));

// A typical mocap hierarchy: a root with three children at different offsets, a joint with two
// children, a zero-offset child, two End Sites at one joint, position channels on the root.
const char* kBranchy = R"(HIERARCHY
ROOT Hips
{
  OFFSET 1 2 3
  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation
  JOINT Spine
  {
    OFFSET 0 5 0
    CHANNELS 3 Zrotation Xrotation Yrotation
    JOINT Chest
    {
      OFFSET 0 5 0
      CHANNELS 3 Zrotation Xrotation Yrotation
      JOINT Neck
      {
        OFFSET 0 3 1
        CHANNELS 3 Zrotation Xrotation Yrotation
        End Site
        {
          OFFSET 0 2 0
        }
      }
      JOINT LeftArm
      {
        OFFSET 4 2 0
        CHANNELS 3 Zrotation Xrotation Yrotation
        JOINT LeftArmRoll
        {
          OFFSET 0 0 0
          CHANNELS 3 Zrotation Xrotation Yrotation
          End Site
          {
            OFFSET 6 0 0
          }
          End Site
          {
            OFFSET 6 1 0
          }
        }
      }
    }
  }
  JOINT LeftUpLeg
  {
    OFFSET 2 -1 0
    CHANNELS 3 Zrotation Xrotation Yrotation
    End Site
    {
      OFFSET 0 -8 0
    }
  }
  JOINT RightUpLeg
  {
    OFFSET -2 -1 0
    CHANNELS 3 Zrotation Xrotation Yrotation
    End Site
    {
      OFFSET 0 -8 0
    }
  }
}
MOTION
Frames: 3
Frame Time: 0.0333333
1 2 3 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0
4 5 6 10 20 30 -40 50 60 70 -80 90 10 10 10 -170 100 30 15 -25 35 45 55 65 -75 85 -95
-3 0.5 7 179 -89 45 12 34 56 -78 90 12 33 44 55 66 77 88 99 -11 22 33 -44 55 66 -77 88
)";

TEST(BvhImport, BranchingHierarchyReproducesEveryJointAndEndSite) {
  BvhImportOptions opt;
  opt.axes = BvhAxes::kYUp;
  const BvhFile bvh = parse_bvh(kBranchy, "branchy.bvh");
  ASSERT_EQ(bvh.joints.size(), 8u);
  EXPECT_EQ(bvh.nchannel, 27);
  const BvhAnimation anim = bvh_to_rig(bvh, "branchy.bvh", opt);
  const Rig& rig = anim.rig();
  // synthetic root Hips + Hips>Spine, Hips>LeftUpLeg, Hips>RightUpLeg, Spine, Chest>Neck,
  // Chest>LeftArm, Neck, LeftArmRoll>end, LeftArmRoll>end2 (LeftArm has a zero-length segment),
  // LeftUpLeg, RightUpLeg
  EXPECT_TRUE(anim.pivots.synthetic_root);
  EXPECT_EQ(rig.nbone, 12);
  for (const char* n : {"Hips", "Hips>Spine", "Hips>LeftUpLeg", "Hips>RightUpLeg", "Spine",
                        "Chest>Neck", "Chest>LeftArm", "Neck", "LeftArmRoll>end",
                        "LeftArmRoll>end2", "LeftUpLeg", "RightUpLeg"}) {
    EXPECT_GE(rig.find_bone(n), 0) << n;
  }
  // the arm roll bones hang from Chest>LeftArm (LeftArm's own bone has zero length)
  EXPECT_EQ(rig.bone_parent[rig.find_bone("LeftArmRoll>end")], rig.find_bone("Chest>LeftArm"));
  // the root rest: a bone ending at the Hips joint (Y up: file (1,2,3) -> rig (1,-3,2))
  EXPECT_TRUE(near(rig.bone_rest_tail_world[0], Vec3(1, -3, 2), 1e-12));
  EXPECT_LT(anim.max_position_error, 1e-9);

  // independent check against the reference FK in file axes, mapped to rig axes
  const Quat a = bvh_axes_to_rig(BvhAxes::kYUp);
  std::vector<Quat> rot;
  std::vector<Vec3> pos;
  for (int f = 0; f < 3; ++f) {
    bvh_world(bvh, f, rot, pos);
    const BoneFrames fk = forward_kinematics(rig, anim.poses[f]);
    EXPECT_TRUE(near(fk.tail_world[rig.find_bone("Hips")], a * pos[0], 1e-9));
    EXPECT_TRUE(near(fk.tail_world[rig.find_bone("Spine")], a * pos[2], 1e-9));  // Chest
    EXPECT_TRUE(near(fk.tail_world[rig.find_bone("Chest>Neck")], a * pos[3], 1e-9));
    EXPECT_TRUE(
        near(fk.tail_world[rig.find_bone("Neck")], a * (pos[3] + rot[3] * Vec3(0, 2, 0)), 1e-9));
    EXPECT_TRUE(near(fk.tail_world[rig.find_bone("LeftArmRoll>end2")],
                     a * (pos[5] + rot[5] * Vec3(6, 1, 0)), 1e-9));
    EXPECT_TRUE(near(fk.tail_world[rig.find_bone("Hips>RightUpLeg")], a * pos[7], 1e-9));
  }
  // frame 0: root at (1,2,3) with all rotations zero = the rest pose
  const BoneFrames f0 = forward_kinematics(rig, anim.poses[0]);
  for (int i = 0; i < rig.nbone; ++i) {
    EXPECT_TRUE(near(f0.tail_world[i], rig.bone_rest_tail_world[i], 1e-9)) << rig.bone_name[i];
  }

  // and it survives export -> import as BVH and as qBVH (bone names and positions kept)
  for (bool q : {false, true}) {
    BvhExportOptions eo;
    eo.quaternion = q;
    std::ostringstream out;
    write_bvh(rig, anim.poses, eo, out);
    const BvhAnimation back = bvh_to_rig(parse_bvh(out.str(), "back.bvh"), "back.bvh", opt);
    EXPECT_EQ(back.rig().nbone, rig.nbone);
    expect_same_world_positions(rig, anim.poses, back.rig(), back.poses, 1e-6);
  }
}

TEST(BvhImport, NonRootPositionChannelsThatMoveAreReportedNotHidden) {
  const std::string text =
      "HIERARCHY\nROOT R\n{\nOFFSET 0 0 0\nCHANNELS 3 Xposition Yposition Zposition\n"
      "JOINT C\n{\nOFFSET 0 1 0\nCHANNELS 4 Xposition Yposition Zposition Xrotation\n"
      "End Site\n{\nOFFSET 0 1 0\n}\n}\n}\nMOTION\nFrames: 2\nFrame Time: 0.1\n"
      "0 0 0 0 1 0 0\n0 0 0 0 1.5 0 0\n";
  BvhImportOptions opt;
  opt.axes = BvhAxes::kZUp;
  const BvhAnimation anim = bvh_to_rig(parse_bvh(text, "t.bvh"), "t.bvh", opt);
  // frame 1 moves C 0.5 along its bone: a fixed-length rig cannot follow, and says so
  EXPECT_NEAR(anim.max_position_error, 0.5, 1e-9);
}

TEST(BvhRecorder, KeepsEveryNthCallAndScalesTheFrameTime) {
  const Rig rig = make_chain_rig(3);
  BvhRecorder rec(rig, 0.05, 4);
  const std::vector<Pose> poses = random_poses(rig, 10, 5);
  for (const Pose& p : poses) rec.record(forward_kinematics(rig, p));
  EXPECT_EQ(rec.recorded(), 3);  // calls 0, 4, 8
  std::ostringstream out;
  rec.write(out);
  BvhImportOptions io;
  const BvhAnimation anim = bvh_to_rig(parse_bvh(out.str(), "rec.bvh"), "rec.bvh", io);
  EXPECT_NEAR(anim.frame_time, 0.2, 1e-12);
  expect_same_world_positions(rig, {poses[0], poses[4], poses[8]}, anim.rig(), anim.poses, 1e-6);
  EXPECT_THROW(BvhRecorder(rig, 0.05, 0), InputError);
  EXPECT_TRUE(is_qbvh_path("a/b.QBVH"));
  EXPECT_FALSE(is_qbvh_path("a/b.bvh"));
}

// ---------------------------------------------------------------- malformed input

struct Bad {
  const char* what;
  std::string text;
  std::string expect;  // substring of the message
};

const std::string kHead =
    "HIERARCHY\nROOT A\n{\n  OFFSET 0 0 0\n  CHANNELS 3 Zrotation Xrotation Yrotation\n";
const std::string kSite = "  End Site\n  {\n    OFFSET 0 1 0\n  }\n";
const std::string kMotion1 = "MOTION\nFrames: 1\nFrame Time: 0.1\n";

// malformed structure: braces, channels, keywords
std::vector<Bad> structure_cases() {
  return {
      {"missing closing brace", kHead + kSite + kMotion1 + "1 2 3\n",
       "bad.bvh: line 10: field '}': unbalanced braces"},
      {"missing closing brace at EOF", kHead + kSite, "unbalanced braces"},
      {"extra closing brace", kHead + kSite + "}\n}\n" + kMotion1 + "1 2 3\n",
       "bad.bvh: line 11: field '}': unbalanced braces"},
      {"End Site not closed", kHead + "  End Site\n  {\n    OFFSET 0 1 0\n  JOINT B\n",
       "unbalanced braces"},
      {"channel count larger than names",
       "HIERARCHY\nROOT A\n{\nOFFSET 0 0 0\nCHANNELS 3 Zrotation Xrotation\n" + kSite + "}\n" +
           kMotion1 + "1 2\n",
       "line 6: field 'CHANNELS': the count says 3 but 2 channel names follow"},
      {"channel count smaller than names",
       "HIERARCHY\nROOT A\n{\nOFFSET 0 0 0\nCHANNELS 2 Zrotation Xrotation Yrotation\n" + kSite +
           "}\n" + kMotion1 + "1 2\n",
       "line 5: field 'CHANNELS': the count says 2 but more channel names follow"},
      {"unknown channel", "HIERARCHY\nROOT A\n{\nOFFSET 0 0 0\nCHANNELS 1 Wrotation\n}\n",
       "unknown channel 'Wrotation'"},
      {"data row shorter than channels", kHead + kSite + "}\n" + kMotion1 + "1 2\n",
       "bad.bvh: line 14: field 'MOTION': frame 0 has 2 values, the hierarchy has 3 channels"},
      {"data row longer than channels", kHead + kSite + "}\n" + kMotion1 + "1 2 3 4\n",
       "frame 0 has 4 values"},
      {"missing MOTION", kHead + kSite + "}\n", "missing MOTION"},
      {"missing HIERARCHY", "ROOT A\n{\n}\n", "expected HIERARCHY"},
      {"second ROOT", kHead + kSite + "}\nROOT B\n{\n}\n", "a second ROOT"},
      {"missing OFFSET",
       "HIERARCHY\nROOT A\n{\nCHANNELS 3 Zrotation Xrotation Yrotation\n}\n" + kMotion1 + "1 2 3\n",
       "has no OFFSET"},
      {"unknown keyword", "HIERARCHY\nROOT A\n{\nOFFSET 0 0 0\nBONE x\n}\n",
       "line 5: field 'BONE': unknown keyword"},
  };
}

// malformed values: numbers, frame counts, quaternions
std::vector<Bad> value_cases() {
  return {
      {"fewer frames than Frames:",
       kHead + kSite + "}\nMOTION\nFrames: 3\nFrame Time: 0.1\n1 2 3\n1 2 3\n",
       "line 12: field 'Frames': says 3 frames but the file has 2"},
      {"more frames than Frames:", kHead + kSite + "}\n" + kMotion1 + "1 2 3\n1 2 3\n",
       "line 15: field 'Frames': more frames than 'Frames: 1'"},
      {"non-number in OFFSET", "HIERARCHY\nROOT A\n{\nOFFSET 0 x 0\n}\n",
       "line 4: field 'OFFSET': 'x' is not a number"},
      {"non-number in MOTION", kHead + kSite + "}\n" + kMotion1 + "1 abc 3\n",
       "line 14: field 'MOTION': 'abc' is not a number"},
      {"NaN in MOTION", kHead + kSite + "}\n" + kMotion1 + "1 nan 3\n",
       "line 14: field 'MOTION': 'nan' is not a finite number"},
      {"infinity in OFFSET", "HIERARCHY\nROOT A\n{\nOFFSET 0 inf 0\n}\n",
       "'inf' is not a finite number"},
      {"overflow in MOTION", kHead + kSite + "}\n" + kMotion1 + "1 1e999 3\n",
       "'1e999' is not a finite number"},
      // finite, but a turn of 1e308 degrees overflows in radians (the fuzzer's seed 9001 case)
      {"angle beyond +-1e6 degrees", kHead + kSite + "}\n" + kMotion1 + "1 1e308 3\n",
       "line 14: field 'MOTION': frame 0: joint 'A': Xrotation '1e308' is beyond +-1e6 degrees"},
      {"angle just beyond +-1e6 degrees", kHead + kSite + "}\n" + kMotion1 + "-1000000.5 0 3\n",
       "joint 'A': Zrotation '-1000000.5' is beyond +-1e6 degrees"},
      {"NaN frame time", kHead + kSite + "}\nMOTION\nFrames: 1\nFrame Time: NaN\n1 2 3\n",
       "line 13: field 'Frame Time'"},
      {"negative frame time", kHead + kSite + "}\nMOTION\nFrames: 1\nFrame Time: -1\n1 2 3\n",
       "must be positive"},
      {"bad frame count", kHead + kSite + "}\nMOTION\nFrames: two\nFrame Time: 0.1\n",
       "'two' is not a frame count"},
      {"quaternion not unit",
       "HIERARCHY\nROOT A\n{\nOFFSET 0 0 0\nCHANNELS 4 Wquaternion Xquaternion Yquaternion "
       "Zquaternion\n" +
           kSite + "}\n" + kMotion1 + "1 1 0 0\n",
       "line 14: field 'MOTION': joint 'A': quaternion norm"},
      {"three quaternion channels",
       "HIERARCHY\nROOT A\n{\nOFFSET 0 0 0\nCHANNELS 3 Wquaternion Xquaternion Yquaternion\n}\n",
       "all four quaternion channels"},
      {"Euler and quaternion mixed",
       "HIERARCHY\nROOT A\n{\nOFFSET 0 0 0\nCHANNELS 5 Xrotation Wquaternion Xquaternion "
       "Yquaternion Zquaternion\n}\n",
       "mixes Euler rotation and quaternion channels"},
      {"duplicate channel",
       "HIERARCHY\nROOT A\n{\nOFFSET 0 0 0\nCHANNELS 2 Xrotation Xrotation\n}\n", "listed twice"},
  };
}

TEST(BvhErrors, EveryMalformedInputNamesFileAndLine) {
  std::vector<Bad> cases = structure_cases();
  for (Bad& c : value_cases()) cases.push_back(std::move(c));
  for (const Bad& c : cases) {
    SCOPED_TRACE(c.what);
    try {
      parse_bvh(c.text, "bad.bvh");
      ADD_FAILURE() << "no error for: " << c.what;
    } catch (const InputError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(c.expect), std::string::npos) << msg;
      EXPECT_EQ(msg.rfind("bad.bvh: line ", 0), 0u) << msg;
      EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    }
  }
}

TEST(BvhErrors, MissingFileIsAnInputError) {
  EXPECT_THROW(read_bvh_file("/nonexistent/x.bvh"), InputError);
}

// ---------------------------------------------------------------- robustness

// a chain nested `depth` joints deep (or `siblings` End-Site joints under the root), 1 frame
std::string deep_bvh(int depth, int siblings = 0) {
  std::ostringstream s;
  s << "HIERARCHY\nROOT r\n{\nOFFSET 0 0 0\nCHANNELS 6 Xposition Yposition Zposition Zrotation "
       "Xrotation Yrotation\n";
  int nch = 6;
  for (int i = 0; i < depth; ++i) {
    s << "JOINT j" << i << "\n{\nOFFSET 0 1 0\nCHANNELS 3 Zrotation Xrotation Yrotation\n";
    nch += 3;
  }
  s << "End Site\n{\nOFFSET 0 1 0\n}\n";
  for (int i = 0; i < depth; ++i) s << "}\n";
  for (int i = 0; i < siblings; ++i) {
    s << "JOINT s\n{\nOFFSET " << (i % 2 ? 1 : -1) << " 0 0\nEnd Site\n{\nOFFSET 0 1 0\n}\n}\n";
  }
  s << "}\nMOTION\nFrames: 1\nFrame Time: 0.1\n";
  for (int k = 0; k < nch; ++k) s << (k ? " 0" : "0");
  s << "\n";
  return s.str();
}

std::string error_of(const std::string& text) {
  try {
    parse_bvh(text, "bad.bvh");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(BvhRobust, WhitespaceOnlyLinesAfterMotionAreBlankWhateverTheirWhitespace) {
  // a vertical tab or form feed alone on a line was a null dereference between MOTION and Frames:
  for (const char* ws : {"\v", "\f", " \v\f\t ", "\r"}) {
    const std::string text = kHead + kSite + "}\nMOTION\n" + ws + "\nFrames: 1\n" + ws +
                             "\nFrame Time: 0.1\n" + ws + "\n1 2 3\n" + ws + "\n";
    const BvhFile f = parse_bvh(text, "ws.bvh");
    ASSERT_EQ(f.frames.size(), 1u);
    EXPECT_EQ(f.frames[0][2], 3.0);
  }
  // a file that ends right after MOTION and a blank line names the missing field
  EXPECT_NE(error_of(kHead + kSite + "}\nMOTION\n\v\n").find("missing 'Frames:'"),
            std::string::npos);
}

TEST(BvhRobust, NestingDepthIsTheFilesNotTheStacks) {
  // 20,000 joints deep overflowed the stack of the recursive reader; now a 20,001-bone chain
  const int depth = 20000;
  const BvhAnimation anim = bvh_to_rig(parse_bvh(deep_bvh(depth), "deep.bvh"), "deep.bvh");
  ASSERT_EQ(anim.rig().nbone, depth + 1);
  EXPECT_EQ(anim.rig().bone_parent[depth], depth - 1);
  EXPECT_NEAR(anim.rig().bone_rest_tail_world[depth].z(), depth + 1.0, 1e-6);  // y up -> z up
  EXPECT_LT(anim.max_position_error, 1e-6);
  // and it writes back out (the writer walks the tree without recursion, indenting at most 32)
  std::ostringstream out;
  write_bvh(anim.rig(), {}, BvhExportOptions{}, out);
  const BvhFile back = parse_bvh(out.str(), "back.bvh");
  EXPECT_EQ(static_cast<int>(back.joints.size()), depth + 1);
  EXPECT_LT(out.str().size(), 1000u * (depth + 1));  // linear in the bone count
}

TEST(BvhRobust, TwentyThousandSiblingsGroupAndNameInLinearTime) {
  // siblings at two offsets merge into two bones (one per offset), all named after the root
  const BvhAnimation anim = bvh_to_rig(parse_bvh(deep_bvh(0, 20000), "wide.bvh"), "wide.bvh");
  // the root's End Site and the two sibling offsets give 3 bones under a synthetic root; every
  // sibling's own End Site a bone of its own, named s, s_2, ..., s_20000
  EXPECT_EQ(anim.rig().nbone, 1 + 3 + 20000);
  EXPECT_GE(anim.rig().find_bone("s_20000"), 0);
  EXPECT_LT(anim.max_position_error, 1e-6);
}

TEST(BvhRobust, JointNamesMustBePrintableUtf8AndSayWhere) {
  const std::string bad_byte =
      "HIERARCHY\nROOT A\xff\n{\n  OFFSET 0 0 0\n  CHANNELS 3 Zrotation Xrotation Yrotation\n" +
      kSite + "}\n" + kMotion1 + "1 2 3\n";
  const std::string msg = error_of(bad_byte);
  EXPECT_EQ(msg.rfind("bad.bvh: line 2: field 'joint name': byte 0xff at offset 1 is not UTF-8", 0),
            0u)
      << msg;
  const std::string control =
      "HIERARCHY\nROOT A\x01"
      "B\n{\n  OFFSET 0 0 0\n}\n";
  EXPECT_NE(error_of(control).find("control character 0x01"), std::string::npos);
  // quotes, '<' and accented letters are names like any other (escaped where written)
  const BvhFile ok = parse_bvh(
      "HIERARCHY\nROOT caf\xc3\xa9\"<x>\n{\n  OFFSET 0 0 0\n  CHANNELS 3 "
      "Zrotation Xrotation Yrotation\n" +
          kSite + "}\n" + kMotion1 + "1 2 3\n",
      "ok.bvh");
  EXPECT_EQ(ok.joints[0].name, "caf\xc3\xa9\"<x>");
}

TEST(BvhRobust, HugeOffsetsAndPositionsFailInTheReaderWithTheirLine) {
  // 1e308 used to fail later, in the rig builder, as a 'rest_frame' error with no line
  std::string msg = error_of("HIERARCHY\nROOT A\n{\n  OFFSET 0 1e308 0\n}\n");
  EXPECT_EQ(msg.rfind("bad.bvh: line 4: field 'OFFSET': '1e308' is beyond", 0), 0u) << msg;
  msg = error_of(
      "HIERARCHY\nROOT A\n{\n  OFFSET 0 0 0\n  CHANNELS 3 Xposition Yposition "
      "Zposition\n" +
      kSite + "}\n" + kMotion1 + "0 -2e10 0\n");
  EXPECT_EQ(msg.rfind("bad.bvh: line 14: field 'MOTION': '-2e10' is beyond", 0), 0u) << msg;
  // offsets that are fine alone but sum, after the scale, past the rig's range name the joint's
  // line
  const std::string text =
      "HIERARCHY\nROOT A\n{\n  OFFSET 0 0 0\n  JOINT B\n  {\n    OFFSET 0 9e8 0\n"
      "    JOINT C\n    {\n      OFFSET 0 9e8 0\n" +
      kSite + "    }\n  }\n}\nMOTION\nFrames: 0\nFrame Time: 0.1\n";
  try {
    bvh_to_rig(parse_bvh(text, "sum.bvh"), "sum.bvh");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("sum.bvh: line 8: field 'OFFSET': joint 'C'", 0), 0u)
        << e.what();
  }
  // underflow is a number (0), not an error
  EXPECT_EQ(parse_bvh("HIERARCHY\nROOT A\n{\n  OFFSET 0 1e-400 0\n" + kSite +
                          "}\nMOTION\nFrames: 0\nFrame Time: 0.1\n",
                      "u.bvh")
                .joints[0]
                .offset.y(),
            0.0);
}

TEST(BvhRobust, WriterRejectsScalesThatWouldWriteNanAndNamesTheFile) {
  const Rig rig = make_chain_rig(3, 2.0);
  for (double scale : {std::numeric_limits<double>::infinity(), 0.0, -1.0,
                       std::numeric_limits<double>::quiet_NaN()}) {
    BvhExportOptions o;
    o.scale = scale;
    o.target = "out.bvh";
    std::ostringstream out;
    try {
      write_bvh(rig, {}, o, out);
      ADD_FAILURE() << "no error for scale " << scale;
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).rfind("out.bvh: field 'scale'", 0), 0u) << e.what();
    }
  }
  // a finite scale that overflows a coordinate
  BvhExportOptions o;
  o.scale = 1e308;
  o.target = "big.bvh";
  std::ostringstream out;
  try {
    write_bvh(rig, {}, o, out);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    // the first bone past the reader's bound (+-1e9), before anything is written
    EXPECT_NE(std::string(e.what()).find("big.bvh: bone 'b0': field 'scale'"), std::string::npos)
        << e.what();
  }
  BvhExportOptions bad_order;
  bad_order.euler_order = "XXY";
  EXPECT_THROW(save_bvh(::testing::TempDir() + "/x.bvh", rig, {}, bad_order), InputError);
  try {
    save_bvh(::testing::TempDir() + "/order.bvh", rig, {}, bad_order);
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("order.bvh: field 'euler order'"), std::string::npos);
  }
}

TEST(BvhRobust, ManyEqualNamesGetTheFirstFreeSuffix) {
  // the writer's names: spaces become '_', duplicates get _2, _3, ... (in linear time)
  std::vector<BoneSpec> specs;
  for (int i = 0; i < 4; ++i) {
    BoneSpec b;
    b.name = i == 0 ? "a b" : i == 1 ? "a_b" : i == 2 ? "a_b_2" : "a{b";
    b.parent = i == 0 ? "" : specs[i - 1].name;
    b.head_world = Vec3(0, 0, i);
    b.tail_world = Vec3(0, 0, i + 1);
    b.rest_frame_world = rest_frame_from_roll(b.head_world, b.tail_world, 0.0);
    specs.push_back(b);
  }
  std::ostringstream out;
  write_bvh(build_rig(specs, "names"), {}, BvhExportOptions{}, out);
  const BvhFile f = parse_bvh(out.str(), "names.bvh");
  ASSERT_EQ(f.joints.size(), 4u);
  EXPECT_EQ(f.joints[0].name, "a_b");
  EXPECT_EQ(f.joints[1].name, "a_b_2");
  EXPECT_EQ(f.joints[2].name, "a_b_2_2");
  EXPECT_EQ(f.joints[3].name, "a_b_3");
}

}  // namespace
}  // namespace physik
