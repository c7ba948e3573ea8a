// The write-back to the source skeleton is lossless (bvh.h "Rig -> its source skeleton"): on
// skeletons in the shapes motion capture comes in, written here (a CMU-like one with zero-offset
// children, fingers, End Sites and a joint with no child; a Mixamo-like one; a MakeHuman-like
// Z-up one in decimetres with position channels on every joint that stretch the bones; qBVH),
// in Euler orders ZYX, ZXY and XYZ with angles on either branch, through gimbal lock and past
// 180 degrees, every channel of every frame comes back within 1e-6. A joint with no bone keeps
// its rotation when a solve moves its parent (its children absorb the change, the positions stay
// the rig's); a root with no position channels is pinned; whatever physik writes, physik reads.
#include <cmath>
#include <functional>
#include <iomanip>
#include <iostream>
#include <random>
#include <sstream>

#include <gtest/gtest.h>

#include "physik/io/bvh.h"
#include "physik/io/rig_io.h"
#include "physik/model/errors.h"
#include "physik/model/names.h"
#include "physik/model/source_pose.h"
#include "test_util.h"

namespace physik {
namespace {

struct TestJoint {
  std::string name;
  int parent = -1;
  Vec3 offset;                  // (x, up, forward), file units, before the axes
  std::vector<std::string> ch;  // channels in file order
  std::vector<Vec3> ends;       // End Sites, (x, up, forward)
  bool stretch = false;         // its position channels move it off its OFFSET
};

struct Skeleton {
  std::string name;
  bool z_up = false;
  double scale = 0.01;  // rig units per file unit
  std::vector<TestJoint> joints;

