// Four motion-capture skeletons in the shapes users bring, written here (not taken from any
// database): the human_body experiment converts them and the tests of the human template read
// them. Each is a BvhFile with a short clip (6 frames) whose joints turn by a few degrees.
//   cmu_like        CMU/cgspeed names and shape: 31 joints, CMU's unit (1/0.45 inch), Y up,
//                   zero-offset children (Hips -> LHipJoint, RHipJoint, LowerBack; Spine1 ->
//                   Neck, LeftShoulder, RightShoulder; LeftHand -> LeftFingerBase, LThumb), legs
//                   splayed at rest, T-pose arms; LHipJoint and RHipJoint never turn (as in
//                   cgspeed's files), the thumbs and the index fingers stay at rest, the toes
//                   hold 5 deg all along
//   mixamo_like     "mixamorig:" names, centimetres, Y up, T-pose, the root Hips with three
//                   children at three offsets (a Hips split into several bones), Spine2 with three
//                   (neck and clavicles), fingers, HeadTop_End and LeftToe_End joints
//   makehuman_like  MakeHuman's default names (spine05..spine01, upperarm01.L, finger2-1.L,
//                   pelvis.L), decimetres, Z up, A-pose arms, fingers and thumbs; the pelvis
//                   bones and each long bone's second bone (upperarm02.L, lowerleg02.L, ...) stay
//                   at rest
//   optitrack_like  OptiTrack Motive's names behind the asset's "Skeleton1_" prefix (Hip, Ab,
//                   Chest, LUArm, LFArm, LThigh, LShin), centimetres, Y up, 21 joints
// Left is +X in every file; forward is +Z in the Y-up files, -Y in the Z-up one.
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "physik/io/bvh.h"

