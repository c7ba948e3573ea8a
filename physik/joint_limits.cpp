// Joint-limit files; the format is documented in joint_limits.h and models/README.md.
#include "physik/joint_limits.h"

#include <cmath>

#include "physik/errors.h"

namespace physik {

namespace {

const char* const kAxisName[3] = {"x", "y", "z"};

std::string fmt_deg(const Json& v) { return v.dump(); }

}  // namespace

JointLimits joint_limits_from_json(const Json& doc, const std::string& source) {
  JsonContext top{source, ""};
  top.require_object(doc, "");
  top.only_keys(doc, {"comment", "rig", "limits_deg"});
  const Json& all = top.require(doc, "limits_deg");
  if (!all.is_object()) top.fail("limits_deg", "expected an object {\"bone\": {\"x\": [min, max]}}");
  JointLimits out;
  out.source = source;
  for (auto it = all.begin(); it != all.end(); ++it) {
    BoneLimits b;
    b.bone = it.key();
    const JsonContext ctx{source, "limits_deg '" + b.bone + "'"};
    const Json& v = it.value();
    if (v.is_string()) {
      const std::string word = v.get<std::string>();
      if (word == "locked") {
        for (AxisLimit& l : b.limit) l = AxisLimit{true, 0.0, 0.0};
      } else if (word != "free") {
        ctx.fail("", "unknown value '" + word + "' (expected an object, \"free\" or \"locked\")");
      }
      out.bones.push_back(b);
      continue;
    }
    if (!v.is_object()) ctx.fail("", "expected {\"x\": [min, max], ...}, \"free\" or \"locked\"");
    for (auto a = v.begin(); a != v.end(); ++a) {
      int axis = -1;
      for (int k = 0; k < 3; ++k) axis = a.key() == kAxisName[k] ? k : axis;
      if (axis < 0) ctx.fail(a.key(), "unknown axis (expected x, y or z)");
      if (!a->is_array() || a->size() != 2) ctx.fail(a.key(), "expected [min, max] in degrees");
      const double lo = ctx.number_value((*a)[0], a.key() + "[0]");
      const double hi = ctx.number_value((*a)[1], a.key() + "[1]");
      if (lo > hi) {
        ctx.fail(a.key(), "min " + fmt_deg((*a)[0]) + " deg is greater than max " +
                              fmt_deg((*a)[1]) + " deg");
      }
      if (lo < -180.0 || hi > 180.0) ctx.fail(a.key(), "limits must lie within [-180, 180] deg");
      b.limit[axis] = AxisLimit{true, deg2rad(lo), deg2rad(hi)};
    }
    out.bones.push_back(b);
  }
  return out;
}

JointLimits load_joint_limits(const std::string& path) {
  return joint_limits_from_json(read_json_file(path), path);
}

void apply_joint_limits(Rig& rig, const JointLimits& limits) {
  std::vector<int> index;
  for (const BoneLimits& b : limits.bones) {
    const int i = rig.find_bone(b.bone);
    if (i < 0) {
      std::string known;
      for (int k = 0; k < rig.nbone && k < 8; ++k) known += (k ? ", " : "") + rig.bone_name[k];
      if (rig.nbone > 8) known += ", ...";
      throw_input_error(limits.source, "limits_deg '" + b.bone + "'", "",
                        "unknown bone: the rig " +
                            (rig.name.empty() ? std::string() : "'" + rig.name + "' ") +
                            "has no bone of that name (its bones: " + known + ")");
    }
    index.push_back(i);
  }
  for (std::size_t k = 0; k < index.size(); ++k) rig.bone_limit[index[k]] = limits.bones[k].limit;
}

Json joint_limits_to_json(const Rig& rig) {
  Json all = Json::object();
  for (int i = 0; i < rig.nbone; ++i) {
    Json lim = Json::object();
    for (int a = 0; a < 3; ++a) {
      const AxisLimit& l = rig.bone_limit[i][a];
      if (l.limited) lim[kAxisName[a]] = {rad2deg(l.min), rad2deg(l.max)};
    }
    if (!lim.empty()) all[rig.bone_name[i]] = lim;
  }
  Json doc;
  if (!rig.name.empty()) doc["rig"] = rig.name;
  doc["limits_deg"] = all;
  return doc;
}

}  // namespace physik
