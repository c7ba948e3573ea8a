#include "physik/engine/potential.h"

#include <cmath>

#include "physik/engine/contacts.h"

namespace physik {

double control_spring_potential(SpringLaw law, double k, double cap, double d) {
  if (law == SpringLaw::kLinear || d <= cap) return 0.5 * k * d * d;
  return k * cap * (d - 0.5 * cap);
}

double torsion_spring_potential(SpringLaw law, double k, double cap, double excess) {
  const double d = std::abs(excess);
  if (law == SpringLaw::kLinear || d <= cap) return 0.5 * k * d * d;
  return k * cap * (d - 0.5 * cap);
}

Vec3 torsion_excess(const std::array<AxisLimit, 3>& limits, double tolerance, const Quat& q) {
  Vec3 e = Vec3::Zero();
  if (!limits[0].limited && !limits[1].limited && !limits[2].limited) return e;
  const Vec3 theta = rotation_vector(q);
  for (int k = 0; k < 3; ++k) {
    if (limits[k].limited) e[k] = torsion_excess(limits[k], tolerance, theta[k]);
  }
  return e;
}

double control_potential(const Scene& scene, const std::vector<Vec3>& attach_world,
                         const std::vector<Vec3>& targets_world) {
  double u = 0.0;
  for (std::size_t c = 0; c < scene.control_points.size(); ++c) {
    const ControlPoint& cp = scene.control_points[c];
    u += control_spring_potential(cp.spring_in(scene.params), cp.k_in(scene.params),
                                  cp.cap_in(scene.params),
                                  (attach_world[c] - targets_world[c]).norm());
  }
  return u;
}

double torsion_potential(const Rig& rig, const EngineParams& params, const Pose& pose) {
  if (params.torsion_k == 0.0) return 0.0;
  double u = 0.0;
  for (int i = 0; i < rig.nbone; ++i) {
    const Vec3 e =
        torsion_excess(rig.bone_limit[i], params.torsion_tolerance, pose.bone_local_rotation[i]);
    for (int k = 0; k < 3; ++k) {
      if (e[k] != 0.0) {
        u += torsion_spring_potential(params.torsion_spring, params.torsion_k, params.torsion_cap,
                                      e[k]);
      }
    }
  }
  return u;
}

double spring_potential(const Scene& scene, const SimState& s) {
  double u = 0.0;
  for (std::size_t c = 0; c < scene.control_points.size(); ++c) {
    const ControlPoint& cp = scene.control_points[c];
    u += control_spring_potential(
        cp.spring_in(scene.params), cp.k_in(scene.params), cp.cap_in(scene.params),
        (point_on_bone(s.frames, cp.bone, cp.alpha) - s.target_effective_world[c]).norm());
  }
  return u + torsion_potential(scene.rig, scene.params, s.pose);
}

double potential_energy(const Scene& scene, const SimState& s) {
  double u = spring_potential(scene, s);
  // both terms are absent, not 0 + u, for a scene without them: its energies stay bit for bit
  if (!scene.gravity_world.isZero(0.0)) u += gravity_potential(scene, s.frames);
  if (scene.collision.any()) u += contact_potential(scene, s);
  return u;
}

}  // namespace physik
