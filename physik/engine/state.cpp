#include "physik/engine/state.h"

namespace physik {

void size_state(const Scene& scene, SimState& s) {
  const Rig& rig = scene.rig;
  const int n = rig.nbone;
  const std::size_t ncontrol = scene.control_points.size();
  s.frames.resize(n);
  s.com_world.assign(n, Vec3::Zero());
  s.vel_world.assign(n, Vec3::Zero());
  s.omega_world.assign(n, Vec3::Zero());
  s.force_world.assign(n, Vec3::Zero());
  s.torque_world.assign(n, Vec3::Zero());
  s.joint_force_world.assign(n, Vec3::Zero());
  s.joint_torque_world.assign(n, Vec3::Zero());
  s.inertia_inv_world.assign(n, Mat3::Zero());
  s.gyro_world.assign(n, Vec3::Zero());

  s.contact.found.clear();
  s.contact.elements.clear();
  s.contact.at_frames.clear();
  s.contact.reached.clear();
  s.contact.anchors.clear();
  s.contact.anchors_next.clear();
  prepare_contact_data(scene, s.contact);

  size_gauss_seidel(rig, s.gauss_seidel);
  size_joint_space(rig, s.joint_space);
  size_implicit(scene, s.contact.anchors.capacity(), s.implicit);

  s.damping_auto_value = 0.0;
  s.damping_auto_updates = 0;

  s.target_effective_world.assign(ncontrol, Vec3::Zero());
  s.target_goal_world.assign(ncontrol, Vec3::Zero());
  s.interp_steps_left.assign(ncontrol, 0);
  s.control_force_world.assign(ncontrol, Vec3::Zero());
  s.step = 0;
  s.time = 0.0;
}

}  // namespace physik
