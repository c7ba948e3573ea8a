#include "physik/engine/orientation_springs.h"

#include "physik/engine/control_springs.h"
#include "physik/engine/implicit_elements.h"

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
    const Mat3 K = spring_step_stiffness(e.law, e.k, e.cap, e.phi);
    s.torque_world[t.bone] -= stage.h * (K * s.omega_world[t.bone]);
  }
}

void orientation_springs_augment(const Scene& scene, const ImplicitStage& stage, SimState& s) {
  ArticulatedBodyData& d = s.joint_space.articulated;
  for (const OrientationTarget& t : scene.orientation_targets) {
    const Turn e = turn_of(scene, s, t);
    const Mat3 K = spring_step_stiffness(e.law, e.k, e.cap, e.phi);
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

}  // namespace physik
