#include "physik/engine/gauss_seidel_workspace.h"

namespace physik {

void size_gauss_seidel(const Rig& rig, GaussSeidelWorkspace& ws) {
  const std::size_t nbody = rig.has_welds() ? static_cast<std::size_t>(rig.nbone) : 0;
  ws.body_mass.assign(nbody, 0.0);
  ws.body_com_world.assign(nbody, Vec3::Zero());
  ws.body_force_world.assign(nbody, Vec3::Zero());
  ws.body_torque_world.assign(nbody, Vec3::Zero());
  ws.body_inertia_inv_world.assign(nbody, Mat3::Zero());
  ws.body_gyro_world.assign(nbody, Vec3::Zero());
  ws.body_vel_world.assign(nbody, Vec3::Zero());

  const std::size_t nmember = rig.joint_member_bone.size();
  ws.member_r_world.assign(nmember, Vec3::Zero());
  ws.member_Minv.assign(nmember, Mat3::Zero());
  ws.member_accel.assign(nmember, Vec3::Zero());
  ws.member_force_world.assign(nmember, Vec3::Zero());
  ws.joint_Sinv.assign(rig.joints.size(), Mat3::Zero());
}

}  // namespace physik
