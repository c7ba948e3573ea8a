#include "physik/engine/implicit_step.h"

#include <algorithm>

#include "physik/engine/articulated_body.h"
#include "physik/engine/control_springs.h"
#include "physik/engine/forces.h"
#include "physik/engine/implicit_elements.h"
#include "physik/engine/implicit_pose_terms.h"
#include "physik/engine/integrate_joint_space.h"
#include "physik/engine/newton_euler.h"
#include "physik/engine/torsion_springs.h"

namespace physik {

void element_tangents(const Scene& scene, SimState& s) {
  control_springs_tangents(scene, s);
  ImplicitStage stage;
  stage.full = scene.params.implicit_linearisation == ImplicitLinearisation::kFull;
  torsion_springs_tangents(scene, stage, s);
}

Mat3 torsion_block_world(const Rig&, const SimState& s, int i) {
  return s.implicit.torsion_block_world[i];
}

namespace {

// a0_i = X a0_p + c_i (root: c_0): the spatial accelerations when qacc = 0
void velocity_product_accels(const Rig& rig, const ArticulatedBodyData& d, std::vector<Vec6>& a0) {
  if (rig.nbone == 0) return;
  a0[0] = d.bias_accel[0];
  for (int i = 1; i < rig.nbone; ++i) {
    const int p = rig.bone_joint_parent[i];
    const Vec6& ap = a0[p];
    const Vec3 r = d.point_world[i] - d.point_world[p];
    a0[i].head<3>() = ap.head<3>() + d.bias_accel[i].head<3>();
    a0[i].tail<3>() = ap.tail<3>() - r.cross(ap.head<3>()) + d.bias_accel[i].tail<3>();
  }
}

// a joint armature: `armature` I on every ball's joint block (the joint's D_i = A_i + J_i)
void add_armature(const Rig& rig, double armature, ArticulatedBodyData& d) {
  for (int i = 0; i < rig.nbone; ++i) {
    if (rig.bone_joint_type[i] != JointType::kBall) continue;
    d.joint_block[i] += armature * Mat3::Identity();
    d.joint_blocks = true;
  }
}

// one linearised step of h with or without the pose terms; the forces are the step's input
void linearised_step(const Scene& scene, SimState& s, double h, bool full,
                     const PoseTermSelection& terms, double armature) {
  const Rig& rig = scene.rig;
  ArticulatedBodyData& d = s.joint_space.articulated;
  const ImplicitStage stage{h, full, terms};
  implicit_rates(scene, stage, s);                    // tau - h K v, every element's (forces.h)
  articulated_velocity_pass(rig, body_motion(s), d);  // rigid inertias, bias forces
  velocity_product_accels(rig, d, s.implicit.accel_bias);
  if (full) rest_accelerations(scene, terms, s);       // a0 and W, for the pose terms
  implicit_augment(scene, stage, s);                   // + h D + h^2 K, every element's
  if (armature > 0.0) add_armature(rig, armature, d);  // + the joints' armature on M
  d.pose_terms = false;
  if (full) add_pose_terms(scene, stage, s);  // + h^2 K's pose terms
  articulated_backward_pass(rig, d);
  articulated_forward_pass(rig, body_motion(s), d);
}

}  // namespace

JointSolveStats solve_implicit(const Scene& scene, SimState& s) {
  return solve_implicit(scene, s, scene.params.dt);
}

JointSolveStats solve_implicit(const Scene& scene, SimState& s, double h,
                               const PoseTermSelection& terms, double armature) {
  ImplicitWorkspace& im = s.implicit;
  const Rig& rig = scene.rig;
  const EngineParams& p = scene.params;
  ArticulatedBodyData& d = s.joint_space.articulated;
  d.torque_per_omega = (p.angular_velocity_factor - 1.0) / p.dt;  // the explicit factor torque
  d.cancel_gyroscopic = !p.gyroscopic;

  const bool full = p.implicit_linearisation == ImplicitLinearisation::kFull;
  if (full && terms.gauss_newton_retake) {  // kept for a Gauss-Newton retake
    std::copy(s.force_world.begin(), s.force_world.end(), im.step_force_world.begin());
    std::copy(s.torque_world.begin(), s.torque_world.end(), im.step_torque_world.begin());
  }
  linearised_step(scene, s, h, full, terms, armature);
  if (full && terms.gauss_newton_retake && !d.pose_terms_positive) {
    // a pivot's symmetric part is not positive definite with the pose terms: the step is taken
    // again with the Gauss-Newton system, whose pivots' are (implicit_step.h)
    std::copy(im.step_force_world.begin(), im.step_force_world.end(), s.force_world.begin());
    std::copy(im.step_torque_world.begin(), im.step_torque_world.end(), s.torque_world.begin());
    linearised_step(scene, s, h, false, terms, armature);
    ++im.gauss_newton_steps;
  }
  articulated_joint_forces(rig, s);

  JointSolveStats stats;
  stats.passes = 1;  // one sweep of the recursion, no iteration
  stats.mismatch = 0.0;
  return stats;
}

}  // namespace physik
