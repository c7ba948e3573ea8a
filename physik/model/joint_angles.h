// Joint angles of a pose and their excess past the rig's limits, per bone and local axis, in a
// joint model (rig.h "Locked axes"): what the torsion springs measure
// (physik/engine/torsion_springs.h), the run monitor's and the summaries' limit violation
// (max_limit_violation), and what tools that show a pose read (the Python module's
// Pose.joint_angles and Pose.limit_excess).
//
//   angle_i    the angles of bone i's joint at its local rotation q_i (relative to rest, in the
//              bone's rest frame), rad, per local axis k (the axis the rig's limit on k bounds):
//     a ball, a free root, every joint under LockedAxes::kSprings (the paper's scheme, and the
//       classic solvers' balls with per-axis limits): log(q_i), the rotation vector of q_i
//       (|angle_i| <= pi; joint_angles, kinematics.h)
//     a hinge, universal joint or weld by locks under LockedAxes::kRemoved (the exact and
//       implicit schemes; joint_coordinates.h): on each free axis its coordinate t
//       (hinge_coordinates), and on each locked axis its lock value plus that axis's component
//       of log(r), r = q(t)^-1 q_i the turn of q_i off the joint's set (in the joint's frame;
//       r = 1 on the set, |log r| = off_joint_set; a universal joint's is its third Euler
//       angle, about the locked axis). The rotation vector's own component on a locked
//       axis is no measure there: on a universal joint with both angles nonzero it is not the
//       lock's value even on the set (a wrist bent and turned read 2-4 deg "past" its twist
//       lock that no axis turned).
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

// The angles of bone i's joint at local rotation q in the joint model `locked` (above), rad.
Vec3 joint_angles(const Rig& rig, LockedAxes locked, int bone, const Quat& q);

// Every bone's angles and excess (each (nbone), rad, per local axis x, y, z) for `pose` in the
// joint model `locked`; the vectors are resized to the rig's bone count (no allocation when
// they already have it).
void joint_angles_and_excess(const Rig& rig, LockedAxes locked, const Pose& pose,
                             std::vector<Vec3>& angles, std::vector<Vec3>& excess);

// The largest |excess| of any limited axis of any bone in `pose` (rad), the root's too (a pinned
// root's limits hold against its rest frame in the world; a free or fixed root has none), in the
// joint model `locked`: a run's or solve's violation is measured in the joints of the scheme it
// ran or solved in (EngineParams::locked_axes()), a classic solver's pose in its scene's; the
// classic solvers' own clamping is of the rotation vector, kSprings'.
double max_limit_violation(const Rig& rig, LockedAxes locked, const Pose& pose);

}  // namespace physik
