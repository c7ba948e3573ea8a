// Joint angles and their excess past the limits: see joint_angles.h.
#include "physik/model/joint_angles.h"

namespace physik {

void joint_angles_and_excess(const Rig& rig, const Pose& pose, std::vector<Vec3>& angles,
                             std::vector<Vec3>& excess) {
  angles.resize(rig.nbone);
  excess.resize(rig.nbone);
  for (int i = 0; i < rig.nbone; ++i) {
    angles[i] = joint_angles(pose, i);
    excess[i].setZero();
    for (int k = 0; k < 3; ++k) excess[i][k] = limit_excess(rig.bone_limit[i][k], angles[i][k]);
  }
}

}  // namespace physik
