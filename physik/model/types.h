// Basic math types and conventions shared by the whole core.
//
// Conventions (see docs/DESIGN.md "Conventions"):
//   - world frame: right-handed, Z up (Blender and MuJoCo); lengths in rig units (the paper's
//     Blender units; read as metres), masses in kg, time in s, angles in radians in code.
//   - bone frame: local +Y runs from head to tail (Blender's convention, the paper's "y axis down
//     the bone"); local x and z complete a right-handed frame.
//   - names carry their frame: `world_*` / `*_world` is in the world frame, `local_*` / `*_local`
//     in the bone's own frame.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace physik {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Quat = Eigen::Quaterniond;

constexpr double kPi = 3.14159265358979323846;
constexpr double deg2rad(double deg) {
  return deg * kPi / 180.0;
}
constexpr double rad2deg(double rad) {
  return rad * 180.0 / kPi;
}

// Which joint model a computation follows (rig.h "Locked axes"): the exact and implicit
// schemes' (locked axes removed from the coordinates: hinges, universal joints, welds) or the
// gauss-seidel scheme's (every bone that is not welded a ball, its locked axes held by torsion
// springs, as the paper's).
enum class LockedAxes { kRemoved, kSprings };

// skew-symmetric matrix [v]x with [v]x w = v x w
inline Mat3 skew(const Vec3& v) {
  Mat3 m;
  m << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return m;
}

}  // namespace physik
