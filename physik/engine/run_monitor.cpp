#include "physik/engine/run_monitor.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <utility>

#include "physik/engine/implicit_advance.h"
#include "physik/engine/joint_forces.h"
#include "physik/engine/measures.h"
#include "physik/engine/potential.h"
#include "physik/model/joint_angles.h"
#include "physik/model/kinematics.h"
#include "physik/model/message_number.h"

namespace physik {

namespace {

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

}  // namespace

double initial_energy(const Scene& scene) {
  const double ke = 0.5 * scene.rig.total_mass() * scene.initial_velocity_world.squaredNorm();
  return ke + initial_potential_energy(scene);
}

RunRules run_rules(const Scene& scene) {
  RunRules r;
  r.speed_tol = scene.speed_tol();
  r.energy_bound = scene.convergence.divergence_energy;  // 0: the energy rule
  r.initial_energy = initial_energy(scene);
  r.energy_floor = 0.5 * scene.rig.total_mass() * r.speed_tol * r.speed_tol;
  r.total_mass = scene.rig.total_mass();
  for (const TargetChange& t : scene.schedule) r.last_event = std::max(r.last_event, t.step);
  r.settle_steps = scene.convergence.settle_steps;
  r.stop_when_converged = scene.convergence.stop_when_converged;
  r.stop_at_residual = scene.convergence.stop_at_residual_tol;
  r.residual_tol = scene.residual_tol();
  return r;
}

bool state_finite(const SimState& s) {
  // the bodies' motion, and what is written out of a state: its frames and its pose
  for (std::size_t i = 0; i < s.com_world.size(); ++i) {
    if (!s.com_world[i].allFinite() || !s.vel_world[i].allFinite() ||
        !s.omega_world[i].allFinite() || !s.frames.orient_world[i].coeffs().allFinite() ||
        !s.frames.head_world[i].allFinite() || !s.frames.tail_world[i].allFinite()) {
      return false;
    }
  }
  for (const Quat& q : s.pose.bone_local_rotation) {
    if (!q.coeffs().allFinite()) return false;
  }
  return s.pose.root_head_world.allFinite();
}

StepObservation observe_step(const Scene& scene, SimState& s, const StepStats& st) {
  StepObservation o;
  o.step = s.step;
  o.kinetic_energy = st.kinetic_energy;
  o.state_finite = state_finite(s);
  o.passes = st.iterations();
  o.joint_separation = st.joint_separation;
  o.limit_violation = max_limit_violation(scene.rig, scene.params.locked_axes(), s.pose);
  for (int left : s.interp_steps_left) o.target_moving = o.target_moving || left > 0;
  o.max_residual = st.max_residual;
  // U toward this step's targets: the targets are the state's, the attachments its frames'
  o.potential_energy = st.energy_measured ? st.potential_energy : potential_energy(scene, s);
  o.state = &s;
  o.unreached_joints = unreached_joints(scene.rig, s);
  return o;
}

RunMonitor::RunMonitor(const RunRules& rules, std::string reason_prefix)
    : rules_(rules), prefix_(std::move(reason_prefix)) {}

RunMonitor::RunMonitor(const Scene& scene, std::string reason_prefix)
    : RunMonitor(run_rules(scene), std::move(reason_prefix)) {
  // the ledger starts where init_state does: every target at its attachment point
  scene_ = &scene;
  const BoneFrames f = forward_kinematics(scene.rig, scene.initial_pose);
  for (const ControlPoint& cp : scene.control_points) {
    prev_attach_world_.push_back(point_on_bone(f, cp.bone, cp.alpha));
  }
  prev_targets_world_ = prev_attach_world_;
  last_finite_pose_ = scene.initial_pose;
  last_finite_step_ = 0;
  last_finite_ke_ = 0.5 * scene.rig.total_mass() * scene.initial_velocity_world.squaredNorm();
}

void RunMonitor::restart(const Scene& scene, SimState& s, const RunRules& rules) {
  rules_ = rules;
  scene_ = &scene;
  const double ke = kinetic_energy(scene.rig, s);
  rules_.initial_energy = ke + observe_step(scene, s, StepStats{}).potential_energy;
  const std::size_t n = scene.control_points.size();
  prev_attach_world_.resize(n);
  prev_targets_world_.resize(n);
  for (std::size_t c = 0; c < n; ++c) {
    const ControlPoint& cp = scene.control_points[c];
    prev_attach_world_[c] = point_on_bone(s.frames, cp.bone, cp.alpha);
    prev_targets_world_[c] = s.target_effective_world[c];
  }
  last_finite_pose_ = s.pose;
  last_finite_step_ = s.step;
  last_finite_ke_ = ke;
  target_work_ = peak_energy_ratio_ = 0.0;
  unpropagated_steps_ = max_unreached_ = 0;
  converged_ = diverged_ = false;
  reason_.clear();
  first_step_ = steps_run_ = s.step;
  steps_to_converge_ = -1;
  rest_run_ = 0;
  total_passes_ = 0;
  max_passes_ = 0;
  peak_ke_ = max_separation_ = max_violation_deg_ = 0.0;
  best_residual_ = std::numeric_limits<double>::infinity();
  last_improvement_ = s.step;
}

double RunMonitor::step_target_work(const StepObservation& o) {
  if (!o.state || !scene_) return o.target_work;
  // W = U_c(a before, t now) - U_c(a before, t before), then remember this step's a and t
  const SimState& s = *o.state;
  double w = 0.0;
  for (std::size_t c = 0; c < scene_->control_points.size(); ++c) {
    const ControlPoint& cp = scene_->control_points[c];
    const SpringLaw law = cp.spring_in(scene_->params);
    const double k = cp.k_in(scene_->params), cap = cp.cap_in(scene_->params);
    const Vec3& a = prev_attach_world_[c];
    w += control_spring_potential(law, k, cap, (a - s.target_effective_world[c]).norm()) -
         control_spring_potential(law, k, cap, (a - prev_targets_world_[c]).norm());
    prev_attach_world_[c] = point_on_bone(s.frames, cp.bone, cp.alpha);
    prev_targets_world_[c] = s.target_effective_world[c];
  }
  return w;
}

// divergence: a non-finite state, or energy past what the rig was given (or the fixed bound)
bool RunMonitor::check_divergence(const StepObservation& o) {
  // the reason's text is built only on a divergence: nothing allocated on a healthy step
  const auto at = [&] { return " at step " + std::to_string(o.step); };
  if (!std::isfinite(o.kinetic_energy) || !o.state_finite || o.engine_non_finite ||
      !std::isfinite(o.max_residual) || !std::isfinite(o.potential_energy)) {
    reason_ = prefix_ + "non-finite state" + at();
    return true;
  }
  if (rules_.energy_bound > 0.0) {
    if (o.kinetic_energy <= rules_.energy_bound) return false;
    reason_ = prefix_ + "kinetic energy " + num(o.kinetic_energy) + " J passed the bound " +
              num(rules_.energy_bound) + " J" + at();
    return true;
  }
  const double e = o.kinetic_energy + o.potential_energy;
  const double given = rules_.initial_energy + target_work_;
  const double scale = std::max(given, 0.0) + rules_.energy_floor;
  const double ratio =
      scale > 0.0 ? e / scale : (e > 0.0 ? std::numeric_limits<double>::infinity() : 0.0);
  peak_energy_ratio_ = std::max(peak_energy_ratio_, ratio);
  if (!(ratio > rules_.energy_multiple)) return false;
  reason_ = prefix_ + "energy " + num(e) + " J (kinetic " + num(o.kinetic_energy) + " J) passed " +
            num(rules_.energy_multiple) + " x the " + num(given) +
            " J the rig was given (initial energy and the targets' work; floor " +
            num(rules_.energy_floor) + " J)" + at();
  return true;
}

bool RunMonitor::observe(const StepObservation& o) {
  steps_run_ = o.step;
  total_passes_ += o.passes;
  max_passes_ = std::max(max_passes_, o.passes);
  // std::max keeps the old value against a NaN: the peak stays the last finite one
  peak_ke_ = std::max(peak_ke_, o.kinetic_energy);
  max_separation_ = std::max(max_separation_, o.joint_separation);
  max_violation_deg_ = std::max(max_violation_deg_, rad2deg(o.limit_violation));
  if (o.unreached_joints > 0) ++unpropagated_steps_;
  max_unreached_ = std::max(max_unreached_, o.unreached_joints);
  target_work_ += step_target_work(o);
  if (o.state && o.state_finite && std::isfinite(o.kinetic_energy)) {
    last_finite_pose_ = o.state->pose;  // same size every step: no allocation after the first
    last_finite_step_ = o.step;
    last_finite_ke_ = o.kinetic_energy;
  }

  diverged_ = check_divergence(o);
  if (diverged_) return true;

  // at rest: mass-weighted rms speed below the tolerance, with no target still moving
  const bool targets_still = !o.target_moving && o.step > rules_.last_event;
  const bool at_rest =
      targets_still && std::sqrt(2.0 * o.kinetic_energy / rules_.total_mass) < rules_.speed_tol;
  rest_run_ = at_rest ? rest_run_ + 1 : 0;
  if (rules_.stop_at_residual) {
    // IK use: converged = targets met; no progress for a while short of them = stalled
    if (targets_still && o.max_residual < rules_.residual_tol) {
      converged_ = true;
      steps_to_converge_ = o.step;
      return true;
    }
    if (!targets_still || o.max_residual < (1.0 - rules_.stall_fraction) * best_residual_) {
      best_residual_ = std::min(best_residual_, o.max_residual);
      last_improvement_ = o.step;
    }
    return o.step - last_improvement_ >= rules_.stall_steps;
  }
  if (rest_run_ >= rules_.settle_steps) {
    if (!converged_) steps_to_converge_ = o.step - rest_run_ + 1;
    converged_ = true;
    return rules_.stop_when_converged;
  }
  if (rest_run_ == 0) {
    converged_ = false;
    steps_to_converge_ = -1;
  }
  return false;
}

RunSummary RunMonitor::summary() const {
  RunSummary out;
  out.converged = converged_;
  out.diverged = diverged_;
  out.divergence_reason = reason_;
  const int run = steps_run_ - first_step_;
  out.steps_run = run;
  out.steps_to_converge = steps_to_converge_ < 0 ? -1 : steps_to_converge_ - first_step_;
  out.max_joint_separation = max_separation_;
  out.mean_passes_per_step = run ? double(total_passes_) / run : 0.0;
  out.max_passes_in_a_step = max_passes_;
  out.peak_kinetic_energy = peak_ke_;
  out.max_limit_violation_deg = max_violation_deg_;
  out.energy_given = rules_.initial_energy + target_work_;
  out.peak_energy_ratio = peak_energy_ratio_;
  out.joint_unpropagated_steps = unpropagated_steps_;
  out.max_unreached_joints = max_unreached_;
  if (unpropagated_steps_ > 0) {
    out.joint_solve_warning =
        "the joint solve stopped before its forces reached every joint in " +
        std::to_string(unpropagated_steps_) + " of " + std::to_string(run) + " steps (up to " +
        std::to_string(max_unreached_) + " joints accelerating at under " +
        num(kUnreachedFraction) +
        " of the largest joint acceleration); the motion of "
        "the far bones is wrong: set params.joint_eps_relative (e.g. 1e-3) to solve on";
  }
  return out;
}

void RunMonitor::fill_final(const Scene& scene, const SimState& s, RunSummary& out) const {
  if (state_finite(s) || last_finite_step_ < 0) {
    fill_final_state(scene, s, out);
    return;
  }
  out.final_pose_step = last_finite_step_;
  out.final_pose = last_finite_pose_;
  out.final_frames = forward_kinematics(scene.rig, last_finite_pose_);
  out.final_kinetic_energy = last_finite_ke_;
  out.final_residuals.resize(scene.control_points.size());
  for (std::size_t c = 0; c < scene.control_points.size(); ++c) {
    const ControlPoint& cp = scene.control_points[c];  // on the last finite frames
    out.final_residuals[c] =
        (point_on_bone(out.final_frames, cp.bone, cp.alpha) - s.target_goal_world[c]).norm();
  }
}

void fill_final_state(const Scene& scene, const SimState& s, RunSummary& out) {
  out.final_pose_step = s.step;
  control_residuals(scene, s, out.final_residuals);
  out.final_kinetic_energy = kinetic_energy(scene.rig, s);
  out.final_pose = s.pose;
  out.final_frames = s.frames;
  out.damping_auto_value = s.damping_auto_value;
  out.damping_auto_updates = s.damping_auto_updates;
  out.implicit_split_steps = s.implicit.split_steps;
  out.implicit_max_substeps = s.implicit.max_substeps;
  out.implicit_retaken_steps = s.implicit.retaken_steps;
  out.implicit_unresolved_steps = s.implicit.unresolved_steps;
  out.implicit_deepest_steps = s.implicit.deepest_steps;
  out.implicit_gauss_newton_steps = s.implicit.gauss_newton_steps;
}

namespace {

// semi-implicit Euler with -c v at both ends of a bone of mass m is stable in translation while
// 2 c dt / m < 2: c below the lightest bone's m / dt (N s/m)
double explicit_damping_bound(const Scene& scene) {
  double c_max = std::numeric_limits<double>::infinity();
  for (int i = 0; i < scene.rig.nbone; ++i) {
    c_max = std::min(c_max, scene.rig.bone_mass[i] / scene.params.dt);
  }
  return c_max;
}

}  // namespace

std::string divergence_hint(const Scene& scene) {
  const EngineParams& p = scene.params;
  const double dt = p.dt;  // s
  if (p.scheme == Scheme::kImplicit) {
    std::string hint = "try a smaller dt (now " + message_number(dt) + " s)";
    const ParamRow& splits = param_row("implicit_max_splits");
    const double most = splits.valid.hi ? *splits.valid.hi : p.implicit_max_splits;
    if (p.implicit_max_splits < most) {
      hint += " or more implicit_max_splits (now " + std::to_string(p.implicit_max_splits) +
              ", at most " + message_number(most) + ")";
    }
    return hint;
  }
  const double c_max = explicit_damping_bound(scene);
  std::string hint = "try --set preset=robust (the implicit step, stable at any dt and damping)";
  if (!p.damping_auto && p.damping >= c_max) {
    return hint + ", or damping below " + message_number(c_max) + " N s/m (now " +
           message_number(p.damping) + ")";
  }
  return hint + ", or a smaller dt (now " + message_number(dt) + " s)";
}

std::string energy_guard_warning(const Scene& scene, const RunSummary& run) {
  if (run.implicit_deepest_steps == 0 && run.implicit_unresolved_steps == 0) return "";
  const int splits = scene.params.implicit_max_splits;
  std::string out = "the implicit step's energy guard could not hold the energy of every step:";
  if (run.implicit_deepest_steps > 0) {
    out += " " + std::to_string(run.implicit_deepest_steps) + " split to implicit_max_splits (" +
           std::to_string(splits) + ": substeps of dt / " +
           message_number(std::ldexp(1.0, splits)) + ")" +
           (splits > 8 ? " or past the guard's " + std::to_string(kImplicitMaxChecks) +
                             " checks in one step, at the length each had then"
                       : std::string()) +
           ", taken unchecked there;";
  }
  if (run.implicit_unresolved_steps > 0) {
    out += " " + std::to_string(run.implicit_unresolved_steps) +
           " (sub)steps kept as they were where halving did not help (a first half ending no "
           "lower, or "
           "turning a joint as far as its whole step);";
  }
  return out + " " + divergence_hint(scene);
}

std::string not_converged_hint(const Scene& scene, const RunSummary& run) {
  const EngineParams& p = scene.params;
  std::string hint = "try more steps (--steps " + std::to_string(2L * std::max(run.steps_run, 1)) +
                     ", twice this run's)";
  if (p.damping_auto) {
    if (run.damping_auto_value > 0.0) {
      // damping auto damps the slowest mode critically; a stiff element elsewhere (a pin) can
      // leave the reach creeping instead of swinging, so both ways are named
      const double c = run.damping_auto_value;
      hint += ", or a fixed damping in place of damping auto's choice (" + message_number(c) +
              " N s/m): above it if the rig still swings (e.g. --set damping=" +
              message_number(2.0 * c) + "), below it if it creeps toward its targets (e.g. " +
              "--set damping=" + message_number(0.5 * c) + ")";
    }
  } else if (p.scheme == Scheme::kImplicit) {
    hint += ", more damping (now " + message_number(p.damping) + " N s/m" +
            (p.damping > 0.0 ? ", e.g. --set damping=" + message_number(2.0 * p.damping) : "") +
            ") or --set damping=auto";
  } else {
    if (p.damping > 0.0 && 2.0 * p.damping < explicit_damping_bound(scene)) {
      hint += ", more damping (--set damping=" + message_number(2.0 * p.damping) + ", now " +
              message_number(p.damping) + " N s/m)";
    }
    hint += ", or --set preset=robust (the implicit step with damping auto)";
  }
  return hint;
}

}  // namespace physik
