#include "physik/engine/engine.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "physik/engine/forces.h"
#include "physik/engine/implicit_advance.h"
#include "physik/engine/implicit_step.h"
#include "physik/engine/integrate.h"
#include "physik/engine/integrate_joint_space.h"
#include "physik/engine/interpolation.h"
#include "physik/engine/joint_forces.h"
#include "physik/engine/linear_modes.h"
#include "physik/engine/newton_euler.h"
#include "physik/engine/run_monitor.h"
#include "physik/model/errors.h"

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
  for (int i = 1; i < rig.nbone; ++i) {
    const int p = rig.bone_parent[i];
    const Vec3 joint = f.head_world[p] + f.orient_world[p] * rig.bone_head_in_parent[i];
    gap = std::max(gap, (f.head_world[i] - joint).norm());
  }
  return gap;
}

void control_residuals(const Scene& scene, const SimState& s, std::vector<double>& out) {
  out.resize(scene.control_points.size());
  for (std::size_t c = 0; c < scene.control_points.size(); ++c) {
    const ControlPoint& cp = scene.control_points[c];
    out[c] = (point_on_bone(s.frames, cp.bone, cp.alpha) - s.target_goal_world[c]).norm();
  }
}

void init_state(const Scene& scene, SimState& s) {
  const Rig& rig = scene.rig;
  size_state(rig, scene.control_points.size(), s);
  forward_kinematics(rig, scene.initial_pose, s.frames);
  for (int i = 0; i < rig.nbone; ++i) {
    s.com_world[i] = 0.5 * (s.frames.head_world[i] + s.frames.tail_world[i]);
    s.vel_world[i] = scene.initial_velocity_world;
  }
  s.pose = scene.initial_pose;
  if (scene.params.joint_solve == JointSolve::kExact) init_joint_space(rig, s);
  for (std::size_t c = 0; c < scene.control_points.size(); ++c) {
    start_pull_from_attachment(scene, s, static_cast<int>(c), scene.control_points[c].target_world);
  }
  if (scene.params.articulated_solve()) init_joint_space(rig, s);
  if (scene.params.integration == Integration::kImplicit) {
    // the energy guard's snapshots, one per halving depth (implicit_advance.h)
    s.implicit_snapshots.resize(static_cast<std::size_t>(scene.params.implicit_max_splits) + 1);
    for (JointStateSnapshot& snap : s.implicit_snapshots) {
      snap.joint_vel_local.assign(rig.nbone, Vec3::Zero());
      snap.bone_local_rotation.assign(rig.nbone, Quat::Identity());
    }
  }
  if (scene.params.damping_auto) update_auto_damping(scene, s);
}

namespace {

bool targets_change_now(const Scene& scene, const SimState& s) {
  for (const TargetChange& t : scene.schedule) {
    if (t.step == s.step) return true;
  }
  return false;
}

// one step of h (s): the table of contents of engine.h
StepStats take_step(const Scene& scene, SimState& s, double h) {
  const Rig& rig = scene.rig;
  const EngineParams& p = scene.params;

  update_targets(scene, s);
  if (p.damping_auto && s.step > 0 && targets_change_now(scene, s)) update_auto_damping(scene, s);
  const bool exact = p.articulated_solve();
  const bool implicit = p.integration == Integration::kImplicit;
  const auto t0 = std::chrono::steady_clock::now();
  JointSolveStats js;
  if (implicit) {
    // forces, the implicit solve and the joint-space update in one: a step that adds energy is
    // taken again in halves (implicit_advance.h), so the three cannot be separate stages here
    js = advance_implicit(scene, s, h);
  } else {
    apply_forces(scene, s);
    js = exact ? solve_articulated(rig, p, s) : solve_joint_forces(rig, p, s);
  }
  const auto t1 = std::chrono::steady_clock::now();
  if (!implicit && exact) {
    integrate_joint_space(rig, p, s);  // s.pose is its ball state: not rebuilt from the frames
  } else if (!implicit) {
    integrate(rig, p, s);
  }

  s.step += 1;
  s.time += h;
  if (!exact) local_rotations_from_world(rig, s.frames, s.pose);

  StepStats st;
  st.passes = js.passes;
  st.mismatch = js.mismatch;
  st.joint_solve_s = std::chrono::duration<double>(t1 - t0).count();
  st.kinetic_energy = kinetic_energy(rig, s);
  for (std::size_t c = 0; c < scene.control_points.size(); ++c) {
    const ControlPoint& cp = scene.control_points[c];
    const double r = (point_on_bone(s.frames, cp.bone, cp.alpha) - s.target_goal_world[c]).norm();
    if (!(r <= st.max_residual)) st.max_residual = r;  // a NaN residual stays NaN (std::max drops it)
  }
  st.joint_separation = max_joint_separation(rig, s.frames);
  return st;
}

}  // namespace

StepStats step(const Scene& scene, SimState& s) { return take_step(scene, s, scene.params.dt); }

StepStats step(const Scene& scene, SimState& s, double h) {
  if (scene.params.integration != Integration::kImplicit) {
    throw_input_error(scene.file, "params", "integration",
                      "a step of another length than dt needs integration implicit");
  }
  if (!(h > 0.0) || !std::isfinite(h)) {
    throw_input_error(scene.file, "step", "h", "the step length must be positive and finite");
  }
  return take_step(scene, s, h);
}

StepStats initial_stats(const Scene& scene, const SimState& s) {
  StepStats st;
  st.kinetic_energy = kinetic_energy(scene.rig, s);
  for (std::size_t c = 0; c < scene.control_points.size(); ++c) {
    const ControlPoint& cp = scene.control_points[c];
    const double r = (point_on_bone(s.frames, cp.bone, cp.alpha) - s.target_goal_world[c]).norm();
    if (!(r <= st.max_residual)) st.max_residual = r;
  }
  st.joint_separation = max_joint_separation(scene.rig, s.frames);
  return st;
}

RunSummary run_scene(const Scene& scene, const StepObserver& observer, bool observe_initial) {
  const auto t0 = std::chrono::steady_clock::now();
  SimState s;
  init_state(scene, s);
  if (observer && observe_initial) observer(s, initial_stats(scene, s));
  RunMonitor monitor(scene);  // convergence and divergence rules, run statistics
  for (int k = 0; k < scene.steps; ++k) {
    const StepStats st = step(scene, s);
    const bool stop = monitor.observe(observe_step(scene, s, st));
    if (observer) observer(s, st);
    if (stop) break;
  }
  RunSummary out = monitor.summary();
  monitor.fill_final(scene, s, out);
  out.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
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