  int add(const std::string& n, int parent, const Vec3& off, std::vector<std::string> ch,
          std::vector<Vec3> ends = {}, bool stretch = false) {
    joints.push_back({n, parent, off, std::move(ch), std::move(ends), stretch});
    return static_cast<int>(joints.size()) - 1;
  }
  // (x, up, forward) in the file's axes
  Vec3 file(const Vec3& v) const { return z_up ? Vec3(v.x(), -v.z(), v.y()) : v; }
};

std::vector<std::string> rot(const std::string& order) {
  std::vector<std::string> out;
  for (char a : order) out.push_back(std::string(1, a) + "rotation");
  return out;
}

std::vector<std::string> pos_rot(const std::string& order) {
  std::vector<std::string> out{"Xposition", "Yposition", "Zposition"};
  for (const std::string& r : rot(order)) out.push_back(r);
  return out;
}

const std::vector<std::string> kQuat{"Wquaternion", "Xquaternion", "Yquaternion", "Zquaternion"};

// CMU's cgspeed conversion, in its shape: ZYX angles, inch-like units, a root with three
// zero-offset children (LHipJoint, RHipJoint, LowerBack), Spine1 whose three children all sit
// at its origin, hands whose finger and thumb joints sit at theirs, End Sites, and a joint with
// no child and no End Site (HeadTop)
Skeleton cmu_like() {
  Skeleton s{"cmu-like", false, 0.056, {}};
  const auto r = rot("ZYX");
  const int hips = s.add("Hips", -1, {0, 17, 0}, pos_rot("ZYX"));
  for (int side : {1, -1}) {
    const std::string L = side > 0 ? "L" : "R", Left = side > 0 ? "Left" : "Right";
    const int hip = s.add(L + "HipJoint", hips, {0, 0, 0}, r);
    const int up = s.add(Left + "UpLeg", hip, {side * 1.36, -1.79, 0.83}, r);
    const int leg = s.add(Left + "Leg", up, {side * 2.44, -6.72, 0}, r);
    const int foot = s.add(Left + "Foot", leg, {0, -7.08, 0}, r);
    s.add(Left + "ToeBase", foot, {0, -0.2, 2.2}, r, {{0, 0, 1.0}});
  }
  const int lower = s.add("LowerBack", hips, {0, 0, 0}, r);
  const int spine = s.add("Spine", lower, {0, 2.03, -0.11}, r);
  const int spine1 = s.add("Spine1", spine, {0, 2.07, 0.01}, r);
  const int neck = s.add("Neck", spine1, {0, 0, 0}, r);
  const int neck1 = s.add("Neck1", neck, {0, 1.67, 0.03}, r);
  const int head = s.add("Head", neck1, {0, 1.61, 0.05}, r);
  s.add("HeadTop", head, {0, 1.8, 0}, r);
  for (int side : {1, -1}) {
    const std::string Left = side > 0 ? "Left" : "Right", L = side > 0 ? "L" : "R";
    const int shoulder = s.add(Left + "Shoulder", spine1, {0, 0, 0}, r);
    const int arm = s.add(Left + "Arm", shoulder, {side * 3.58, 0.56, -0.37}, r);
    const int fore = s.add(Left + "ForeArm", arm, {side * 4.98, 0, 0}, r);
    const int hand = s.add(Left + "Hand", fore, {side * 3.48, 0, 0}, r);
    const int base = s.add(Left + "FingerBase", hand, {0, 0, 0}, r);
    s.add(Left + "HandIndex1", base, {side * 0.71, 0, 0}, r, {{side * 0.57, 0, 0}});
    s.add(L + "Thumb", hand, {0, 0, 0}, r, {{side * 0.58, 0, 0.58}});
  }
  return s;
}

// Mixamo's shape: centimetres, ZXY angles, a root whose children leave at distinct offsets (a
// synthetic root with welded segments), a hand whose fingers leave at distinct offsets
Skeleton mixamo_like() {
  Skeleton s{"mixamo-like", false, 0.01, {}};
  const auto r = rot("ZXY");
  const int hips = s.add("mixamorig:Hips", -1, {0, 98, 0}, pos_rot("ZXY"));
  const int spine = s.add("mixamorig:Spine", hips, {0, 9.9, 0.2}, r);
  const int chest = s.add("mixamorig:Spine1", spine, {0, 11.6, 0}, r);
  const int neck = s.add("mixamorig:Neck", chest, {0, 30, 0}, r);
  s.add("mixamorig:Head", neck, {0, 9.6, 1.5}, r, {{0, 18, 0}});
  for (double side : {1.0, -1.0}) {
    const std::string Left = side > 0 ? "Left" : "Right";
    const int up = s.add("mixamorig:" + Left + "UpLeg", hips, {side * 9.1, -6.6, -0.6}, r);
    const int leg = s.add("mixamorig:" + Left + "Leg", up, {0, -42, 0.3}, r);
    s.add("mixamorig:" + Left + "Foot", leg, {0, -42, -2}, r, {{0, -6, 14}});
    const int arm = s.add("mixamorig:" + Left + "Arm", chest, {side * 14, 24, 0}, r);
    const int fore = s.add("mixamorig:" + Left + "ForeArm", arm, {side * 27, 0, 0}, r);
    const int hand = s.add("mixamorig:" + Left + "Hand", fore, {side * 26, 0, 0}, r);
    s.add("mixamorig:" + Left + "HandThumb1", hand, {side * 3, -1, 3}, r, {{side * 3, 0, 2}});
    s.add("mixamorig:" + Left + "HandIndex1", hand, {side * 9, 0, 2.5}, r, {{side * 4, 0, 0}});
  }
  return s;
}

// MakeHuman's shape: Z up, decimetres, XYZ angles, six channels on every joint whose position
// channels stretch the bones, fingers, End Sites
Skeleton makehuman_like() {
  Skeleton s{"makehuman-like", true, 0.1, {}};
  const auto pr = pos_rot("XYZ");
  const int root = s.add("root", -1, {0, 9.5, 0}, pr);
  const int spine = s.add("spine05", root, {0, 1.1, 0}, pr, {}, true);
  const int chest = s.add("spine01", spine, {0, 3.5, 0}, pr, {}, true);
  s.add("head", chest, {0, 2.5, 0.2}, pr, {{0, 2.2, 0}}, true);
  for (int side : {1, -1}) {
    const std::string sfx = side > 0 ? ".L" : ".R";
    const int thigh = s.add("upperleg01" + sfx, root, {side * 1.0, -0.5, 0}, pr, {}, true);
    const int shin = s.add("lowerleg01" + sfx, thigh, {0, -4.2, 0}, pr, {}, true);
    s.add("foot" + sfx, shin, {0, -4.1, -0.2}, pr, {{0, -0.5, 1.4}});
    const int arm = s.add("upperarm01" + sfx, chest, {side * 1.6, 2.2, 0}, pr, {}, true);
    const int hand = s.add("wrist" + sfx, arm, {side * 5.2, 0, 0}, pr, {}, true);
    for (int f = 0; f < 3; ++f) {
      s.add("finger" + std::to_string(f + 1) + "-1" + sfx, hand, {side * 0.9, 0, 0.3 * f - 0.3}, pr,
            {{side * 0.5, 0, 0}});
    }
  }
  return s;
}

// the Mixamo-like skeleton with every rotation as qBVH quaternion channels
Skeleton quaternion_like() {
  Skeleton s = mixamo_like();
  s.name = "qbvh";
  for (TestJoint& j : s.joints) {
    std::vector<std::string> ch;
    for (const std::string& c : j.ch) {
      if (c.find("position") != std::string::npos) ch.push_back(c);
    }
    for (const std::string& q : kQuat) ch.push_back(q);
    j.ch = ch;
  }
  return s;
}

std::string num(double v) {
  std::ostringstream s;
  s << std::setprecision(15) << v;
  return s.str();
}

std::string triple(const Vec3& v) {
  return num(v.x()) + " " + num(v.y()) + " " + num(v.z());
}

// HIERARCHY of the skeleton (children after their parent, in the order added)
std::string hierarchy(const Skeleton& s) {
  std::string out = "HIERARCHY\n";
  std::function<void(int, int)> write = [&](int j, int depth) {
    const TestJoint& t = s.joints[j];
    const std::string ind(2 * depth, ' ');
    out += ind + (t.parent < 0 ? "ROOT " : "JOINT ") + t.name + "\n" + ind + "{\n";
    out += ind + "  OFFSET " + triple(s.file(t.offset)) + "\n" + ind + "  CHANNELS " +
           std::to_string(t.ch.size());
    for (const std::string& c : t.ch) out += " " + c;
    out += "\n";
    for (std::size_t c = 0; c < s.joints.size(); ++c) {
      if (s.joints[c].parent == j) write(static_cast<int>(c), depth + 1);
    }
    for (const Vec3& e : t.ends) {
      out += ind + "  End Site\n" + ind + "  {\n" + ind + "    OFFSET " + triple(s.file(e)) + "\n" +
             ind + "  }\n";
    }
    out += ind + "}\n";
  };
  write(0, 0);
  return out;
}

// the joints in the order the file lists them (depth-first)
std::vector<int> file_order(const Skeleton& s) {
  std::vector<int> order;
  std::function<void(int)> visit = [&](int j) {
    order.push_back(j);
    for (std::size_t c = 0; c < s.joints.size(); ++c) {
      if (s.joints[c].parent == j) visit(static_cast<int>(c));
    }
  };
  visit(0);
  return order;
}

// a frame's angle: any value a file holds. Frame 1 puts every middle angle at gimbal lock
// (+-90), frame 2 takes the outer ones past 180 (a curve that went round), the others are
// uniform over (-180, 180] for all three angles, so the file's triple is either branch
double angle(std::mt19937& rng, int frame, int k) {
  std::uniform_real_distribution<double> any(-180.0, 180.0), past(180.0, 300.0);
  if (frame == 1 && k == 1) return (rng() % 2) ? 90.0 : -90.0;
  if (frame == 2 && k != 1) return (rng() % 2) ? past(rng) : -past(rng);
  return any(rng);
}

std::string motion(const Skeleton& s, int nframe, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> move(-20.0, 20.0), stretch(-0.5, 0.5), unit(-1.0, 1.0);
  std::string out = "MOTION\nFrames: " + std::to_string(nframe) + "\nFrame Time: 0.0083333333\n";
  const std::vector<int> order = file_order(s);
  for (int f = 0; f < nframe; ++f) {
    std::string row;
    for (int j : order) {
      const TestJoint& t = s.joints[j];
      const Vec3 off = s.file(t.offset);
      int k = 0;
      for (const std::string& c : t.ch) {
        const int axis = c[0] == 'X' ? 0 : c[0] == 'Y' ? 1 : 2;
        double v = 0.0;
        if (c.find("position") != std::string::npos) {
          v = off[axis] + (t.parent < 0 ? move(rng) : t.stretch ? stretch(rng) : 0.0);
        } else if (c.find("rotation") != std::string::npos) {
          v = angle(rng, f, k++);
        } else if (c == "Wquaternion") {
          // a random unit quaternion, either sign (the file's hemisphere comes back)
          Quat q(unit(rng), unit(rng), unit(rng), unit(rng));
          q.normalize();
          v = q.w();
          row += num(v) + " " + num(q.x()) + " " + num(q.y()) + " " + num(q.z()) + " ";
          continue;
        } else {
          continue;  // X, Y, Z quaternion: written with W
        }
        row += num(v) + " ";
      }
    }
    out += row + "\n";
  }
  return out;
}

BvhFile clip_of(const Skeleton& s, int nframe = 8, unsigned seed = 11) {
  return parse_bvh(hierarchy(s) + motion(s, nframe, seed), s.name + ".bvh");
}

BvhImportOptions options_of(const Skeleton& s) {
  BvhImportOptions o;
  o.axes = s.z_up ? BvhAxes::kZUp : BvhAxes::kYUp;
  o.scale = s.scale;
  return o;
}

// a rig through its file: what `rig from-bvh` writes and a later command reads
Rig through_file(const Rig& rig) {
  return rig_from_json_text(rig_to_json(rig).dump(), "rig.json");
}

// the largest difference of any channel of any frame (degrees, file units, quaternion values)
double largest_channel_difference(const BvhFile& a, const BvhFile& b) {
  EXPECT_EQ(a.joints.size(), b.joints.size());
  EXPECT_EQ(a.frames.size(), b.frames.size());
  double worst = 0.0;
  for (std::size_t f = 0; f < a.frames.size() && f < b.frames.size(); ++f) {
    EXPECT_EQ(a.frames[f].size(), b.frames[f].size());
    for (std::size_t k = 0; k < a.frames[f].size() && k < b.frames[f].size(); ++k) {
      worst = std::max(worst, std::abs(a.frames[f][k] - b.frames[f][k]));
    }
  }
  return worst;
}

BvhFile written(const Rig& rig, const std::vector<Pose>& poses, const SourceFrames& source,
                BvhWriteReport* report = nullptr, BvhExportOptions o = {}) {
  std::ostringstream s;
  const BvhWriteReport r = write_bvh(rig, poses, o, s, source);
  if (report) *report = r;
  return parse_bvh(s.str(), "written.bvh");
}

std::vector<Skeleton> all_skeletons() {
  return {cmu_like(), mixamo_like(), makehuman_like(), quaternion_like()};
}

// every channel of every frame, as the file gave it: rotations on the file's branch (either
// one, through gimbal lock, past 180 degrees), held joints, stretches, quaternion hemispheres
TEST(BvhWriteBack, EveryChannelOfEveryFrameComesBack) {
  for (const Skeleton& s : all_skeletons()) {
    const BvhFile in = clip_of(s);
    const BvhAnimation anim = bvh_to_rig(in, s.name, options_of(s));
    const Rig rig = through_file(anim.rig());
    BvhWriteReport report;
    const BvhFile out = written(rig, anim.poses, SourceFrames::of_clip(in), &report);
    const double worst = largest_channel_difference(in, out);
    EXPECT_LT(worst, 1e-6) << s.name;
    EXPECT_TRUE(report.warnings.empty()) << s.name << ": " << report.warnings.at(0);
    std::cout << "[ measured ] " << s.name << ": largest channel difference " << worst << "\n";
  }
}

// before: a joint with no bone wrote 0 0 0 and handed its turn to its children (CMU's Spine1 by
// 5 degrees, LeftHand by 10); now it keeps its own, and so do its children
TEST(BvhWriteBack, JointsWithNoBoneKeepTheirOwnRotation) {
  const Skeleton s = cmu_like();
  const BvhFile in = clip_of(s);
  const BvhAnimation anim = bvh_to_rig(in, s.name, options_of(s));
  const Rig& rig = anim.rig();
  for (const char* name : {"Spine1", "LeftHand", "RightHand", "HeadTop"}) {
    int j = 0;
    while (rig.source_skeleton.joints[j].name != name) ++j;
    EXPECT_TRUE(source_joint_held(rig, j)) << name;
  }
  const BvhFile out = written(rig, anim.poses, SourceFrames::of_clip(in));
  std::vector<Quat> rin, rout;
  std::vector<Vec3> pin, pout;
  for (std::size_t f = 0; f < in.frames.size(); ++f) {
    bvh_world(in, static_cast<int>(f), rin, pin);
    bvh_world(out, static_cast<int>(f), rout, pout);
    for (std::size_t j = 0; j < rin.size(); ++j) {
      EXPECT_LT(rin[j].angularDistance(rout[j]), 1e-9) << in.joints[j].name << " frame " << f;
      EXPECT_LT((pin[j] - pout[j]).norm(), 1e-9) << in.joints[j].name << " frame " << f;
    }
  }
}

// a scene naming a joint with no bone of its own (CMU's RightHand) as a bone gets no typo hint
// (no bone is close) but the bones that stand at it: the one ending at its origin, at alpha 1,
// and those that start there
TEST(BvhWriteBack, AJointWithNoBoneIsNamedWithTheBonesAtIt) {
  const Skeleton s = cmu_like();
  const BvhAnimation anim = bvh_to_rig(clip_of(s), s.name, options_of(s));
  const Rig& rig = anim.rig();
  ASSERT_LT(rig.find_bone("RightHand"), 0);
  const std::string m = unknown_bone("RightHand", rig);
  EXPECT_NE(
      m.find("unknown bone 'RightHand': a joint of the rig's source skeleton without a bone of "
             "its own"),
      std::string::npos)
      << m;
  const std::size_t at = m.find("its point is bone '");
  ASSERT_NE(at, std::string::npos) << m;
  const std::size_t from = at + std::string("its point is bone '").size();
  const int ends = rig.find_bone(m.substr(from, m.find('\'', from) - from));
  ASSERT_GE(ends, 0) << m;
  const std::size_t st = m.find("the bones that start there: '");
  ASSERT_NE(st, std::string::npos) << m;
  const std::size_t sfrom = st + std::string("the bones that start there: '").size();
  const int starts = rig.find_bone(m.substr(sfrom, m.find('\'', sfrom) - sfrom));
  ASSERT_GE(starts, 0) << m;
  // the hand's origin: where the forearm ends and the fingers begin
  EXPECT_LT((rig.bone_rest_tail_world[ends] - rig.bone_rest_head_world[starts]).norm(), 1e-12);
  // a typo of a bone still gets its hint, and a name that is nothing gets neither
  EXPECT_NE(unknown_bone("RightForArm", rig).find("did you mean 'RightForeArm'"), std::string::npos)
      << unknown_bone("RightForArm", rig);
  EXPECT_EQ(unknown_bone("Tail", rig), "unknown bone 'Tail'");
}

// a joint whose bone is welded to another joint's (a girdle a human cannot move on its own, as
// CMU's LHipJoint) has no turn of its own in the rig either: it is held, and its channels come
// back from the source frame
TEST(BvhWriteBack, AWeldedJointIsHeld) {
  const Skeleton s = cmu_like();
  const BvhFile in = clip_of(s);
  Json doc = rig_to_json(bvh_to_rig(in, s.name, options_of(s)).rig());
  for (Json& b : doc["bones"]) {
    if (b["name"] == "LHipJoint") b["weld"] = "Hips";
  }
  const Rig rig = rig_from_json(doc, "welded.json");
  ASSERT_TRUE(rig.welded(rig.find_bone("LHipJoint")));
  EXPECT_TRUE(source_joint_held(rig, 1));  // LHipJoint, the root's first child
  std::vector<Pose> poses(in.frames.size());
  BoneFrames scratch;
  for (std::size_t f = 0; f < poses.size(); ++f) {
    source_clip_pose(rig, in, static_cast<int>(f), scratch, poses[f]);
  }
  EXPECT_LT(largest_channel_difference(in, written(rig, poses, SourceFrames::of_clip(in))), 1e-6);
}

// a solve that turns the Neck (a child of Spine1, which has no bone): Spine1 keeps the frame's
// rotation, the Neck's channels take the change, and the written file's joints sit where the
// rig's bones are
TEST(BvhWriteBack, ASolvedPoseKeepsTheHeldJointAndTheRigsPositions) {
  const Skeleton s = cmu_like();
  const BvhFile in = clip_of(s);
  const BvhAnimation anim = bvh_to_rig(in, s.name, options_of(s));
  const Rig& rig = anim.rig();
  Pose moved = anim.poses[3];
  const int neck_bone = rig.find_bone("Neck");
  ASSERT_GE(neck_bone, 0);
  moved.bone_local_rotation[neck_bone] = moved.bone_local_rotation[neck_bone] *
                                         Quat(Eigen::AngleAxisd(0.4, Vec3(1, 2, 3).normalized()));
  SourceFrames source{{in.frames[3]}, {0}};
  const BvhFile out = written(rig, {moved}, source);
  int spine1 = 0;
  while (out.joints[spine1].name != "Spine1") ++spine1;
  const int col = out.joints[spine1].channel_start;
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(out.frames[0][col + k], in.frames[3][col + k], 1e-9);
  int neck = 0;
  while (out.joints[neck].name != "Neck") ++neck;
  EXPECT_GT(std::abs(out.frames[0][out.joints[neck].channel_start] -
                     in.frames[3][out.joints[neck].channel_start]),
            1e-3);
  // the written joints are the rig's bone heads (each bone starts at its joint)
  const BoneFrames fk = forward_kinematics(rig, moved);
  std::vector<Quat> r;
  std::vector<Vec3> p;
  bvh_world(out, 0, r, p);
  const Quat a = bvh_axes_to_rig(BvhAxes::kYUp);
  for (int b = 0; b < rig.nbone; ++b) {
    const int j = anim.pivots.bone_node[b];
    if (b == 0 || j < 0) continue;  // the synthetic root starts below its joint
    EXPECT_LT((s.scale * (a * p[j]) - fk.head_world[b]).norm(), 1e-9) << rig.bone_name[b];
  }
}

// with no source frame (a pose from rest), a held joint is at rest and the positions are still
// the rig's; a stretch channel holds the OFFSET
TEST(BvhWriteBack, WithNoSourceFrameTheHeldJointRestsAndPositionsStay) {
  for (const Skeleton& s : {cmu_like(), makehuman_like()}) {
    const BvhFile in = clip_of(s);
    const BvhAnimation anim = bvh_to_rig(in, s.name, options_of(s));
    const Rig& rig = anim.rig();
    const BvhFile out = written(rig, {anim.poses[4]}, SourceFrames{});
    std::vector<Quat> r;
    std::vector<Vec3> p;
    bvh_world(out, 0, r, p);
    const BoneFrames fk = forward_kinematics(rig, anim.poses[4]);
    const Quat a = bvh_axes_to_rig(s.z_up ? BvhAxes::kZUp : BvhAxes::kYUp);
    for (int b = 1; b < rig.nbone; ++b) {
      const int j = anim.pivots.bone_node[b];
      if (j < 0) continue;
      EXPECT_LT((s.scale * (a * p[j]) - fk.head_world[b]).norm(), 1e-9)
          << s.name << " " << rig.bone_name[b];
    }
    for (std::size_t j = 1; j < out.joints.size(); ++j) {
      for (std::size_t c = 0; c < out.joints[j].channels.size(); ++c) {
        const int axis = static_cast<int>(out.joints[j].channels[c]);
        if (axis > 2) continue;  // rotation channels
        EXPECT_NEAR(out.frames[0][out.joints[j].channel_start + c], out.joints[j].offset[axis],
                    1e-12);
      }
    }
  }
}

// the stretch is named, joint by joint, with its size; so is a joint with no bone
TEST(BvhWriteBack, TheConversionNamesWhatTheRigCannotHold) {
  const Skeleton mh = makehuman_like();
  const BvhAnimation a = bvh_to_rig(clip_of(mh), mh.name, options_of(mh));
  int stretched = 0;
  for (const std::string& w : a.warnings) {
    if (w.find("position channels move it up to") != std::string::npos) ++stretched;
  }
  int expected = 0;
  for (const TestJoint& j : mh.joints) expected += j.stretch ? 1 : 0;
  EXPECT_EQ(stretched, expected);
  const Skeleton cmu = cmu_like();
  const BvhAnimation c = bvh_to_rig(clip_of(cmu), cmu.name, options_of(cmu));
  std::vector<std::string> named;
  for (const std::string& w : c.warnings) {
    if (w.find("has no bone of its own") != std::string::npos) {
      named.push_back(
          w.substr(w.find('\'') + 1, w.find('\'', w.find('\'') + 1) - w.find('\'') - 1));
    }
  }
  EXPECT_EQ(named, (std::vector<std::string>{"Spine1", "HeadTop", "LeftHand", "RightHand"}));
}

// the Euler branch follows the source row's values where it has them, else the previous frame's
TEST(BvhWriteBack, NearestEulerKeepsTheReferenceBranch) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> any(-3.0, 3.0);
  for (const std::string order : {"ZYX", "ZXY", "XYZ", "YXZ"}) {
    for (int t = 0; t < 200; ++t) {
      Vec3 e(any(rng), any(rng), any(rng));
      if (t % 10 == 0) e[1] = (t % 20 ? 1 : -1) * kPi / 2;  // gimbal lock
      const Quat q = rotation_from_euler(e, order);
      const Vec3 got = nearest_euler(q, order, e);
      EXPECT_LT((got - e).cwiseAbs().maxCoeff(), 1e-9) << order << " " << e.transpose();
      EXPECT_LT(rotation_from_euler(got, order).angularDistance(q), 1e-12);
    }
  }
}

// a root without position channels (three.js's pirouette) is pinned: a solve cannot move it
TEST(BvhWriteBack, ARootWithoutPositionChannelsIsPinned) {
  for (bool synthetic : {true, false}) {
    Skeleton s = mixamo_like();
    s.joints[0].ch = rot("ZXY");
    if (!synthetic) {
      // one child at the root: the root bone starts at the root joint
      Skeleton one{"chain", false, 0.01, {}};
      one.add("hip", -1, {0, 98, 0}, rot("ZXY"));
      one.add("spine", 0, {0, 20, 0}, rot("ZXY"));
      one.add("head", 1, {0, 30, 0}, rot("ZXY"), {{0, 15, 0}});
      s = one;
    }
    const BvhFile in = clip_of(s);
    const BvhAnimation anim = bvh_to_rig(in, s.name, options_of(s));
    const Rig rig = through_file(anim.rig());
    EXPECT_EQ(rig.root_joint, synthetic ? RootJoint::kFixed : RootJoint::kPinned) << s.name;
    EXPECT_FALSE(anim.notes.empty());
    // the root's joint point is its rest point in every frame, and the round trip is exact
    const BvhFile out = written(rig, anim.poses, SourceFrames::of_clip(in));
    EXPECT_LT(largest_channel_difference(in, out), 1e-6) << s.name;
    BvhImportOptions free = options_of(s);
    free.root = RootJoint::kFree;
    EXPECT_EQ(bvh_to_rig(in, s.name, free).rig().root_joint, RootJoint::kFree);
  }
}

// the rig file's source skeleton must be listed as a file nests it: depth-first
TEST(BvhWriteBack, ASkeletonNotDepthFirstIsRefused) {
  const Skeleton s = mixamo_like();
  const Rig rig = bvh_to_rig(clip_of(s), s.name, options_of(s)).rig();
  Json doc = rig_to_json(rig);
  // Hips, Spine, Spine1, Neck, Head, LeftArm, LeftForeArm, ...: give LeftForeArm Neck as its
  // parent: parents first still, but Neck's subtree closed when LeftArm opened
  Json& joints = doc["source_skeleton"]["joints"];
  int fore_arm = 0;
  while (joints[fore_arm]["name"] != "mixamorig:LeftForeArm") ++fore_arm;
  ASSERT_EQ(joints[3]["name"], "mixamorig:Neck");
  joints[fore_arm]["parent"] = 3;
  try {
    rig_from_json(doc, "r.json");
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("depth-first"), std::string::npos) << e.what();
  }
}

// whatever physik writes, physik reads: offsets or sums beyond +-1e9 are refused, not written
TEST(BvhWriteBack, WhatPhysikWouldNotReadIsNotWritten) {
  const Skeleton s = mixamo_like();
  const BvhAnimation anim = bvh_to_rig(clip_of(s), s.name, options_of(s));
  // the own skeleton at a scale that puts the rig past the bound
  BvhExportOptions big;
  big.source_skeleton = false;
  big.scale = 1e10;
  std::ostringstream out;
  EXPECT_THROW(write_bvh(anim.rig(), {}, big, out), InputError);
  // a source skeleton whose offsets are each within the bound but add up past it
  Rig rig = anim.rig();
  for (SourceJoint& j : rig.source_skeleton.joints) j.offset *= 1e8;
  EXPECT_THROW(write_bvh(rig, {}, BvhExportOptions{}, out), InputError);
  // and what is written reads back
  std::ostringstream ok;
  write_bvh(anim.rig(), anim.poses, BvhExportOptions{}, ok);
  EXPECT_NO_THROW(bvh_to_rig(parse_bvh(ok.str(), "ok.bvh"), "ok.bvh"));
}

}  // namespace
}  // namespace physik
