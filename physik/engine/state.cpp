#include "physik/engine/state.h"

namespace physik {

namespace {

// the gauss-seidel scheme's bodies (state.h), for a rig with welds only
void size_welded_bodies(const Rig& rig, SimState& s) {
  const std::size_t nbody = rig.has_welds() ? static_cast<std::size_t>(rig.nbone) : 0;
  s.body_mass.assign(nbody, 0.0);
  s.body_com_world.assign(nbody, Vec3::Zero());
  s.body_force_world.assign(nbody, Vec3::Zero());
  s.body_torque_world.assign(nbody, Vec3::Zero());
  s.body_inertia_inv_world.assign(nbody, Mat3::Zero());
  s.body_gyro_world.assign(nbody, Vec3::Zero());
  s.body_vel_world.assign(nbody, Vec3::Zero());
}

}  // namespace

void size_state(const Rig& rig, std::size_t ncontrol, SimState& s) {
  const int n = rig.nbone;
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

  size_welded_bodies(rig, s);

  const std::size_t nmember = rig.joint_member_bone.size();
  s.member_r_world.assign(nmember, Vec3::Zero());
  s.member_Minv.assign(nmember, Mat3::Zero());
  s.member_accel.assign(nmember, Vec3::Zero());
  s.member_force_world.assign(nmember, Vec3::Zero());
  s.joint_Sinv.assign(rig.joints.size(), Mat3::Zero());

  s.accel_bias.assign(n, Vec6::Zero());
  s.torsion_stiffness.assign(n, Vec3::Zero());
  s.control_stiffness.assign(ncontrol, Mat3::Zero());
  s.torsion_block_world.assign(n, Mat3::Zero());
  resize_articulated_data(n, s.articulated_rest);
  s.rest_wrench.assign(n, Vec6::Zero());
  s.torsion_torque_world.assign(n, Vec3::Zero());
  s.pose_rate.assign(n, Vec6::Zero());
  s.step_force_world.assign(n, Vec3::Zero());
  s.step_torque_world.assign(n, Vec3::Zero());
  s.implicit_gauss_newton_steps = 0;
  s.implicit_snapshots.clear();  // sized by init_state for implicit scenes (implicit_advance.h)
  s.implicit_split_steps = 0;
  s.implicit_max_substeps = 0;
  s.implicit_retaken_steps = 0;
  s.implicit_unresolved_steps = 0;
  s.implicit_deepest_steps = 0;
  s.contact.found.clear();
  s.contact.elements.clear();
  s.contact.at_frames.clear();
  s.contact.reached.clear();
  s.contact.anchors.clear();
  s.contact.anchors_next.clear();
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
