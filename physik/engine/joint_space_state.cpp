#include "physik/engine/joint_space_state.h"

namespace physik {

void size_joint_space(const Rig& rig, JointSpaceState& js) {
  js.root_com_world.setZero();
  js.root_vel_world.setZero();
  js.root_orient_world.setIdentity();
  js.joint_vel_local.assign(rig.nbone, Vec3::Zero());
  js.hinge_angle.assign(rig.nbone, Vec2::Zero());
  resize_articulated_data(rig.nbone, js.articulated);
}

}  // namespace physik