namespace physik::experiments::human_skeletons {

// A joint while a skeleton is written: its OFFSET, children, End Sites and how it moves.
struct SkJoint {
  std::string name;
  Vec3 offset = Vec3::Zero();  // file units
  std::vector<SkJoint> children;
  std::vector<Vec3> ends;
  double motion = 1.0;               // the amplitude of its turn, as a fraction of the clip's
  Vec3 constant_deg = Vec3::Zero();  // a turn held all along, Z, X, Y degrees (motion 0)
};

inline SkJoint sk(const std::string& name, const Vec3& offset, std::vector<SkJoint> children = {},
                  std::vector<Vec3> ends = {}) {
  SkJoint j;
  j.name = name;
  j.offset = offset;
  j.children = std::move(children);
  j.ends = std::move(ends);
  return j;
}

// a joint and its subtree mirrored to the body's right: "Left" -> "Right", "L" -> "R", ".L" ->
// ".R", x negated
inline SkJoint mirror(const SkJoint& j) {
  SkJoint m = j;
  std::string& n = m.name;
  const auto swap = [&](const std::string& from, const std::string& to) {
    const std::size_t at = n.find(from);
    if (at != std::string::npos) n.replace(at, from.size(), to);
  };
  if (n.find("Left") != std::string::npos) {
    swap("Left", "Right");
  } else if (n.size() > 2 && n.compare(n.size() - 2, 2, ".L") == 0) {
    n[n.size() - 1] = 'R';
  } else if (n.find("Skeleton1_L") == 0) {
    n[10] = 'R';
  } else if (!n.empty() && n[0] == 'L') {
    n[0] = 'R';
  }
  m.offset.x() = -j.offset.x();
  for (Vec3& e : m.ends) e.x() = -e.x();
  for (std::size_t c = 0; c < j.children.size(); ++c) m.children[c] = mirror(j.children[c]);
  return m;
}

inline void add_joints(const SkJoint& j, int parent, BvhFile& out,
                       std::vector<const SkJoint*>& src) {
  BvhJoint b;
  b.name = j.name;
  b.parent = parent;
  b.offset = j.offset;
  b.end_sites = j.ends;
  if (parent < 0) b.channels = {BvhChannel::kXpos, BvhChannel::kYpos, BvhChannel::kZpos};
  for (BvhChannel c : {BvhChannel::kZrot, BvhChannel::kXrot, BvhChannel::kYrot}) {
    b.channels.push_back(c);
  }
  b.channel_start = out.nchannel;
  out.nchannel += static_cast<int>(b.channels.size());
  const int index = static_cast<int>(out.joints.size());
  out.joints.push_back(b);
  src.push_back(&j);
  for (const SkJoint& c : j.children) add_joints(c, index, out, src);
}

// The skeleton as a BvhFile with `frames` frames: the root walks along `walk` (file units per
// frame) from `root_at`; joint k turns by amplitude_deg x motion x (sin(0.7 f + k),
// 0.5 sin(0.5 f + 2 k), 0.3 sin(0.3 f + 3 k)) about Z, X, Y, plus its constant turn.
inline BvhFile skeleton_clip(const SkJoint& root, const Vec3& root_at, const Vec3& walk, int frames,
                             double amplitude_deg) {
  BvhFile out;
  std::vector<const SkJoint*> src;
  add_joints(root, -1, out, src);
  out.frame_time = 1.0 / 30.0;
  for (int f = 0; f < frames; ++f) {
    std::vector<double> row;
    const Vec3 p = root_at + f * walk;
    row.insert(row.end(), {p.x(), p.y(), p.z()});
    for (std::size_t k = 0; k < src.size(); ++k) {
      const double a = amplitude_deg * src[k]->motion;
      const double kk = static_cast<double>(k);
      row.push_back(src[k]->constant_deg.x() + a * std::sin(0.7 * f + kk));
      row.push_back(src[k]->constant_deg.y() + 0.5 * a * std::sin(0.5 * f + 2 * kk));
      row.push_back(src[k]->constant_deg.z() + 0.3 * a * std::sin(0.3 * f + 3 * kk));
    }
    out.frames.push_back(row);
  }
  return out;
}

inline SkJoint still(SkJoint j, const Vec3& constant_deg = Vec3::Zero()) {
  j.motion = 0.0;
  j.constant_deg = constant_deg;
  return j;
}

// CMU/cgspeed-like: 31 joints in CMU's unit, 25.3 units (1.43 m) tall
inline BvhFile cmu_like(int frames = 6) {
  const SkJoint leg =
      still(sk("LHipJoint", Vec3::Zero(),
               {sk("LeftUpLeg", {1.4, -1.8, 0.8},
                   {sk("LeftLeg", {0.9, -7.1, 0},
                       {sk("LeftFoot", {0.9, -7.0, 0},
                           {still(sk("LeftToeBase", {0.2, -0.5, 2.2}, {}, {{0, 0, 1.1}}),
                                  {5, 0, 0})})})})}));
  const SkJoint arm =
      sk("LeftShoulder", Vec3::Zero(),
         {sk("LeftArm", {3.2, 1.0, 0},
             {sk("LeftForeArm", {5.2, 0, 0},
                 {sk("LeftHand", {3.6, 0, 0},
                     {sk("LeftFingerBase", Vec3::Zero(),
                         {still(sk("LeftHandIndex1", {0.7, 0, 0}, {}, {{0.6, 0, 0}}))}),
                      still(sk("LThumb", Vec3::Zero(), {}, {{0.5, 0, 0.5}}))})})})});
  const SkJoint spine =
      sk("LowerBack", Vec3::Zero(),
         {sk("Spine", {0, 2.0, -0.1},
             {sk("Spine1", {0, 2.0, 0},
                 {sk("Neck", Vec3::Zero(),
                     {sk("Neck1", {0, 1.6, 0.1}, {sk("Head", {0, 1.6, 0.1}, {}, {{0, 1.7, 0}})})}),
                  arm, mirror(arm)})})});
  const SkJoint root = sk("Hips", Vec3::Zero(), {leg, mirror(leg), spine});
  return skeleton_clip(root, {0, 16.5, 0}, {0, 0, 0.4}, frames, 12.0);
}

// Mixamo-like: mixamorig: names, centimetres, 176 cm tall, T-pose, fingers
inline BvhFile mixamo_like(int frames = 6) {
  const std::string p = "mixamorig:";
  const SkJoint index = sk(p + "LeftHandIndex1", {9, 0, 1},
                           {sk(p + "LeftHandIndex2", {3.5, 0, 0},
                               {sk(p + "LeftHandIndex3", {2.5, 0, 0}, {}, {{2, 0, 0}})})});
  const SkJoint thumb = sk(p + "LeftHandThumb1", {3, -1, 3},
                           {sk(p + "LeftHandThumb2", {3, 0, 1.5}, {}, {{2.5, 0, 1}})});
  const SkJoint arm = sk(
      p + "LeftShoulder", {6, 11, 0},
      {sk(p + "LeftArm", {11, 0, 0},
          {sk(p + "LeftForeArm", {28, 0, 0}, {sk(p + "LeftHand", {25, 0, 0}, {index, thumb})})})});
  const SkJoint neck =
      sk(p + "Neck", {0, 16, 1},
         {sk(p + "Head", {0, 9, 2}, {sk(p + "HeadTop_End", {0, 20, 0}, {}, {{0, 2, 0}})})});
  const SkJoint spine =
      sk(p + "Spine", {0, 10, 1},
         {sk(p + "Spine1", {0, 12, 0}, {sk(p + "Spine2", {0, 13, -1}, {neck, arm, mirror(arm)})})});
  const SkJoint leg = sk(p + "LeftUpLeg", {9, -6, 0},
                         {sk(p + "LeftLeg", {0, -42, 0},
                             {sk(p + "LeftFoot", {0, -42, 0},
                                 {sk(p + "LeftToeBase", {0, -6, 13},
                                     {sk(p + "LeftToe_End", {0, 0, 7}, {}, {{0, 0, 2}})})})})});
  const SkJoint root = sk(p + "Hips", Vec3::Zero(), {spine, leg, mirror(leg)});
  return skeleton_clip(root, {0, 100, 0}, {0, 0, 4}, frames, 10.0);
}

// MakeHuman-like: decimetres, Z up (forward -Y), 16.4 dm tall, A-pose arms, fingers and thumbs
inline BvhFile makehuman_like(int frames = 6) {
  const SkJoint finger = sk("finger2-1.L", {0.3, 0, -0.3},
                            {sk("finger2-2.L", {0.2, 0, -0.2},
                                {sk("finger2-3.L", {0.15, 0, -0.15}, {}, {{0.1, 0, -0.1}})})});
  const SkJoint thumb = sk("finger1-1.L", {0.2, -0.25, -0.2},
                           {sk("finger1-2.L", {0.2, -0.1, -0.2}, {}, {{0.15, -0.05, -0.15}})});
  const SkJoint hand = sk("wrist.L", {0.45, 0, -0.45},
                          {still(sk("metacarpal2.L", {0.1, 0, -0.1}, {finger})), thumb});
  const SkJoint forearm =
      sk("lowerarm01.L", {1.0, 0, -1.0}, {still(sk("lowerarm02.L", {0.8, 0, -0.8}, {hand}))});
  const SkJoint upper_arm =
      sk("upperarm01.L", {0.3, 0, -0.1}, {still(sk("upperarm02.L", {1.2, 0, -1.2}, {forearm}))});
  const SkJoint arm =
      sk("clavicle.L", {0.2, -0.3, 0.4}, {still(sk("shoulder01.L", {1.4, 0.3, 0}, {upper_arm}))});
  const SkJoint neck =
      sk("neck01", {0, 0, 0.6},
         {sk("neck02", {0, -0.1, 0.4}, {sk("head", {0, -0.1, 0.5}, {}, {{0, 0, 2.0}})})});
  const SkJoint spine =
      sk("spine05", {0, 0.1, 0.6},
         {sk("spine04", {0, 0, 0.6},
             {sk("spine03", {0, -0.1, 0.7},
                 {sk("spine02", {0, 0, 0.7},
                     {sk("spine01", {0, 0.1, 0.6}, {neck, arm, mirror(arm)})})})})});
  const SkJoint foot =
      sk("foot.L", {0, 0, -2.0}, {sk("toe1-1.L", {0, -1.2, -0.5}, {}, {{0, -0.5, 0}})});
  const SkJoint shank =
      sk("lowerleg01.L", {0, 0, -2.2}, {still(sk("lowerleg02.L", {0, 0.05, -2.0}, {foot}))});
  const SkJoint thigh =
      sk("upperleg01.L", {0.4, -0.1, -0.3}, {still(sk("upperleg02.L", {0, 0, -2.2}, {shank}))});
  const SkJoint leg = still(sk("pelvis.L", {0.5, 0, -0.5}, {thigh}));
  const SkJoint root = sk("root", Vec3::Zero(), {spine, leg, mirror(leg)});
  return skeleton_clip(root, {0, 0, 9.8}, {0, -0.4, 0}, frames, 10.0);
}

// OptiTrack-like: Motive's bone names behind "Skeleton1_", centimetres, 173 cm tall
inline BvhFile optitrack_like(int frames = 6) {
  const std::string p = "Skeleton1_";
  const SkJoint arm =
      sk(p + "LShoulder", {3, 18, 0},
         {sk(p + "LUArm", {15, 0, 0},
             {sk(p + "LFArm", {28, 0, 0}, {sk(p + "LHand", {25, 0, 0}, {}, {{17, 0, 0}})})})});
  const SkJoint leg =
      sk(p + "LThigh", {9, -4, 0},
         {sk(p + "LShin", {0, -43, 0},
             {sk(p + "LFoot", {0, -42, 0}, {sk(p + "LToe", {0, -6, 13}, {}, {{0, 0, 5}})})})});
  const SkJoint trunk =
      sk(p + "Ab", {0, 9, 0},
         {sk(p + "Chest", {0, 20, 0},
             {sk(p + "Neck", {0, 22, 0}, {sk(p + "Head", {0, 10, 1}, {}, {{0, 17, 0}})}), arm,
              mirror(arm)})});
  const SkJoint root = sk(p + "Hip", Vec3::Zero(), {trunk, leg, mirror(leg)});
  return skeleton_clip(root, {0, 96, 0}, {0, 0, 4}, frames, 10.0);
}

struct Shape {
  const char* name;
  BvhFile (*clip)(int);
  BvhAxes axes;          // the file's up axis
  double scale;          // the unit's --scale to metres
  const char* expected;  // the convention the table should find
};

inline std::vector<Shape> shapes() {
  return {{"cmu_like", cmu_like, BvhAxes::kYUp, 0.0564444, "CMU (cgspeed BVH)"},
          {"mixamo_like", mixamo_like, BvhAxes::kYUp, 0.01, "Mixamo / HumanIK"},
          {"makehuman_like", makehuman_like, BvhAxes::kZUp, 0.1, "MakeHuman"},
          {"optitrack_like", optitrack_like, BvhAxes::kYUp, 0.01, "OptiTrack Motive"}};
}

}  // namespace physik::experiments::human_skeletons
