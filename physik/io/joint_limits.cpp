// Joint-limit files; the format is documented in joint_limits.h and models/README.md.
#include "physik/io/joint_limits.h"

#include <cmath>

#include "physik/io/axis_limits.h"
#include "physik/model/errors.h"
#include "physik/model/names.h"

namespace physik {

namespace {

const char* const kAxisName[3] = {"x", "y", "z"};

}  // namespace

JointLimits joint_limits_from_json(const Json& doc, const std::string& source) {
  JsonContext top{source, ""};
  top.require_object(doc, "");
  top.only_keys(doc, {"comment", "rig", "limits_deg"});
  top.name_or(doc, "rig", "");  // the rig's name, as joint_limits_to_json writes it
  const Json& all = top.require(doc, "limits_deg");
  if (!all.is_object())
    top.fail("limits_deg", "expected an object {\"bone\": {\"x\": [min, max]}}");
  JointLimits out;
  out.source = source;
  for (auto it = all.begin(); it != all.end(); ++it) {
    BoneLimits b;
    b.bone = it.key();
    const std::string bad = name_problem(b.bone);
    if (!bad.empty()) throw_input_error(source, "limits_deg", "", "a bone name: " + bad);
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
    b.limit = parse_axis_limits(v, ctx, "");
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
      // the nearest name when one is close, else the first bones
      std::string known = did_you_mean(b.bone, rig.bone_name);
      if (known.empty()) {
        for (int k = 0; k < rig.nbone && k < 8; ++k) known += (k ? ", " : "") + rig.bone_name[k];
        known = " (its bones: " + known + (rig.nbone > 8 ? ", ...)" : ")");
      }
      throw_input_error(limits.source, "limits_deg '" + b.bone + "'", "",
                        "unknown bone: the rig " +
                            (rig.name.empty() ? std::string() : "'" + rig.name + "' ") +
                            "has no bone of that name" + known);
    }
    const auto& l = b.limit;
    const bool limited = l[0].limited || l[1].limited || l[2].limited;
    if (limited && i == 0 && rig.root_joint != RootJoint::kPinned) {
      throw_input_error(limits.source, "limits_deg '" + b.bone + "'", "",
                        std::string("the rig's root is ") + to_string(rig.root_joint) +
                            ": it has nothing to limit its turn against (limits on the root "
                            "need the rig's \"root\": \"pinned\")");
    }
    if (limited && rig.welded(i)) {
      throw_input_error(limits.source, "limits_deg '" + b.bone + "'", "",
                        "welded to '" + rig.bone_name[rig.bone_weld[i]] +
                            "': a welded bone has no degree of freedom to limit");
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
