#include "physik/engine/torsion_springs.h"

#include <algorithm>
#include <cmath>

#include "physik/engine/potential.h"

namespace physik {

Vec3 torsion_torque_local(const std::array<AxisLimit, 3>& limits, const Vec3& theta,
                          const EngineParams& params) {
  Vec3 tau = Vec3::Zero();
  for (int k = 0; k < 3; ++k) {
    const AxisLimit& l = limits[k];
    if (!l.limited) continue;
    // the dead zone of potential.h: tau = -dU/dtheta
    double d = torsion_excess(l, params.torsion_tolerance, theta[k]);
    if (d == 0.0) continue;
    if (params.torsion_spring == SpringLaw::kCapped) {
      d = std::copysign(std::min(std::abs(d), params.torsion_cap), d);
    }
    tau[k] = params.torsion_k * d;
  }
  return tau;
}

namespace {

// per axis: k on an engaged axis within the cap; beyond the cap 0 (tangent) or k c / |d| (secant)
Vec3 axis_stiffness(const std::array<AxisLimit, 3>& limits, const Vec3& theta,
                    const EngineParams& params, bool secant_beyond_cap) {
  Vec3 k = Vec3::Zero();
  for (int a = 0; a < 3; ++a) {
    const AxisLimit& l = limits[a];
    if (!l.limited) continue;
    const double d = torsion_excess(l, params.torsion_tolerance, theta[a]);
    if (d == 0.0) continue;
    k[a] = params.torsion_k;
    if (params.torsion_spring == SpringLaw::kCapped && std::abs(d) > params.torsion_cap) {
      k[a] = secant_beyond_cap ? params.torsion_k * params.torsion_cap / std::abs(d) : 0.0;
    }
  }
  return k;
}

}  // namespace

Vec3 torsion_stiffness_local(const std::array<AxisLimit, 3>& limits, const Vec3& theta,
                             const EngineParams& params) {
  return axis_stiffness(limits, theta, params, false);
}

Vec3 torsion_step_stiffness_local(const std::array<AxisLimit, 3>& limits, const Vec3& theta,
                                  const EngineParams& params) {
  return axis_stiffness(limits, theta, params, true);
}

void apply_torsion_springs(const Rig& rig, const EngineParams& params, SimState& s) {
  if (params.torsion_k == 0.0) return;
  for (int i = 1; i < rig.nbone; ++i) {
    const auto& limits = rig.bone_limit[i];
    if (!limits[0].limited && !limits[1].limited && !limits[2].limited) continue;
    const Vec3 tau_local =
        torsion_torque_local(limits, rotation_vector(s.pose.bone_local_rotation[i]), params);
    if (tau_local.isZero(0.0)) continue;
    const int p = rig.bone_parent[i];
    const Vec3 tau_world = s.frames.orient_world[p] * (rig.bone_rest_orient_parent[i] * tau_local);
    s.torque_world[i] += tau_world;
    s.torque_world[p] -= tau_world;
  }
}

}  // namespace physik
