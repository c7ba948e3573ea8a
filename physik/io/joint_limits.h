// Joint-limit files: per-bone limits kept apart from the rig and applied to it by bone name
// (seed 002: "read in the joint limit file ... right now all joint limit specifications are
// hardwired; if the motion file has different joint names, that joint will not rotate" -- here a
// name the rig does not have is an error, never a silent skip).
//
// Format (JSON, documented in models/README.md):
//   {
//     "comment": "free text",                       optional
//     "limits_deg": {                               required; keys are bone names
//       "forearm.L": {"x": [-160, 0], "y": [0, 0], "z": [0, 0]},
//       "upper_arm.L": {"x": [-90, 90]},            absent axes become free
//       "head": "free",                             all three axes free
//       "hips": "locked"                            all three axes [0, 0]
//     }
//   }
// Limits are what the rig file's limits_deg are (rig.h): an interval in degrees on the component
// of the bone's rotation vector (relative to its rest orientation) about the bone-local axis.
// A listed bone's limits are replaced as a whole; bones not listed keep theirs.
// Errors (InputError "<file>: limits_deg '<bone>': field '<axis>': <reason>"): an unknown bone,
// an unknown axis, min > max, a bound outside [-180, 180], a non-number, NaN, a malformed entry.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "physik/io/json_fields.h"
#include "physik/model/rig.h"

namespace physik {

struct BoneLimits {
  std::string bone;
  std::array<AxisLimit, 3> limit{};  // per bone-local axis x, y, z (rad)
};

struct JointLimits {
  std::string source;             // file, for error messages
  std::vector<BoneLimits> bones;  // in file order
};

JointLimits joint_limits_from_json(const Json& doc, const std::string& source);
JointLimits load_joint_limits(const std::string& path);

// Replaces the limits of every listed bone. Throws InputError naming the file and the bone if a
// bone is not in the rig (the rig is left unchanged then).
void apply_joint_limits(Rig& rig, const JointLimits& limits);

// The limits of every bone that has any, in the file format (degrees).
Json joint_limits_to_json(const Rig& rig);

}  // namespace physik
