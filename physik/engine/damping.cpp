#include "physik/engine/damping.h"

#include "physik/engine/implicit_elements.h"
#include "physik/engine/newton_euler.h"

namespace physik {

void apply_damping(const Rig& rig, const EngineParams& params, SimState& s) {
  const double c = step_damping(params, s);
  if (c == 0.0) return;
  for (int i = 0; i < rig.nbone; ++i) {
    for (const Vec3* p : {&s.frames.head_world[i], &s.frames.tail_world[i]}) {
      apply_force_at(s, i, -c * point_velocity(s, i, *p), *p);
    }
  }
}

void damping_augment(const Scene& scene, const ImplicitStage& stage, SimState& s) {
  const Rig& rig = scene.rig;
  ArticulatedBodyData& d = s.joint_space.articulated;
  const double h = stage.h, c = step_damping(scene.params, s);
  // h D of the factor / I_com: the damper (1 - f) / dt I_com times h (1 - f at h = dt)
  const double rot = (1.0 - scene.params.angular_velocity_factor) * (h / scene.params.dt);
  const Mat3 damper = h * c * Mat3::Identity();
  for (int i = 0; i < rig.nbone; ++i) {
    const Vec3& o = d.point_world[i];
    const Vec6& a0 = s.implicit.accel_bias[i];
    SpatialInertia& I = d.inertia_art[i];
    Vec6& bias = d.bias_force[i];
    if (rot != 0.0) {
      const Mat3 Ir = rot * d.inertia_com_world[i];
      I.A += Ir;
      bias.head<3>() -= Ir * a0.head<3>();
    }
    if (c != 0.0) {
      for (const Vec3* p : {&s.frames.head_world[i], &s.frames.tail_world[i]}) {
        add_point_element(damper, *p - o, a0, I, bias);
      }
    }
  }
}

}  // namespace physik
