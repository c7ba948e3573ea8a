#include "physik/engine/control_springs.h"

#include "physik/engine/implicit_elements.h"
#include "physik/engine/newton_euler.h"

namespace physik {

Vec3 spring_force(SpringLaw law, double k, double cap, const Vec3& d) {
  if (law == SpringLaw::kLinear) return k * d;
  const double len = d.norm();
  if (len <= cap) return k * d;  // inside the cap the two laws agree (and d = 0 is safe)
  return (k * cap / len) * d;
}

Mat3 spring_tangent(SpringLaw law, double k, double cap, const Vec3& d) {
  const double len = d.norm();
  if (law == SpringLaw::kLinear || len <= cap) return k * Mat3::Identity();
  const Vec3 n = d / len;
  return (k * cap / len) * (Mat3::Identity() - n * n.transpose());
}

Mat3 spring_step_stiffness(SpringLaw law, double k, double cap, const Vec3& d) {
  const double len = d.norm();
  if (law == SpringLaw::kLinear || len <= cap) return k * Mat3::Identity();
  return (k * cap / len) * Mat3::Identity();
}

double control_spring_potential(SpringLaw law, double k, double cap, double d) {
  if (law == SpringLaw::kLinear || d <= cap) return 0.5 * k * d * d;
  return k * cap * (d - 0.5 * cap);
}

void apply_control_springs(const Scene& scene, SimState& s) {
  for (std::size_t c = 0; c < scene.control_points.size(); ++c) {
    const ControlPoint& cp = scene.control_points[c];
    const Vec3 a = point_on_bone(s.frames, cp.bone, cp.alpha);
    const Vec3 f = spring_force(cp.spring_in(scene.params), cp.k_in(scene.params),
                                cp.cap_in(scene.params), s.target_effective_world[c] - a);
    s.control_force_world[c] = f;
    apply_force_at(s, cp.bone, f, a);
  }
}

double control_springs_potential(const Scene& scene, const SimState& s) {
  double u = 0.0;
  for (std::size_t c = 0; c < scene.control_points.size(); ++c) {
    const ControlPoint& cp = scene.control_points[c];
    u += control_spring_potential(
        cp.spring_in(scene.params), cp.k_in(scene.params), cp.cap_in(scene.params),
        (point_on_bone(s.frames, cp.bone, cp.alpha) - s.target_effective_world[c]).norm());
  }
  return u;
}

void control_springs_tangents(const Scene& scene, SimState& s) {
  const EngineParams& p = scene.params;
  for (std::size_t c = 0; c < scene.control_points.size(); ++c) {
    const ControlPoint& cp = scene.control_points[c];
    const Vec3 a = point_on_bone(s.frames, cp.bone, cp.alpha);
    s.implicit.control_stiffness[c] = spring_step_stiffness(
        cp.spring_in(p), cp.k_in(p), cp.cap_in(p), s.target_effective_world[c] - a);
  }
}

void control_springs_rate(const Scene& scene, const ImplicitStage& stage, SimState& s) {
  control_springs_tangents(scene, s);
  for (std::size_t c = 0; c < scene.control_points.size(); ++c) {
    const ControlPoint& cp = scene.control_points[c];
    const Vec3 a = point_on_bone(s.frames, cp.bone, cp.alpha);
    const Vec3 v = point_velocity(s, cp.bone, a);
    apply_force_at(s, cp.bone, -stage.h * (s.implicit.control_stiffness[c] * v), a);
  }
}

void control_springs_augment(const Scene& scene, const ImplicitStage& stage, SimState& s) {
  ArticulatedBodyData& d = s.joint_space.articulated;
  const double h = stage.h;
  for (std::size_t k = 0; k < scene.control_points.size(); ++k) {
    const ControlPoint& cp = scene.control_points[k];
    const Vec3 r = point_on_bone(s.frames, cp.bone, cp.alpha) - d.point_world[cp.bone];
    add_point_element(h * h * s.implicit.control_stiffness[k], r, s.implicit.accel_bias[cp.bone],
                      d.inertia_art[cp.bone], d.bias_force[cp.bone]);
  }
}

void control_springs_mode_stiffness(const Scene& scene, const SimState& s,
                                    const std::vector<Vec3>& targets, ModeStiffness& out) {
  const EngineParams& p = scene.params;
  for (std::size_t c = 0; c < scene.control_points.size(); ++c) {
    const ControlPoint& cp = scene.control_points[c];
    const Vec3 a = point_on_bone(s.frames, cp.bone, cp.alpha);
    const Mat3 K = spring_tangent(cp.spring_in(p), cp.k_in(p), cp.cap_in(p), targets[c] - a);
    if (!K.isZero(0.0)) out.points.push_back({cp.bone, a, K});
  }
}

void control_springs_pose_forces(const Scene& scene, const SimState& s, PoseForces& out) {
  for (std::size_t c = 0; c < scene.control_points.size(); ++c) {
    const ControlPoint& cp = scene.control_points[c];
    out.point(cp.bone, point_on_bone(s.frames, cp.bone, cp.alpha), s.control_force_world[c]);
  }
}

}  // namespace physik
