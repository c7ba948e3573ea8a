#include "physik/engine/interpolation.h"

#include <algorithm>
#include <cmath>

namespace physik {

Vec3 interpolate_step(Interpolation scheme, const Vec3& current, const Vec3& goal,
                      const Vec3& origin, double alpha, double fallback) {
  if (alpha >= 1.0 || scheme == Interpolation::kNone) return goal;
  const Vec3 d0 = current - origin, d1 = goal - origin;
  const double r0 = d0.norm(), r1 = d1.norm();
  if (scheme == Interpolation::kLinear || r0 < fallback || r1 < fallback) {
    return current + alpha * (goal - current);
  }
  const Vec3 u0 = d0 / r0, u1 = d1 / r1;
  const double theta = std::atan2(u0.cross(u1).norm(), u0.dot(u1));
  Vec3 n = u0.cross(u1);
  if (n.norm() < 1e-12) {
    // parallel: no turn needed; antiparallel: any axis perpendicular to u0
    if (theta < 1.0)
      n = Vec3::UnitZ();
    else
      n = u0.unitOrthogonal();
  }
  n.normalize();
  const double r = (1.0 - alpha) * r0 + alpha * r1;
  return origin + r * (Eigen::AngleAxisd(alpha * theta, n) * u0);
}

void start_target_jump(const Scene& scene, SimState& s, int c, const Vec3& goal) {
  s.target_goal_world[c] = goal;
  const EngineParams& p = scene.params;
  if (p.interpolation == Interpolation::kNone || p.interpolation_steps <= 1) {
    s.target_effective_world[c] = goal;
    s.interp_steps_left[c] = 0;
  } else {
    s.interp_steps_left[c] = p.interpolation_steps;
  }
}

void start_pull_from_attachment(const Scene& scene, SimState& s, int c, const Vec3& goal) {
  const ControlPoint& cp = scene.control_points[c];
  s.target_effective_world[c] = point_on_bone(s.frames, cp.bone, cp.alpha);
  start_target_jump(scene, s, c, goal);
}

void update_targets(const Scene& scene, SimState& s) {
  for (const TargetChange& t : scene.schedule) {
    if (t.step == s.step) start_target_jump(scene, s, t.control_point, t.target_world);
  }
  const EngineParams& p = scene.params;
  bool need_com = false;
  for (int left : s.interp_steps_left) need_com = need_com || left > 0;
  if (!need_com) return;
  Vec3 com = Vec3::Zero();
  if (p.interpolation == Interpolation::kPolarCom) {
    double m = 0.0;
    for (int i = 0; i < scene.rig.nbone; ++i) {
      com += scene.rig.bone_mass[i] * s.com_world[i];
      m += scene.rig.bone_mass[i];
    }
    com /= m;
  }
  for (std::size_t c = 0; c < scene.control_points.size(); ++c) {
    int& left = s.interp_steps_left[c];
    if (left <= 0) continue;
    const Vec3 origin = p.interpolation == Interpolation::kPolarHead
                            ? s.frames.head_world[scene.control_points[c].bone]
                            : com;
    s.target_effective_world[c] =
        interpolate_step(p.interpolation, s.target_effective_world[c], s.target_goal_world[c],
                         origin, 1.0 / left, p.interpolation_fallback);
    --left;
  }
}

}  // namespace physik
