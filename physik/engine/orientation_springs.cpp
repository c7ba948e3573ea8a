#include "physik/engine/orientation_springs.h"

#include "physik/engine/control_springs.h"
#include "physik/engine/implicit_elements.h"
#include "physik/engine/torsion_springs.h"

namespace physik {

Vec3 orientation_error(const Quat& q, const Quat& target) {
  return rotation_vector(target * q.conjugate());  // rotation_vector takes the short way round
}

namespace {

struct Turn {
  SpringLaw law;
  double k, cap;  // N m/rad, rad
  Vec3 phi;       // rad, world axes
};

Turn turn_of(const Scene& scene, const SimState& s, const OrientationTarget& t) {
  return {t.spring_in(scene.params), t.k_in(scene.params, scene.rig),
          t.cap_in(scene.params, scene.rig),
          orientation_error(s.frames.orient_world[t.bone], t.target_world)};
}

// The couple's step stiffness (N m/rad, world axes): the control springs' on phi (k 1, the secant
// beyond a cap), or with the pose terms (implicit_linearisation full) and within the cap the
// tangent -dtau/d(delta) = k J_r^-1(phi) = k J_l^-T(phi) (turning the bone by delta, world axes:
// phi -> log(exp(phi) exp(-delta)) = phi - J_r^-1(phi) delta + O(delta^2)), whose Newton step the
// pose terms complete (implicit_pose_terms.h)
Mat3 step_stiffness(const Turn& e, bool full) {
  if (full && (e.law == SpringLaw::kLinear || e.phi.norm() <= e.cap)) {
    return e.k * left_jacobian_inverse_transpose(e.phi);
  }
  return spring_step_stiffness(e.law, e.k, e.cap, e.phi);
}

}  // namespace

void apply_orientation_springs(const Scene& scene, SimState& s) {
  for (const OrientationTarget& t : scene.orientation_targets) {
    const Turn e = turn_of(scene, s, t);
    s.torque_world[t.bone] += spring_force(e.law, e.k, e.cap, e.phi);
  }
}

double orientation_springs_potential(const Scene& scene, const SimState& s) {
  double u = 0.0;
  for (const OrientationTarget& t : scene.orientation_targets) {
    const Turn e = turn_of(scene, s, t);
    u += control_spring_potential(e.law, e.k, e.cap, e.phi.norm());
  }
  return u;
}

void orientation_springs_rate(const Scene& scene, const ImplicitStage& stage, SimState& s) {
  for (const OrientationTarget& t : scene.orientation_targets) {
    const Turn e = turn_of(scene, s, t);
    const Mat3 K = step_stiffness(e, stage.full);
    s.torque_world[t.bone] -= stage.h * (K * s.omega_world[t.bone]);
  }
}

void orientation_springs_augment(const Scene& scene, const ImplicitStage& stage, SimState& s) {
  ArticulatedBodyData& d = s.joint_space.articulated;
  for (const OrientationTarget& t : scene.orientation_targets) {
    const Turn e = turn_of(scene, s, t);
    const Mat3 K = step_stiffness(e, stage.full);
    add_couple_element(stage.h * stage.h * K, s.implicit.accel_bias[t.bone], d.inertia_art[t.bone],
                       d.bias_force[t.bone]);
  }
}

void orientation_springs_mode_stiffness(const Scene& scene, const SimState& s,
                                        const std::vector<Vec3>&, ModeStiffness& out) {
  for (const OrientationTarget& t : scene.orientation_targets) {
    const Turn e = turn_of(scene, s, t);
    const Mat3 K = spring_tangent(e.law, e.k, e.cap, e.phi);
    if (!K.isZero(0.0)) out.couples.push_back({t.bone, K});
  }
}

void orientation_springs_pose_forces(const Scene& scene, const SimState& s, PoseForces& out) {
  for (const OrientationTarget& t : scene.orientation_targets) {
    const Turn e = turn_of(scene, s, t);
    out.couple(t.bone, spring_force(e.law, e.k, e.cap, e.phi));
  }
}

}  // namespace physik
