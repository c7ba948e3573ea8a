// The source skeleton: a rig made from a BVH keeps the file's skeleton (in the rig file too), a
// pose written back gives the file's channel values (Euler orders ZYX, ZXY, XYZ; Y-up and Z-up;
// a root with and without position channels), a clip of that skeleton comes onto the rig, and a
// clip of another skeleton is refused with the difference named.
#include <iomanip>
#include <random>
#include <sstream>

#include <gtest/gtest.h>

#include "physik/io/bvh.h"
#include "physik/io/rig_io.h"
#include "physik/model/errors.h"
#include "physik/model/source_pose.h"
#include "test_util.h"

namespace physik {
namespace {

struct ClipSpec {
  std::string order = "ZXY";  // every joint's rotation channels
  bool z_up = false;
  bool root_position = true;  // the root has Xposition Yposition Zposition
  int frames = 6;
};

// A small figure in centimetres written here: a root with four children (a synthetic root in the
// rig, its segments welded to it), a spine, a head, two legs and an arm; frame 0 at rest, the
// others with random turns within +-50 deg (the middle angle within +-40 deg, so the file's
// angles are the writer's branch) and a moving root.
std::string clip_text(const ClipSpec& c, unsigned seed = 7) {
  auto v = [&](double x, double up, double fwd) {
    std::ostringstream s;
    if (c.z_up) {
      s << x << " " << -fwd << " " << up;
    } else {
      s << x << " " << up << " " << fwd;
    }
    return s.str();
  };
  std::string rot = "CHANNELS 3";
  for (char a : c.order) rot += std::string(" ") + a + "rotation";
  rot += "\n";
  int njoint = 0;
  auto joint = [&](const std::string& name, const std::string& off, const std::string& inner) {
    ++njoint;
    return "JOINT " + name + "\n{\nOFFSET " + off + "\n" + rot + inner + "}\n";
  };
  auto end = [](const std::string& off) { return "End Site\n{\nOFFSET " + off + "\n}\n"; };
  std::string body = joint("Spine", v(0, 20, 0), joint("Head", v(0, 30, 0), end(v(0, 15, 0))));
  body += joint("LeftUpLeg", v(9, -5, 0), joint("LeftLeg", v(0, -42, 0), end(v(0, -40, 5))));
  body += joint("RightUpLeg", v(-9, -5, 0), joint("RightLeg", v(0, -42, 0), end(v(0, -40, 5))));
  body += joint("LeftArm", v(15, 18, 0), joint("LeftHand", v(25, 0, 0), end(v(18, 0, 0))));
  ++njoint;  // the root
  const std::string root_off = v(0, 95, 0);
  std::string text = "HIERARCHY\nROOT Hips\n{\nOFFSET " + root_off + "\n";
  if (c.root_position) {
    text += "CHANNELS 6 Xposition Yposition Zposition" + rot.substr(10);
  } else {
    text += rot;
  }
  text += body + "}\nMOTION\nFrames: " + std::to_string(c.frames) + "\nFrame Time: 0.04\n";
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> outer(-50.0, 50.0), middle(-40.0, 40.0), move(-20.0, 20.0);
  for (int f = 0; f < c.frames; ++f) {
    std::ostringstream row;
    row << std::setprecision(15);
    if (c.root_position) {
      row << (f ? move(rng) : 0.0) << " "
          << (c.z_up ? (f ? move(rng) : 0.0) : 95.0 + (f ? move(rng) : 0.0)) << " "
          << (c.z_up ? 95.0 + (f ? move(rng) : 0.0) : (f ? move(rng) : 0.0)) << " ";
    }
    for (int j = 0; j < njoint; ++j) {
      for (int k = 0; k < 3; ++k) {
        row << (f == 0 ? 0.0 : (k == 1 ? middle(rng) : outer(rng))) << " ";
      }
    }
    text += row.str() + "\n";
  }
  return text;
}

BvhImportOptions import_options(const ClipSpec& c) {
  BvhImportOptions o;
  o.axes = c.z_up ? BvhAxes::kZUp : BvhAxes::kYUp;
  o.scale = 0.01;
  return o;
}

// a rig through its file: what `rig from-bvh` writes and a later command reads
Rig through_file(const Rig& rig) {
  return rig_from_json_text(rig_to_json(rig).dump(), "rig.json");
}

void expect_same_file(const BvhFile& in, const BvhFile& out, const std::string& what) {
  ASSERT_EQ(in.joints.size(), out.joints.size()) << what;
  for (std::size_t j = 0; j < in.joints.size(); ++j) {
    EXPECT_EQ(in.joints[j].name, out.joints[j].name) << what;
    EXPECT_EQ(in.joints[j].parent, out.joints[j].parent) << what;
    EXPECT_EQ(in.joints[j].channels, out.joints[j].channels) << what << " joint " << j;
    EXPECT_LT((in.joints[j].offset - out.joints[j].offset).norm(), 1e-12) << what;
    ASSERT_EQ(in.joints[j].end_sites.size(), out.joints[j].end_sites.size()) << what;
  }
  ASSERT_EQ(in.frames.size(), out.frames.size()) << what;
  for (std::size_t f = 0; f < in.frames.size(); ++f) {
    ASSERT_EQ(in.frames[f].size(), out.frames[f].size());
    for (std::size_t k = 0; k < in.frames[f].size(); ++k) {
      EXPECT_NEAR(in.frames[f][k], out.frames[f][k], 1e-6)
          << what << ": frame " << f << " channel " << k;
    }
  }
}

TEST(BvhSource, RoundTripGivesTheFilesChannelValues) {
  for (const std::string order : {"ZYX", "ZXY", "XYZ"}) {
    for (bool z_up : {false, true}) {
      for (bool root_position : {true, false}) {
        ClipSpec c;
        c.order = order;
        c.z_up = z_up;
        c.root_position = root_position;
        const std::string what = order + (z_up ? " z-up" : " y-up") +
                                 (root_position ? " root positions" : " no root positions");
        const BvhFile in = parse_bvh(clip_text(c), "clip.bvh");
        const BvhAnimation anim = bvh_to_rig(in, "clip.bvh", import_options(c));
        const Rig rig = through_file(anim.rig());
        ASSERT_FALSE(rig.source_skeleton.empty());
        BvhExportOptions o;
        o.frame_time = in.frame_time;
        std::ostringstream s;
        const BvhWriteReport report = write_bvh(rig, anim.poses, o, s);
        EXPECT_TRUE(report.source_skeleton);
        EXPECT_TRUE(report.warnings.empty()) << what << ": " << report.warnings.at(0);
        expect_same_file(in, parse_bvh(s.str(), "out.bvh"), what);
        // the rest pose: the file's frame 0
        std::ostringstream r;
        write_bvh(rig, {}, o, r);
        BvhFile rest_in = in;
        rest_in.frames.resize(1);
        expect_same_file(rest_in, parse_bvh(r.str(), "rest.bvh"), what + " rest");
      }
    }
  }
}

// reading a clip of the source skeleton onto the rig gives the converter's poses
TEST(BvhSource, ClipPoseIsTheConvertersPose) {
  ClipSpec c;
  const BvhFile in = parse_bvh(clip_text(c), "clip.bvh");
  const BvhAnimation anim = bvh_to_rig(in, "clip.bvh", import_options(c));
  const Rig rig = through_file(anim.rig());
  EXPECT_EQ(source_skeleton_mismatch(rig.source_skeleton, in), "");
  BoneFrames scratch, want, got;
  Pose pose;
  for (int f = 0; f < c.frames; ++f) {
    source_clip_pose(rig, in, f, scratch, pose);
    forward_kinematics(rig, pose, got);
    forward_kinematics(rig, anim.poses[f], want);
    for (int b = 0; b < rig.nbone; ++b) {
      EXPECT_LT((got.head_world[b] - want.head_world[b]).norm(), 1e-12) << f << " " << b;
      EXPECT_LT((got.tail_world[b] - want.tail_world[b]).norm(), 1e-12) << f << " " << b;
    }
  }
}

// qBVH and another Euler order on the source skeleton: the same joints, and the same positions
TEST(BvhSource, QuaternionAndOrderOptionsKeepTheMotion) {
  ClipSpec c;
  const BvhFile in = parse_bvh(clip_text(c), "clip.bvh");
  const BvhAnimation anim = bvh_to_rig(in, "clip.bvh", import_options(c));
  for (bool quaternion : {true, false}) {
    BvhExportOptions o;
    o.quaternion = quaternion;
    o.euler_order = quaternion ? "" : "XYZ";
    std::ostringstream s;
    write_bvh(anim.rig(), anim.poses, o, s);
    const BvhFile out = parse_bvh(s.str(), "out");
    ASSERT_EQ(out.joints.size(), in.joints.size());
    EXPECT_EQ(bvh_channel_name(out.joints[1].channels[0]),
              std::string(quaternion ? "Wquaternion" : "Xrotation"));
    std::vector<Quat> rin, rout;
    std::vector<Vec3> pin, pout;
    for (int f = 0; f < c.frames; ++f) {
      bvh_world(in, f, rin, pin);
      bvh_world(out, f, rout, pout);
      for (std::size_t j = 0; j < pin.size(); ++j) {
        EXPECT_LT((pin[j] - pout[j]).norm(), 1e-9) << f << " " << j;
        EXPECT_LT(rin[j].angularDistance(rout[j]), 1e-9) << f << " " << j;
      }
    }
  }
}

// the rig's own skeleton on request: one joint per bone, as before
TEST(BvhSource, OwnSkeletonOnRequest) {
  ClipSpec c;
  const BvhAnimation anim =
      bvh_to_rig(parse_bvh(clip_text(c), "clip.bvh"), "clip.bvh", import_options(c));
  BvhExportOptions o;
  o.source_skeleton = false;
  std::ostringstream s;
  EXPECT_FALSE(write_bvh(anim.rig(), {}, o, s).source_skeleton);
  EXPECT_EQ(static_cast<int>(parse_bvh(s.str(), "own").joints.size()), anim.rig().nbone);
}

// a root without position channels cannot hold a moved root, a joint with one rotation channel
// cannot hold a turn about another axis: the writer says so with the amounts
TEST(BvhSource, WhatTheFileCannotHoldIsSaid) {
  ClipSpec c;
  c.root_position = false;
  const BvhAnimation anim =
      bvh_to_rig(parse_bvh(clip_text(c), "clip.bvh"), "clip.bvh", import_options(c));
  Pose moved = anim.poses[1];
  moved.root_head_world += Vec3(0.0, 0.0, 0.1);  // 10 cm up the rig's Z, the file's Y
  std::ostringstream s;
  const BvhWriteReport r = write_bvh(anim.rig(), {moved}, BvhExportOptions{}, s);
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_NE(r.warnings[0].find("no Yposition channel"), std::string::npos) << r.warnings[0];
  EXPECT_NE(r.warnings[0].find("up to 10 file units"), std::string::npos) << r.warnings[0];
}

TEST(BvhSource, AnotherSkeletonIsNamed) {
  ClipSpec c;
  const BvhFile in = parse_bvh(clip_text(c), "clip.bvh");
  const Rig rig = bvh_to_rig(in, "clip.bvh", import_options(c)).rig();
  ClipSpec other = c;
  other.order = "XYZ";
  EXPECT_EQ(source_skeleton_mismatch(rig.source_skeleton, parse_bvh(clip_text(other), "other.bvh")),
            "joint 'Hips' has other channels in the clip");
  std::string renamed = clip_text(c);
  renamed.replace(renamed.find("LeftArm"), 7, "LeftArx");
  EXPECT_EQ(source_skeleton_mismatch(rig.source_skeleton, parse_bvh(renamed, "r.bvh")),
            "joint 7 is 'LeftArx' in the clip, 'LeftArm' in the rig's source skeleton");
}

// the rig file's source_skeleton is checked: a bone the rig has not, a channel BVH has not
TEST(BvhSource, BadSourceSkeletonInRigFile) {
  ClipSpec c;
  const Rig rig =
      bvh_to_rig(parse_bvh(clip_text(c), "clip.bvh"), "clip.bvh", import_options(c)).rig();
  Json doc = rig_to_json(rig);
  Json bad = doc;
  bad["source_skeleton"]["joints"][1]["bones"] = {"NoSuchBone"};
  EXPECT_THROW(
      {
        try {
          rig_from_json(bad, "r.json");
        } catch (const InputError& e) {
          EXPECT_NE(std::string(e.what()).find("source_skeleton.joints[1]"), std::string::npos)
              << e.what();
          EXPECT_NE(std::string(e.what()).find("NoSuchBone"), std::string::npos) << e.what();
          throw;
        }
      },
      InputError);
  bad = doc;
  bad["source_skeleton"]["joints"][2]["channels"][0] = "Qrotation";
  EXPECT_THROW(rig_from_json(bad, "r.json"), InputError);
  bad = doc;
  bad["source_skeleton"]["joints"][2]["parent"] = 5;
  EXPECT_THROW(rig_from_json(bad, "r.json"), InputError);
}

}  // namespace
}  // namespace physik
