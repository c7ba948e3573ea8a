#include "physik/engine/engine.h"

#include <chrono>
#include <cmath>

#include "physik/engine/forces.h"
#include "physik/engine/implicit_advance.h"
#include "physik/engine/integrate.h"
#include "physik/engine/integrate_joint_space.h"
#include "physik/engine/interpolation.h"
#include "physik/engine/joint_forces.h"
#include "physik/engine/linear_modes.h"
#include "physik/engine/newton_euler.h"
#include "physik/engine/run_monitor.h"
#include "physik/engine/subnormals.h"
#include "physik/model/errors.h"

namespace physik {

void set_pose(const Scene& scene, SimState& s, const Pose& pose, const Vec3& velocity_world) {
  const Rig& rig = scene.rig;
  forward_kinematics(rig, pose, s.frames);
  for (int i = 0; i < rig.nbone; ++i) {
    s.com_world[i] = bone_centre_world(s.frames, i);
    s.vel_world[i] = velocity_world;
    s.omega_world[i].setZero();
  }
  s.pose = pose;
  // a welded bone's rotation is its weld's, whatever the pose said (kinematics.h)
  welded_local_rotations(rig, s.frames, s.pose);
  // the exact and implicit schemes integrate the joint-space state: take it from the world view
  if (scene.params.joint_space()) init_joint_space(rig, s);
}

void init_state(const Scene& scene, SimState& s) {
  check_scene_joints(scene);
  size_state(scene, s);
  set_pose(scene, s, scene.initial_pose, scene.initial_velocity_world);
  for (std::size_t c = 0; c < scene.control_points.size(); ++c) {
    start_pull_from_attachment(scene, s, static_cast<int>(c), scene.control_points[c].target_world);
  }
  if (scene.params.damping_auto) update_auto_damping(scene, s);
}

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

bool targets_change_now(const Scene& scene, const SimState& s) {
  for (const TargetChange& t : scene.schedule) {
    if (t.step == s.step) return true;
  }
  return false;
}

// --- the schemes: each fills the stats of its solve (passes or substeps, mismatch, time) --------

// The joint angles of the scheme's new world frames. A bone that did not turn this step and
// whose parent did not either (both angular velocities exactly zero: integrate.h rotate_by left
// both orientations as they were) keeps its joint angle: recomputed from the frames, an angle of
// exactly 0 at rest comes back as round-off (1e-16 rad), which the torsion springs of locked axes
// turn into torques, and an unstable step (the paper's scheme at dt 0.05 on a converted MuJoCo
// humanoid) grows them into a run that leaves its rest by itself.
void refresh_pose_gauss_seidel(const Rig& rig, SimState& s) {
  s.pose.root_head_world = s.frames.head_world[0];
  for (int i = 0; i < rig.nbone; ++i) {
    const int p = rig.bone_parent[i];
    const bool still = s.omega_world[i].isZero(0.0) && (p < 0 || s.omega_world[p].isZero(0.0));
    if (!still) s.pose.bone_local_rotation[i] = local_rotation_from_world(rig, s.frames, i);
  }
}

void step_gauss_seidel(const Scene& scene, SimState& s, double h, StepStats& st) {
  const Rig& rig = scene.rig;
  const auto t0 = Clock::now();
  apply_forces(scene, s);
  if (rig.has_welds()) prepare_welded_bodies(rig, scene.params, s);  // welded groups as bodies
  const JointSolveStats js = solve_joint_forces(rig, scene.params, s);
  st.joint_solve_s = seconds_since(t0);
  st.passes = js.passes;
  st.mismatch = js.mismatch;
  if (scene.params.free_rods) {
    integrate_free_rods(rig, scene.params, h, s);
  } else {
    integrate_articulated(rig, scene.params, h, s);
  }
  refresh_pose_gauss_seidel(rig, s);
}

void step_exact(const Scene& scene, SimState& s, double h, StepStats& st) {
  const auto t0 = Clock::now();
  apply_forces(scene, s);
  st.passes = solve_articulated(scene.rig, scene.params, s).passes;  // 1: no iteration
  st.joint_solve_s = seconds_since(t0);
  integrate_joint_space(scene.rig, h, s);  // s.pose is its ball state: not rebuilt from the frames
}

// the energy guard's last check measured KE and U of the state the step ends in: the step's
// measures take them (the same values) rather than measuring that state again
void step_implicit(const Scene& scene, SimState& s, double h, StepStats& st) {
  const auto t0 = Clock::now();
  MeasuredEnergy end;
  st.substeps = advance_implicit(scene, s, h, take_implicit_step, nullptr, &end);
  st.joint_solve_s = seconds_since(t0);
  if (end.known) {
    st.kinetic_energy = end.kinetic;
    st.energy_measured = true;
    st.potential_energy = end.potential;
  }
}

// one step of h (s): the table of contents of engine.h
StepStats take_step(const Scene& scene, SimState& s, double h) {
  update_targets(scene, s);
  if (scene.params.damping_auto && s.step > 0 && targets_change_now(scene, s)) {
    update_auto_damping(scene, s);
  }
  StepStats st;
  switch (scene.params.scheme) {
    case Scheme::kGaussSeidel:
      step_gauss_seidel(scene, s, h, st);
      break;
    case Scheme::kExact:
      step_exact(scene, s, h, st);
      break;
    case Scheme::kImplicit:
      step_implicit(scene, s, h, st);
      break;
  }
  s.step += 1;
  s.time += h;
  if (!st.energy_measured) st.kinetic_energy = kinetic_energy(scene.rig, s);
  st.max_residual = max_goal_residual(scene, s);
  st.joint_separation = max_joint_separation(scene.rig, s.frames);
  return st;
}

}  // namespace

// each step with subnormals flushed (flush_subnormals, subnormals.h), the caller's modes restored
StepStats step(const Scene& scene, SimState& s) {
  const FlushSubnormals flushed(scene.params.flush_subnormals);
  return take_step(scene, s, scene.params.dt);
}

StepStats step(const Scene& scene, SimState& s, double h) {
  if (scene.params.scheme != Scheme::kImplicit) {
    throw_input_error(scene.file, "params", "scheme",
                      "a step of another length than dt needs scheme implicit");
  }
  if (!(h > 0.0) || !std::isfinite(h)) {
    throw_input_error(scene.file, "step", "h", "the step length must be positive and finite");
  }
  const FlushSubnormals flushed(scene.params.flush_subnormals);
  return take_step(scene, s, h);
}

RunSummary run_scene(const Scene& scene, const StepObserver& observer, bool observe_initial) {
  const auto t0 = Clock::now();
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
  out.wall_time_s = seconds_since(t0);
  return out;
}

}  // namespace physik
