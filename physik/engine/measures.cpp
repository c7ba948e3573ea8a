#include "physik/engine/measures.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

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

int goal_count(const Scene& scene) {
  return static_cast<int>(scene.control_points.size() + scene.orientation_targets.size() +
                          scene.aim_targets.size());
}

GoalRef goal_ref(const Scene& scene, int g) {
  const int ncp = static_cast<int>(scene.control_points.size());
  const int nori = static_cast<int>(scene.orientation_targets.size());
  if (g < ncp) return {GoalKind::kControlPoint, g};
  if (g < ncp + nori) return {GoalKind::kOrientation, g - ncp};
  return {GoalKind::kAim, g - ncp - nori};
}

double goal_residual(const Scene& scene, const SimState& s, int g) {
  return goal_residual(scene, s.frames, s.target_goal_world, g);
}

double goal_residual(const Scene& scene, const BoneFrames& f, const std::vector<Vec3>& targets,
                     int g) {
  const GoalRef r = goal_ref(scene, g);
  switch (r.kind) {
    case GoalKind::kControlPoint: {
      const ControlPoint& cp = scene.control_points[r.index];
      return (point_on_bone(f, cp.bone, cp.alpha) - targets[r.index]).norm();
    }
    case GoalKind::kOrientation:
      return orientation_residual(f, scene.orientation_targets[r.index]);
    case GoalKind::kAim:
      return aim_residual(f, scene.aim_targets[r.index]);
  }
  return 0.0;
}

std::string goal_label(const Scene& scene, int g) {
  const GoalRef r = goal_ref(scene, g);
  const auto named = [&](const char* what, const std::string& name, int bone) {
    std::string out = std::string(what) + " ";
    if (!name.empty()) out += "'" + name + "' ";
    return out + (r.kind == GoalKind::kAim ? "of '" : "on '") + scene.rig.bone_name[bone] + "'";
  };
  switch (r.kind) {
    case GoalKind::kControlPoint: {
      const ControlPoint& c = scene.control_points[r.index];
      return named(("control point " + std::to_string(r.index)).c_str(), c.name, c.bone);
    }
    case GoalKind::kOrientation: {
      const OrientationTarget& t = scene.orientation_targets[r.index];
      return named("orientation target", t.name, t.bone);
    }
    case GoalKind::kAim: {
      const AimTarget& t = scene.aim_targets[r.index];
      return named("aim", t.name, t.bone);
    }
  }
  return "";
}

const char* goal_unit(GoalKind kind) {
  return kind == GoalKind::kControlPoint ? "rig units" : "rad";
}

bool goals_met(const Scene& scene, const SimState& s, const GoalTolerance& tol) {
  const int n = goal_count(scene);
  for (int g = 0; g < n; ++g) {
    if (!(goal_residual(scene, s, g) < tol.of(goal_ref(scene, g).kind))) return false;
  }
  return true;
}

void GoalProgress::restart(const Scene& scene, int now, int window, double fraction) {
  const std::size_t n = static_cast<std::size_t>(goal_count(scene));
  best_.assign(n, std::numeric_limits<double>::infinity());
  improved_.assign(n, now);
  window_ = window;
  fraction_ = fraction;
}

bool GoalProgress::observe(const Scene& scene, const SimState& s, const GoalTolerance& tol,
                           int now) {
  int last = -1;  // the latest improvement of a goal still short
  for (std::size_t g = 0; g < best_.size(); ++g) {
    const int gi = static_cast<int>(g);
    const double excess = goal_residual(scene, s, gi) / tol.of(goal_ref(scene, gi).kind);
    if (excess < 1.0) {  // met: a goal that falls short again counts from then
      best_[g] = std::numeric_limits<double>::infinity();
      improved_[g] = now;
      continue;
    }
    if (excess < (1.0 - fraction_) * best_[g]) {  // the first finite one always
      best_[g] = excess;
      improved_[g] = now;
    }
    last = std::max(last, improved_[g]);
  }
  return last >= 0 && now - last >= window_;
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
