// Per-axis joint limits in JSON; the format and the checks are documented in axis_limits.h.
#include "physik/io/axis_limits.h"

namespace physik {

std::array<AxisLimit, 3> parse_axis_limits(const Json& value, const JsonContext& ctx,
                                           const std::string& field) {
  static const char* const kAxisName[3] = {"x", "y", "z"};
  if (!value.is_object()) ctx.fail(field, "expected an object {\"x\": [min, max], ...}");
  std::array<AxisLimit, 3> out{};
  for (auto it = value.begin(); it != value.end(); ++it) {
    const std::string axis_field = field.empty() ? it.key() : field + "." + it.key();
    int axis = -1;
    for (int a = 0; a < 3; ++a) axis = it.key() == kAxisName[a] ? a : axis;
    if (axis < 0) ctx.fail(axis_field, "unknown axis (expected x, y or z)");
    if (!it->is_array() || it->size() != 2) ctx.fail(axis_field, "expected [min, max] in degrees");
    // number_value rejects non-numbers and non-finite values
    const double lo = ctx.number_value((*it)[0], axis_field + "[0]");
    const double hi = ctx.number_value((*it)[1], axis_field + "[1]");
    if (lo > hi) {
      ctx.fail(axis_field,
               "min " + (*it)[0].dump() + " deg is greater than max " + (*it)[1].dump() + " deg");
    }
    if (lo < -180.0 || hi > 180.0) {
      ctx.fail(axis_field, "limits must lie within [-180, 180] deg (got [" + (*it)[0].dump() +
                               ", " + (*it)[1].dump() + "])");
    }
    out[axis] = AxisLimit{true, deg2rad(lo), deg2rad(hi)};
  }
  return out;
}

}  // namespace physik
