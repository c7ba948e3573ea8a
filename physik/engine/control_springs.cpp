#include "physik/engine/control_springs.h"

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

}  // namespace physik
