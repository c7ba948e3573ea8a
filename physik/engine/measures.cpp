#include "physik/engine/measures.h"

#include <algorithm>
#include <cstring>

#include "physik/engine/aim_springs.h"
#include "physik/engine/newton_euler.h"
#include "physik/engine/orientation_springs.h"

namespace physik {

double kinetic_energy(const Rig& rig, const SimState& s) {
  double e = 0.0;
  for (int i = 0; i < rig.nbone; ++i) {
    const Mat3 I = inertia_world(rig, s.frames.orient_world[i], i);
    e += 0.5 * rig.bone_mass[i] * s.vel_world[i].squaredNorm() +
         0.5 * s.omega_world[i].dot(I * s.omega_world[i]);
  }
  return e;
}

double max_joint_separation(const Rig& rig, const BoneFrames& f) {
  double gap = 0.0;
  // an anchored root's head from its anchor, its rest position
  if (rig.root_anchored()) gap = (f.head_world[0] - rig.bone_rest_head_world[0]).norm();
  for (int i = 1; i < rig.nbone; ++i) {
    const int p = rig.bone_parent[i];
    const Vec3 joint = f.head_world[p] + f.orient_world[p] * rig.bone_head_in_parent[i];
    gap = std::max(gap, (f.head_world[i] - joint).norm());
  }
  return gap;
}

double control_residual(const Scene& scene, const SimState& s, int c) {
  const ControlPoint& cp = scene.control_points[c];
  return (point_on_bone(s.frames, cp.bone, cp.alpha) - s.target_goal_world[c]).norm();
}

void control_residuals(const Scene& scene, const SimState& s, std::vector<double>& out) {
  out.resize(scene.control_points.size());
  for (std::size_t c = 0; c < out.size(); ++c)
    out[c] = control_residual(scene, s, static_cast<int>(c));
}

double max_control_residual(const Scene& scene, const SimState& s) {
  double r = 0.0;
  for (std::size_t c = 0; c < scene.control_points.size(); ++c) {
    const double d = control_residual(scene, s, static_cast<int>(c));
    if (!(d <= r)) r = d;  // a NaN residual stays NaN (std::max would drop it)
  }
  return r;
}

double max_turning_arc(const Scene& scene, const BoneFrames& f) {
  double r = 0.0;
  const auto take = [&r](double d) {
    if (!(d <= r)) r = d;  // NaN stays
  };
  for (const OrientationTarget& t : scene.orientation_targets) {
    take(orientation_residual(f, t) * scene.rig.bone_length[t.bone]);
  }
  for (const AimTarget& t : scene.aim_targets) {
    take(aim_residual(f, t) * scene.rig.bone_length[t.bone]);
  }
  return r;
}

double max_goal_residual(const Scene& scene, const SimState& s) {
  const double r = max_control_residual(scene, s), arc = max_turning_arc(scene, s.frames);
  return arc <= r ? r : arc;  // NaN stays
}

double orientation_residual(const BoneFrames& f, const OrientationTarget& t) {
  return orientation_error(f.orient_world[t.bone], t.target_world).norm();
}

double aim_residual(const BoneFrames& f, const AimTarget& t) {
  return aim_turn(f, t).turn.norm();
}

double pin_residual(const BoneFrames& f, const Pin& pin) {
  return (point_on_bone(f, pin.bone, pin.alpha) - pin.point_world).norm();
}

StepStats initial_stats(const Scene& scene, const SimState& s) {
  StepStats st;
  st.kinetic_energy = kinetic_energy(scene.rig, s);
  st.max_residual = max_goal_residual(scene, s);
  st.joint_separation = max_joint_separation(scene.rig, s.frames);
  return st;
}

std::uint64_t state_hash(const BoneFrames& f) {
  std::uint64_t h = 1469598103934665603ull;
  const auto mix = [&h](double v) {
    unsigned char bytes[sizeof(double)];
    std::memcpy(bytes, &v, sizeof(double));
    for (unsigned char b : bytes) {
      h ^= b;
      h *= 1099511628211ull;
    }
  };
  for (std::size_t i = 0; i < f.head_world.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      mix(f.head_world[i][k]);
      mix(f.tail_world[i][k]);
    }
    for (int k = 0; k < 4; ++k) mix(f.orient_world[i].coeffs()[k]);
  }
  return h;
}

}  // namespace physik
