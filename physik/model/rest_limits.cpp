// Limits whose torsion band holds the rest angle, and their fix (rest_limits.h).
#include "physik/model/rest_limits.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace physik {

namespace {

const char* const kAxisName[3] = {"x", "y", "z"};

// the band's edges as the engine computes them (physik/engine/potential.h torsion_excess)
bool rest_in_band(const AxisLimit& l, double tolerance) {
  if (!l.limited) return true;
  const double band = tolerance * (l.max - l.min);
  const double lo = l.min + band, hi = l.max - band;
  return !(0.0 < lo) && !(0.0 > hi);
}

// the fixed limit (the same where it cannot be fixed)
AxisLimit widened(const AxisLimit& l, double tolerance) {
  AxisLimit out = l;
  if (l.locked()) return out;
  const double t = tolerance, m = kRestBandMargin;
  const double band = t * (l.max - l.min);
  if (0.0 < l.min + band) out.min = std::max(-kPi, -(t * l.max + m) / (1.0 - t));
  if (0.0 > l.max - band) out.max = std::min(kPi, (m - t * l.min) / (1.0 - t));
  return out;
}

void check_bone(const std::array<AxisLimit, 3>& limits, int bone, double tolerance,
                std::vector<RestBandProblem>& out) {
  for (int a = 0; a < 3; ++a) {
    if (rest_in_band(limits[a], tolerance)) continue;
    RestBandProblem p;
    p.bone = bone;
    p.axis = a;
    p.before = limits[a];
    p.after = widened(limits[a], tolerance);
    out.push_back(p);
  }
}

}  // namespace

std::vector<RestBandProblem> rest_band_problems(const Rig& rig, double tolerance) {
  std::vector<RestBandProblem> out;
  // every limited bone's (a root has limits only when pinned: against the world)
  for (int b = 0; b < rig.nbone; ++b) check_bone(rig.bone_limit[b], b, tolerance, out);
  return out;
}

std::vector<RestBandProblem> fit_limits_to_rest(std::vector<BoneSpec>& specs, double tolerance) {
  std::vector<RestBandProblem> out;
  for (std::size_t s = 0; s < specs.size(); ++s) {
    const std::size_t first = out.size();
    check_bone(specs[s].limit, static_cast<int>(s), tolerance, out);
    for (std::size_t k = first; k < out.size(); ++k) specs[s].limit[out[k].axis] = out[k].after;
  }
  return out;
}

std::string describe(const RestBandProblem& p, const std::string& bone_name) {
  std::ostringstream s;
  s.precision(4);
  s << bone_name << " " << kAxisName[p.axis] << ": [" << rad2deg(p.before.min) << ", "
    << rad2deg(p.before.max) << "]";
  if (p.fixed()) {
    s << " -> [" << rad2deg(p.after.min) << ", " << rad2deg(p.after.max) << "] deg";
  } else {
    s << " deg (locked away from rest: left as it is)";
  }
  return s.str();
}

}  // namespace physik
