// Per-axis joint limits in JSON, shared by the rig format (rig_io.h, a bone's "limits_deg") and the
// joint-limit file format (joint_limits.h, one entry per bone under "limits_deg"):
//
//   {"x": [min, max], "y": [min, max], "z": [min, max]}    degrees; any axis may be absent (free)
//
// Each present axis becomes AxisLimit{true, deg2rad(min), deg2rad(max)} on the bone-local axis
// (rig.h: an interval on that component of the rotation vector relative to the rest orientation).
// Checks, in this order, each an InputError through `ctx` (file and element, e.g. the bone):
//   the value is an object; axis names are x, y or z; each entry is [min, max]; both are finite
//   numbers; min <= max; both lie within [-180, 180].
// Error fields are "<field>.<axis>" (e.g. "limits_deg.x") or, with an empty `field`, "<axis>";
// a bound that is not a number names "<...>[0]" or "<...>[1]".
#pragma once

#include <array>
#include <string>

#include "physik/io/json_fields.h"
#include "physik/model/rig.h"

namespace physik {

std::array<AxisLimit, 3> parse_axis_limits(const Json& value, const JsonContext& ctx,
                                           const std::string& field);

}  // namespace physik
