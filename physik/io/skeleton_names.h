// Joint-name tables: which segment of the human template (physik/model/human_template.h) each
// joint of a skeleton starts, by its name in one of the common conventions. The table is data,
// models/human/joint_names.json (compiled in), which a person can read and extend; `rig from-bvh
// --mapping FILE` takes another.
//
// File format (JSON):
//   {"comment": "...",                                  optional, free text
//    "conventions": [{"name": "CMU (cgspeed BVH)",      one or more conventions
//                     "source": "...",                  optional, free text
//                     "joints": {"LeftUpLeg": "thigh.L", "LHipJoint": "pelvis", ...}}]}
// or, for one convention, {"comment": "...", "joints": {...}} (named after the file). A joint
// name is a pattern: '*' matches any run of characters ("LeftHandIndex*"). Segment names are the
// template's ("pelvis", "thigh.L", ...).
//
// Matching (match_skeleton): names are compared by their key, normalise_joint_name: the part
// after the last ':' (a namespace, "mixamorig:LeftArm"), lower case, without ' ', '_', '-' and
// '.'; a prefix every joint but the root shares and that ends in one of those separators
// ("Skeleton1_" in "Skeleton1_LThigh") is taken off first. Each convention names some of the
// joints; the one naming the most wins (ties: the first in the table). A joint it leaves out takes
// its parent's segment (the root: the pelvis, whatever its name). The skeleton is human when the
// named joints hold the core (human_core_complete: pelvis, thighs, shanks, upper arms, forearms and
// a spine bone).
//
// Errors (InputError naming the file and the field): a segment the template does not have (with
// the nearest name), two patterns of one convention with the same key, a file without
// conventions; for a user's file (match_skeleton with `strict`), a pattern no joint of the
// skeleton matches (with the nearest joint name).
#pragma once

#include <string>
#include <vector>

#include "physik/io/json_fields.h"

namespace physik {

struct NameConvention {
  std::string name;
  std::string source;
  std::vector<std::string> patterns;  // as written in the file
  std::vector<std::string> keys;      // normalise_joint_name of each pattern ('*' kept)
  std::vector<int> segments;          // index into human_segments(), one per pattern
};

struct NameTable {
  std::string source;  // the file, for messages ("models/human/joint_names.json" compiled in)
  std::vector<NameConvention> conventions;
};

NameTable name_table_from_json(const Json& doc, const std::string& source);
NameTable load_name_table(const std::string& path);
// models/human/joint_names.json as compiled in
const NameTable& default_name_table();

// "mixamorig:Left_Fore-Arm.L" -> "leftforearml"
std::string normalise_joint_name(const std::string& name);

struct SkeletonMatch {
  std::string convention;            // the convention that named the most joints ("" for none)
  std::string prefix;                // the shared prefix taken off ("" for none)
  std::vector<int> node_segment;     // (njoint) the segment each joint's name gives, -1 for none
  int named = 0;                     // joints the convention names
  std::vector<std::string> unnamed;  // joints it leaves out (they take their parent's segment)
  bool human = false;                // the named joints hold the template's core
  std::vector<std::string> missing;  // the core segments no joint names
};

// The names of a skeleton's joints, the root first. The root counts as the pelvis whatever its
// name. With `strict` (a user's file), a pattern that matches no joint is an InputError naming
// table.source, the field "joints '<pattern>'" and the nearest joint name.
SkeletonMatch match_skeleton(const std::vector<std::string>& names, const NameTable& table,
                             bool strict = false);

}  // namespace physik
