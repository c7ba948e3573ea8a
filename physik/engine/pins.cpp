#include "physik/engine/pins.h"

#include "physik/engine/implicit_elements.h"
#include "physik/engine/newton_euler.h"

namespace physik {

void apply_pins(const Scene& scene, SimState& s) {
  for (const Pin& pin : scene.pins) {
    const Vec3 a = point_on_bone(s.frames, pin.bone, pin.alpha);
    apply_force_at(s, pin.bone, pin.k_in(scene.params) * (pin.point_world - a), a);
  }
}

double pins_potential(const Scene& scene, const SimState& s) {
  double u = 0.0;
  for (const Pin& pin : scene.pins) {
    const Vec3 a = point_on_bone(s.frames, pin.bone, pin.alpha);
    u += 0.5 * pin.k_in(scene.params) * (pin.point_world - a).squaredNorm();
  }
  return u;
}

void pins_rate(const Scene& scene, const ImplicitStage& stage, SimState& s) {
  for (const Pin& pin : scene.pins) {
    const Vec3 a = point_on_bone(s.frames, pin.bone, pin.alpha);
    const Vec3 v = point_velocity(s, pin.bone, a);
    apply_force_at(s, pin.bone, -stage.h * pin.k_in(scene.params) * v, a);
  }
}

void pins_augment(const Scene& scene, const ImplicitStage& stage, SimState& s) {
  ArticulatedBodyData& d = s.joint_space.articulated;
  for (const Pin& pin : scene.pins) {
    const Vec3 r = point_on_bone(s.frames, pin.bone, pin.alpha) - d.point_world[pin.bone];
    add_point_element(stage.h * stage.h * pin.k_in(scene.params) * Mat3::Identity(), r,
                      s.implicit.accel_bias[pin.bone], d.inertia_art[pin.bone],
                      d.bias_force[pin.bone]);
  }
}

void pins_mode_stiffness(const Scene& scene, const SimState& s, const std::vector<Vec3>&,
                         ModeStiffness& out) {
  for (const Pin& pin : scene.pins) {
    out.points.push_back({pin.bone, point_on_bone(s.frames, pin.bone, pin.alpha),
                          pin.k_in(scene.params) * Mat3::Identity()});
  }
}

void pins_pose_forces(const Scene& scene, const SimState& s, PoseForces& out) {
  for (const Pin& pin : scene.pins) {
    const Vec3 a = point_on_bone(s.frames, pin.bone, pin.alpha);
    out.point(pin.bone, a, pin.k_in(scene.params) * (pin.point_world - a));
  }
}

}  // namespace physik
