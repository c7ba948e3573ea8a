#include "physik/engine/implicit_workspace.h"

namespace physik {

void size_joint_snapshot(int n, std::size_t anchor_capacity, JointStateSnapshot& snap) {
  snap.joint_vel_local.assign(n, Vec3::Zero());
  snap.hinge_angle.assign(n, Vec2::Zero());
  snap.bone_local_rotation.assign(n, Quat::Identity());
  snap.friction_anchors.reserve(anchor_capacity);
}

void size_implicit(const Scene& scene, std::size_t anchor_capacity, ImplicitWorkspace& ws) {
  const Rig& rig = scene.rig;
  const int n = rig.nbone;
  ws.accel_bias.assign(n, Vec6::Zero());
  ws.torsion_stiffness.assign(n, Vec3::Zero());
  ws.control_stiffness.assign(scene.control_points.size(), Mat3::Zero());
  ws.torsion_block_world.assign(n, Mat3::Zero());
  resize_articulated_data(n, ws.articulated_rest);
  ws.rest_wrench.assign(n, Vec6::Zero());
  ws.torsion_torque_world.assign(n, Vec3::Zero());
  ws.pose_rate.assign(n, Vec6::Zero());
  ws.step_force_world.assign(n, Vec3::Zero());
  ws.step_torque_world.assign(n, Vec3::Zero());

  ws.snapshots.clear();
  if (scene.params.scheme == Scheme::kImplicit) {
    ws.snapshots.resize(static_cast<std::size_t>(scene.params.implicit_max_splits) + 1);
    for (JointStateSnapshot& snap : ws.snapshots) size_joint_snapshot(n, anchor_capacity, snap);
  }
  ws.gauss_newton_steps = 0;
  ws.split_steps = 0;
  ws.max_substeps = 0;
  ws.retaken_steps = 0;
  ws.unresolved_steps = 0;
  ws.deepest_steps = 0;
}

}  // namespace physik
