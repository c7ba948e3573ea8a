// The source skeleton's checks and its axes (source_skeleton.h).
#include "physik/model/source_skeleton.h"

#include <algorithm>
#include <cctype>
#include <cmath>

#include "physik/model/errors.h"
#include "physik/model/names.h"
#include "physik/model/rig.h"

namespace physik {

Quat source_axes_to_rig(SourceAxes axes) {
  if (axes == SourceAxes::kZUp) return Quat::Identity();
  return Quat(Eigen::AngleAxisd(kPi / 2, Vec3::UnitX()));  // file Y -> rig Z, file Z -> rig -Y
}

const char* to_string(SourceAxes axes) {
  return axes == SourceAxes::kZUp ? "z-up" : "y-up";
}

std::vector<int> source_bone_joints(const SourceSkeleton& skeleton, int nbone) {
  std::vector<int> joint_of(nbone, -1);
  for (std::size_t j = 0; j < skeleton.joints.size(); ++j) {
    for (int b : skeleton.joints[j].bones) {
      if (b >= 0 && b < nbone) joint_of[b] = static_cast<int>(j);
    }
  }
  return joint_of;
}

namespace {

const char* const kChannelNames[] = {"Xposition",   "Yposition",  "Zposition",   "Xrotation",
                                     "Yrotation",   "Zrotation",  "Wquaternion", "Xquaternion",
                                     "Yquaternion", "Zquaternion"};

// the channels of one joint: known names, each once, Euler or all four quaternion channels
void check_channels(const SourceJoint& j, const std::string& source, const std::string& el) {
  int seen[10] = {};
  for (const std::string& c : j.channels) {
    const auto* end = std::end(kChannelNames);
    const auto* it = std::find(std::begin(kChannelNames), end, c);
    if (it == end) {
      throw_input_error(source, el, "channels",
                        "unknown channel '" + c +
                            "' (Xposition, Yposition, Zposition, Xrotation, Yrotation, "
                            "Zrotation, or Wquaternion ... Zquaternion)");
    }
    if (seen[it - std::begin(kChannelNames)]++) {
      throw_input_error(source, el, "channels", "channel '" + c + "' twice");
    }
  }
  const int euler = seen[3] + seen[4] + seen[5];
  const int quat = seen[6] + seen[7] + seen[8] + seen[9];
  if (quat != 0 && quat != 4) {
    throw_input_error(source, el, "channels", "needs all four quaternion channels or none");
  }
  if (quat && euler) {
    throw_input_error(source, el, "channels", "mixes Euler rotation and quaternion channels");
  }
}

// a joint's name must read back from a BVH file as it was written: words separated by single
// spaces (the reader joins a line's words so), no braces
void check_joint_name(const SourceJoint& j, const std::string& source, const std::string& el) {
  if (j.name.empty()) throw_input_error(source, el, "name", "empty");
  const std::string bad = name_problem(j.name);
  if (!bad.empty()) throw_input_error(source, el, "name", bad);
  const bool spaced =
      j.name.front() == ' ' || j.name.back() == ' ' || j.name.find("  ") != std::string::npos;
  const bool other = std::any_of(j.name.begin(), j.name.end(), [](char c) {
    return (c != ' ' && std::isspace(static_cast<unsigned char>(c))) || c == '{' || c == '}';
  });
  if (spaced || other) {
    throw_input_error(source, el, "name",
                      "a BVH joint name is words separated by single spaces, without braces");
  }
}

}  // namespace

void check_source_skeleton(const SourceSkeleton& s, int nbone, const std::string& source) {
  const std::string top = "source_skeleton";
  if (s.format != "bvh") {
    throw_input_error(source, top, "format", "expected \"bvh\", got \"" + s.format + "\"");
  }
  if (!(s.scale > 0.0) || !std::isfinite(s.scale)) {
    throw_input_error(source, top, "scale",
                      "must be a positive finite number (rig units per "
                      "file unit)");
  }
  if (!(s.frame_time >= 0.0) || !std::isfinite(s.frame_time)) {
    throw_input_error(source, top, "frame_time", "must be a positive finite number (s)");
  }
  if (s.joints.empty()) throw_input_error(source, top, "joints", "no joints");
  std::vector<int> listed(nbone, -1);
  std::vector<int> path;  // the joint before this one and its ancestors, root first
  for (std::size_t i = 0; i < s.joints.size(); ++i) {
    const SourceJoint& j = s.joints[i];
    const std::string el = top + ".joints[" + std::to_string(i) + "]";
    check_joint_name(j, source, el);
    if (i == 0 ? j.parent != -1 : (j.parent < 0 || j.parent >= static_cast<int>(i))) {
      throw_input_error(source, el, "parent",
                        i == 0 ? "the first joint is the root (no parent)"
                               : "must be an earlier joint's index (parents before children)");
    }
    // depth-first: the parent is on the path to the joint before (a BVH file nests so)
    while (!path.empty() && path.back() != j.parent) path.pop_back();
    if (i > 0 && path.empty()) {
      throw_input_error(source, el, "parent",
                        "joint " + std::to_string(j.parent) +
                            " is not the joint before nor one of its ancestors: the joints must "
                            "be listed depth-first, as a BVH file nests them (a joint's subtree "
                            "right after it)");
    }
    path.push_back(static_cast<int>(i));
    if (!(j.offset.cwiseAbs().maxCoeff() <= kMaxCoordinate)) {
      throw_input_error(source, el, "offset", "not a finite coordinate within +-1e9");
    }
    for (const Vec3& e : j.end_sites) {
      if (!(e.cwiseAbs().maxCoeff() <= kMaxCoordinate)) {
        throw_input_error(source, el, "end_sites", "not a finite coordinate within +-1e9");
      }
    }
    check_channels(j, source, el);
    for (int b : j.bones) {
      if (b < 0 || b >= nbone) throw_input_error(source, el, "bones", "a bone the rig has not");
      if (listed[b] >= 0) {
        throw_input_error(source, el, "bones",
                          "bone " + std::to_string(b) + " is listed by joint " +
                              std::to_string(listed[b]) + " too (a bone turns with one joint)");
      }
      listed[b] = static_cast<int>(i);
    }
  }
}

}  // namespace physik
