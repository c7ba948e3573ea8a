#include "physik/engine.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "physik/control_springs.h"
#include "physik/damping.h"
#include "physik/integrate.h"
#include "physik/interpolation.h"
#include "physik/joint_forces.h"
#include "physik/newton_euler.h"
#include "physik/torsion_springs.h"

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

StepStats step(const Scene& scene, SimState& s) {
  const Rig& rig = scene.rig;
  const EngineParams& p = scene.params;

  update_targets(scene, s);
  local_rotations_from_world(rig, s.frames, s.pose);
  prepare_bodies(rig, p, s);
  apply_damping(rig, p, s);
  apply_control_springs(scene, s);
  apply_torsion_springs(rig, p, s);
  const auto t0 = std::chrono::steady_clock::now();
  const JointSolveStats js = solve_joint_forces(rig, p, s);
  const auto t1 = std::chrono::steady_clock::now();
  integrate(rig, p, s);

  s.step += 1;
  s.time += p.dt;
  local_rotations_from_world(rig, s.frames, s.pose);

  StepStats st;
  st.passes = js.passes;
  st.mismatch = js.mismatch;
  st.joint_solve_s = std::chrono::duration<double>(t1 - t0).count();
  st.kinetic_energy = kinetic_energy(rig, s);
  for (std::size_t c = 0; c < scene.control_points.size(); ++c) {
    const ControlPoint& cp = scene.control_points[c];
    st.max_residual = std::max(
        st.max_residual, (point_on_bone(s.frames, cp.bone, cp.alpha) - s.target_goal_world[c]).norm());
  }
  st.joint_separation = max_joint_separation(rig, s.frames);
  return st;
}

namespace {

bool state_finite(const SimState& s) {
  for (std::size_t i = 0; i < s.com_world.size(); ++i) {
    if (!s.com_world[i].allFinite() || !s.vel_world[i].allFinite() ||
        !s.omega_world[i].allFinite() || !s.frames.orient_world[i].coeffs().allFinite()) {
      return false;
    }
  }
  return true;
}

}  // namespace

RunSummary run_scene(const Scene& scene, const StepObserver& observer) {
  const auto t0 = std::chrono::steady_clock::now();
  const Rig& rig = scene.rig;
  SimState s;
  init_state(scene, s);
  RunSummary out;

  const double speed_tol = scene.speed_tol();
  const double energy_bound = scene.divergence_energy();
  const double mass = rig.total_mass();
  int last_event = 0;  // the last step at which a target changed
  for (const TargetChange& t : scene.schedule) last_event = std::max(last_event, t.step);
  int rest_run = 0;   // consecutive steps at rest
  long total_passes = 0;

  for (int k = 0; k < scene.steps; ++k) {
    const StepStats st = step(scene, s);
    out.steps_run = s.step;
    total_passes += st.passes;
    out.max_passes_in_a_step = std::max(out.max_passes_in_a_step, st.passes);
    out.peak_kinetic_energy = std::max(out.peak_kinetic_energy, st.kinetic_energy);
    out.max_joint_separation = std::max(out.max_joint_separation, st.joint_separation);
    out.max_limit_violation_deg =
        std::max(out.max_limit_violation_deg, rad2deg(max_limit_violation(rig, s.pose)));

    // divergence: a non-finite state, or energy past the bound
    if (!std::isfinite(st.kinetic_energy) || !state_finite(s)) {
      out.diverged = true;
      out.divergence_reason = "non-finite state at step " + std::to_string(s.step);
    } else if (st.kinetic_energy > energy_bound) {
      out.diverged = true;
      out.divergence_reason = "kinetic energy " + std::to_string(st.kinetic_energy) +
                              " J passed the bound " + std::to_string(energy_bound) +
                              " J at step " + std::to_string(s.step);
    }
    if (observer) observer(s, st);
    if (out.diverged) break;

    // at rest: mass-weighted rms speed below the tolerance, with no target still moving
    bool moving_target = false;
    for (int left : s.interp_steps_left) moving_target = moving_target || left > 0;
    const bool at_rest = !moving_target && s.step > last_event &&
                         std::sqrt(2.0 * st.kinetic_energy / mass) < speed_tol;
    rest_run = at_rest ? rest_run + 1 : 0;
    if (rest_run >= scene.convergence.settle_steps) {
      if (!out.converged) out.steps_to_converge = s.step - rest_run + 1;
      out.converged = true;
      if (scene.convergence.stop_when_converged) break;
    } else if (rest_run == 0) {
      out.converged = false;
      out.steps_to_converge = -1;
    }
  }

  control_residuals(scene, s, out.final_residuals);
  out.final_kinetic_energy = kinetic_energy(rig, s);
  out.mean_passes_per_step = out.steps_run ? double(total_passes) / out.steps_run : 0.0;
  out.final_pose = s.pose;
  out.final_frames = s.frames;
  out.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

nlohmann::json summary_to_json(const Scene& scene, const RunSummary& s) {
  const double h = scene.rig.height();
  nlohmann::json rel = nlohmann::json::array();
  for (double r : s.final_residuals) rel.push_back(r / h);
  return {{"scene", scene.file},
          {"rig", scene.rig_file},
          {"params", params_to_json(scene.params)},
          {"converged", s.converged},
          {"diverged", s.diverged},
          {"divergence_reason", s.divergence_reason},
          {"steps_run", s.steps_run},
          {"steps_to_converge", s.steps_to_converge < 0 ? nlohmann::json(nullptr)
                                                         : nlohmann::json(s.steps_to_converge)},
          {"final_residuals", s.final_residuals},
          {"final_residuals_over_height", rel},
          {"rig_height", h},
          {"max_joint_separation", s.max_joint_separation},
          {"mean_passes_per_step", s.mean_passes_per_step},
          {"max_passes_in_a_step", s.max_passes_in_a_step},
          {"peak_kinetic_energy", s.peak_kinetic_energy},
          {"final_kinetic_energy", s.final_kinetic_energy},
          {"max_limit_violation_deg", s.max_limit_violation_deg},
          {"speed_tol", scene.speed_tol()},
          {"residual_tol", scene.residual_tol()},
          {"wall_time_s", s.wall_time_s}};
}

}  // namespace physik
