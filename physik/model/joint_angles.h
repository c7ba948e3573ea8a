// Joint angles of a pose and their excess past the rig's limits, per bone and local axis: what
// the torsion springs measure (physik/engine/torsion_springs.h) and the run monitor's limit
// violation reports (max_limit_violation, kinematics.h), for tools that show a pose (the Python
// module's Pose.joint_angles and Pose.limit_excess).
//
//   angle_i    = log(q_i), the rotation vector of bone i's local rotation q_i (relative to rest,
//                in the bone's rest frame; |angle_i| <= pi), rad: component k is the angle about
//                local axis k that the rig's limit on axis k bounds (joint_angles, kinematics.h)
//   excess_ik  = angle_ik - max  above the max,  angle_ik - min (< 0) below the min,  else 0
//                (within the limits and on a free axis), rad; the root's too: a pinned root's
//                limits hold against its rest frame in the world (a free or fixed root has
//                none)
// The excess is signed so that it says which limit is passed: a linear torsion spring with no
// engage band (torsion_tolerance 0) pulls with -torsion_k * excess, and the largest |excess| of
// a pose is its max_limit_violation.
#pragma once

#include <vector>

#include "physik/model/kinematics.h"

namespace physik {

// The signed excess of `angle` (rad) past one axis's limit (0 on a free axis).
inline double limit_excess(const AxisLimit& limit, double angle) {
  if (!limit.limited) return 0.0;
  if (angle > limit.max) return angle - limit.max;
  if (angle < limit.min) return angle - limit.min;
  return 0.0;
}

// Every bone's angles and excess (each (nbone), rad, per local axis x, y, z) for `pose`; the
// vectors are resized to the rig's bone count (no allocation when they already have it).
void joint_angles_and_excess(const Rig& rig, const Pose& pose, std::vector<Vec3>& angles,
                             std::vector<Vec3>& excess);

}  // namespace physik
