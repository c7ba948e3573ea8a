#include "physik/engine/state.h"

#include "physik/engine/integrate_joint_space.h"
#include "physik/engine/interpolation.h"
#include "physik/engine/joint_forces.h"

namespace physik {

void init_state(const Scene& scene, SimState& s) {
  const Rig& rig = scene.rig;
  const int n = rig.nbone;
  forward_kinematics(rig, scene.initial_pose, s.frames);
  s.com_world.resize(n);
  for (int i = 0; i < n; ++i) s.com_world[i] = 0.5 * (s.frames.head_world[i] + s.frames.tail_world[i]);
  s.vel_world.assign(n, scene.initial_velocity_world);
  s.omega_world.assign(n, Vec3::Zero());
  s.force_world.assign(n, Vec3::Zero());
  s.torque_world.assign(n, Vec3::Zero());
  s.joint_force_world.assign(n, Vec3::Zero());
  s.joint_torque_world.assign(n, Vec3::Zero());
  s.inertia_inv_world.assign(n, Mat3::Zero());
  s.gyro_world.assign(n, Vec3::Zero());
  init_joint_tables(rig, s);
  if (scene.params.joint_solve == JointSolve::kExact) init_joint_space(rig, s);

  const std::size_t nc = scene.control_points.size();
  s.target_effective_world.resize(nc);
  s.target_goal_world.resize(nc);
  s.interp_steps_left.assign(nc, 0);
  s.control_force_world.assign(nc, Vec3::Zero());
  s.step = 0;
  s.time = 0.0;
  s.pose = scene.initial_pose;
  // the initial targets are a jump from where each attachment point starts
  for (std::size_t c = 0; c < nc; ++c) {
    const ControlPoint& cp = scene.control_points[c];
    s.target_effective_world[c] = point_on_bone(s.frames, cp.bone, cp.alpha);
    start_target_jump(scene, s, static_cast<int>(c), cp.target_world);
  }
}

}  // namespace physik
