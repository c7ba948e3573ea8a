// A rest pose inside a joint limit's engage band: a rig problem, found and fixed here.
//
// The torsion spring of a limited axis with range [min, max] engages `tolerance` x (max - min)
// inside each limit (physik/engine/torsion_springs.h):
//   lo = min + t (max - min),   hi = max - t (max - min),   t = torsion_tolerance
// At rest every joint angle is 0 (angles are taken from the rest pose), so a limit with
// 0 < lo or 0 > hi pushes the bone from the first step of any run: a rig at rest, with no target
// and no gravity, moves. A source's limit that starts at the rest angle (an elbow 0..150 deg,
// whose band then reaches 15 deg into the range), or ends near it (the knee of MuJoCo's
// humanoid, -160..2 deg: its band ends at -14 deg), or excludes it, does so.
//
// The fix widens the limit on the side the rest angle lies past, just enough that the band's
// edge sits at the rest angle (a margin kRestBandMargin inside, so that rounding of the limit in
// degrees in a rig file never puts it back out):
//   0 < lo:  min' = -(t max + m) / (1 - t)       (then lo' = -m)
//   0 > hi:  max' =  (m - t min) / (1 - t)       (then hi' =  m)
// The spring then engages where the source's limit is reached at rest, and the other side of
// the range keeps its band; limits beyond +-180 deg are not made. A locked axis (min == max)
// away from 0 cannot be widened without unlocking it: it is reported, not changed. A root has
// limits only when pinned (against the world), and they are fitted the same way. The tolerance is
// the engine parameter's: a scene with a larger torsion_tolerance than the one the rig was fitted
// for can push at rest again. Units: rad.
#pragma once

#include <string>
#include <vector>

#include "physik/model/rig.h"

namespace physik {

constexpr double kRestBandMargin = 1e-9;  // rad, the rest angle's distance inside the band

// One limited axis whose band holds the rest angle: before and after the fix (rad).
struct RestBandProblem {
  int bone = -1;            // index into the specs or the rig's bones
  int axis = 0;             // 0, 1, 2: the bone-local x, y, z
  AxisLimit before, after;  // after == before where it could not be fixed (locked away from 0)
  bool fixed() const { return after.min != before.min || after.max != before.max; }
};

// The axes of the rig whose torsion band (at `tolerance`) pushes at rest; `after` is the fix.
std::vector<RestBandProblem> rest_band_problems(const Rig& rig, double tolerance);

// Widens the limits of `specs` (any order) as above; returns
// what it changed and what it could not (bone = the spec's index).
std::vector<RestBandProblem> fit_limits_to_rest(std::vector<BoneSpec>& specs, double tolerance);

// "forearm x: [0, 150] -> [-16.7, 150] deg" or "... (locked away from rest: left as it is)".
std::string describe(const RestBandProblem& p, const std::string& bone_name);

}  // namespace physik
