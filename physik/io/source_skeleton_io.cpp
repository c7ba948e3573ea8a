// The rig file's source skeleton, read and written (source_skeleton_io.h).
#include "physik/io/source_skeleton_io.h"

#include <limits>

#include "physik/model/errors.h"
#include "physik/model/names.h"

namespace physik {

namespace {

Json vec_json(const Vec3& v) {
  return Json::array({v.x(), v.y(), v.z()});
}

SourceJoint joint_from_json(const Json& j, const JsonContext& ctx, const Rig& rig) {
  ctx.require_object(j, "");
  ctx.only_keys(j, {"name", "parent", "offset", "channels", "end_sites", "bones"});
  SourceJoint out;
  out.name = ctx.name(j, "name");
  out.parent = j.contains("parent") ? ctx.integer(j, "parent") : -1;  // absent: the root
  out.offset = ctx.vec3(j, "offset");
  const Json& channels = ctx.require(j, "channels");
  if (!channels.is_array()) ctx.fail("channels", "expected an array of channel names");
  for (std::size_t i = 0; i < channels.size(); ++i) {
    if (!channels[i].is_string()) {
      ctx.fail("channels[" + std::to_string(i) + "]", "expected a channel name");
    }
    out.channels.push_back(channels[i].get<std::string>());
  }
  if (j.contains("end_sites")) {
    const Json& ends = j["end_sites"];
    if (!ends.is_array()) ctx.fail("end_sites", "expected an array of [x, y, z] offsets");
    for (std::size_t i = 0; i < ends.size(); ++i) {
      out.end_sites.push_back(ctx.vec3_value(ends[i], "end_sites[" + std::to_string(i) + "]"));
    }
  }
  if (j.contains("bones")) {
    const Json& bones = j["bones"];
    if (!bones.is_array()) ctx.fail("bones", "expected an array of bone names");
    for (std::size_t i = 0; i < bones.size(); ++i) {
      const std::string field = "bones[" + std::to_string(i) + "]";
      if (!bones[i].is_string()) ctx.fail(field, "expected a bone name");
      const std::string name = bones[i].get<std::string>();
      const int b = rig.find_bone(name);
      if (b < 0) ctx.fail(field, unknown_bone(name, rig) + " in the rig");
      if (!out.bones.empty() && b <= out.bones.back()) {
        ctx.fail(field, "bones are listed in the rig's order, each once");
      }
      out.bones.push_back(b);
    }
  }
  return out;
}

}  // namespace

void read_source_skeleton(const Json& doc, const std::string& source, Rig& rig) {
  if (!doc.contains("source_skeleton")) return;
  const Json& s = doc["source_skeleton"];
  JsonContext ctx{source, "source_skeleton"};
  ctx.require_object(s, "source_skeleton");
  ctx.only_keys(s, {"format", "axes", "scale", "frame_time", "joints"});
  SourceSkeleton out;
  out.format = ctx.string(s, "format");
  const std::string axes = ctx.choice_or(s, "axes", {"y-up", "z-up"}, "y-up");
  out.axes = axes == "z-up" ? SourceAxes::kZUp : SourceAxes::kYUp;
  out.scale = ctx.number(s, "scale");
  out.frame_time = ctx.number_or(s, "frame_time", 0.0);
  if (s.contains("frame_time") && !(out.frame_time > 0.0)) {
    ctx.fail("frame_time", "must be a positive finite number (s)");
  }
  const Json& joints = ctx.require(s, "joints");
  if (!joints.is_array()) ctx.fail("joints", "expected an array of joints");
  for (std::size_t i = 0; i < joints.size(); ++i) {
    const JsonContext jc{source, "source_skeleton.joints[" + std::to_string(i) + "]"};
    out.joints.push_back(joint_from_json(joints[i], jc, rig));
  }
  check_source_skeleton(out, rig.nbone, source);
  rig.source_skeleton = std::move(out);
}

Json source_skeleton_to_json(const Rig& rig) {
  const SourceSkeleton& s = rig.source_skeleton;
  Json joints = Json::array();
  for (const SourceJoint& j : s.joints) {
    Json o;
    o["name"] = j.name;
    if (j.parent >= 0) o["parent"] = j.parent;
    o["offset"] = vec_json(j.offset);
    o["channels"] = j.channels;
    if (!j.end_sites.empty()) {
      o["end_sites"] = Json::array();
      for (const Vec3& e : j.end_sites) o["end_sites"].push_back(vec_json(e));
    }
    if (!j.bones.empty()) {
      o["bones"] = Json::array();
      for (int b : j.bones) o["bones"].push_back(rig.bone_name[b]);
    }
    joints.push_back(o);
  }
  Json out{{"format", s.format}, {"axes", to_string(s.axes)}, {"scale", s.scale}};
  if (s.frame_time > 0.0) out["frame_time"] = s.frame_time;
  out["joints"] = joints;
  return out;
}

}  // namespace physik
