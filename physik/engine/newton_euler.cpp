#include "physik/engine/newton_euler.h"

namespace physik {

Mat3 inertia_world(const Rig& rig, const Quat& orient_world, int bone) {
  const Mat3 R = orient_world.toRotationMatrix();
  return R * rig.bone_inertia_local[bone].asDiagonal() * R.transpose();
}

void prepare_bodies(const Rig& rig, const EngineParams& params, SimState& s) {
  for (int i = 0; i < rig.nbone; ++i) {
    s.force_world[i].setZero();
    s.torque_world[i].setZero();
    s.joint_force_world[i].setZero();
    s.joint_torque_world[i].setZero();
    // only the Gauss-Seidel solve and its integration read I^-1 and w x I w; the exact solve
    // forms the inertias itself (articulated_body.h)
    if (params.scheme != Scheme::kGaussSeidel) continue;
    const Mat3 R = s.frames.orient_world[i].toRotationMatrix();
    s.inertia_inv_world[i] =
        R * rig.bone_inertia_local[i].cwiseInverse().asDiagonal() * R.transpose();
    if (params.gyroscopic) {
      const Vec3& w = s.omega_world[i];
      const Vec3 Iw = R * rig.bone_inertia_local[i].asDiagonal() * (R.transpose() * w);
      s.gyro_world[i] = w.cross(Iw);
    } else {
      s.gyro_world[i].setZero();
    }
  }
}

}  // namespace physik
