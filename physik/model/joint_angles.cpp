// Joint angles and their excess past the limits: see joint_angles.h.
#include "physik/model/joint_angles.h"

#include <algorithm>
#include <cmath>

#include "physik/model/joint_coordinates.h"

namespace physik {

Vec3 joint_angles(const Rig& rig, LockedAxes locked, int i, const Quat& q) {
  const JointType type = rig.joint_type(i, locked);
  const bool coordinates = type == JointType::kHinge || type == JointType::kUniversal ||
                           (type == JointType::kWeld && !rig.welded(i) &&
                            !(i == 0 && rig.root_joint == RootJoint::kFixed));
  if (!coordinates) return rotation_vector(q);
  const Vec2 t = hinge_coordinates(rig, i, q);
  const Vec3 off = rotation_vector((hinge_rotation(rig, i, t).conjugate() * q).normalized());
  Vec3 a = Vec3::Zero();
  for (int k = 0; k < 3; ++k) {
    const AxisLimit& l = rig.bone_limit[i][k];
    if (l.locked()) a[k] = l.min + off[k];
  }
  const auto& axes = rig.bone_joint_axes[i];
  if (axes[0] >= 0) a[axes[0]] = t[0];
  if (axes[1] >= 0) a[axes[1]] = t[1];
  return a;
}

void joint_angles_and_excess(const Rig& rig, LockedAxes locked, const Pose& pose,
                             std::vector<Vec3>& angles, std::vector<Vec3>& excess) {
  angles.resize(rig.nbone);
  excess.resize(rig.nbone);
  for (int i = 0; i < rig.nbone; ++i) {
    angles[i] = joint_angles(rig, locked, i, pose.bone_local_rotation[i]);
    excess[i].setZero();
    for (int k = 0; k < 3; ++k) excess[i][k] = limit_excess(rig.bone_limit[i][k], angles[i][k]);
  }
}

double max_limit_violation(const Rig& rig, LockedAxes locked, const Pose& pose) {
  double worst = 0.0;
  for (int i = 0; i < rig.nbone; ++i) {
    const Vec3 a = joint_angles(rig, locked, i, pose.bone_local_rotation[i]);
    for (int k = 0; k < 3; ++k)
      worst = std::max(worst, std::abs(limit_excess(rig.bone_limit[i][k], a[k])));
  }
  return worst;
}

}  // namespace physik
