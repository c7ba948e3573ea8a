// PosingSession: see posing_session.h (the solve rule and the hybrid switch-over).
#include "physik/posing/posing_session.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "physik/engine/engine.h"
#include "physik/engine/integrate_joint_space.h"
#include "physik/engine/interpolation.h"
#include "physik/engine/linear_modes.h"
#include "physik/engine/run_monitor.h"
#include "physik/model/bone_targets.h"
#include "physik/model/errors.h"
#include "physik/model/joint_angles.h"

namespace physik {

void use_solve_mode(EngineParams& params) {
  params.scheme = Scheme::kImplicit;
  params.torsion_torque = TorsionTorque::kGradient;
}

void use_solve_mode(Scene& scene) {
  const auto given = [&](const char* name) {
    return std::find(scene.params_given.begin(), scene.params_given.end(), name) !=
           scene.params_given.end();
  };
  if (given("scheme") && scene.params.scheme != Scheme::kImplicit) {
    throw_input_error(scene.file, "params", "scheme",
                      std::string("the solve mode is the implicit step, and the scene gives ") +
                          to_string(scene.params.scheme) +
                          " (its own engine solves with --solver physik-explicit)");
  }
  const TorsionTorque torque = scene.params.torsion_torque;
  use_solve_mode(scene.params);
  if (given("torsion_torque")) scene.params.torsion_torque = torque;
}

double StepLength::next(double h, bool split, double ke, double previous_ke) const {
  const double longest = std::max(max_dt, dt);
  if (split) return std::max(h / growth, dt);
  if (ke <= previous_ke) return std::min(h * growth, longest);
  return h;
}

SolveRule steps_mode_rule() {
  SolveRule rule;
  rule.method = SolveMethod::kSteps;
  rule.dt_growth = kSolveDtGrowth;
  rule.max_dt = kSolveMaxDt;
  return rule;
}

SolveRule solve_mode_rule() {
  return SolveRule{};
}

double goals_reach(const Scene& scene) {
  const Rig& rig = scene.rig;
  double r = 0.0;
  for (const ControlPoint& c : scene.control_points)
    r = std::max(r, rig.chain_length(c.bone, c.alpha));
  for (const OrientationTarget& t : scene.orientation_targets)
    r = std::max(r, rig.chain_length(t.bone, 1.0));
  for (const AimTarget& t : scene.aim_targets) r = std::max(r, rig.chain_length(t.bone, 1.0));
  for (const Pin& p : scene.pins) r = std::max(r, rig.chain_length(p.bone, p.alpha));
  return r;
}

PosingSession::PosingSession(const Scene& scene) : scene_(scene) {
  for (std::size_t c = 0; c < scene_.control_points.size(); ++c) {
    const ControlPoint& cp = scene_.control_points[c];
    if (cp.bone < 0 || cp.bone >= scene_.rig.nbone) {
      throw_input_error(scene_.file, "control_points[" + std::to_string(c) + "]", "bone",
                        "no such bone in the rig");
    }
    goals_.push_back({cp.bone, cp.alpha, cp.target_world});
  }
  init_state(scene_, state_);
  residuals_.resize(goals_.size());
  size_equilibrium(scene_, state_.contact.anchors.capacity(), equilibrium_);
  progress_.restart(scene_, 0, 1, 0.0);
  start_pose_ = state_.pose;
  start_goal_world_ = state_.target_goal_world;  // sized once: a solve copies without allocating
  start_effective_world_ = state_.target_effective_world;
  start_interp_left_ = state_.interp_steps_left;
  scene_rules_ = run_rules(scene_);
  monitor_.restart(scene_, state_, scene_rules_);  // sizes its buffers once
}

void PosingSession::set_target(int c, const Vec3& target_world, bool interpolate) {
  if (c < 0 || c >= num_control_points()) {
    throw_input_error("set_target", "", "control point",
                      "no control point " + std::to_string(c) + " (the scene has " +
                          std::to_string(num_control_points()) + ")");
  }
  if (!target_world.allFinite()) {
    throw_input_error("set_target", "", "target", "not finite");
  }
  if (interpolate) {
    start_target_jump(scene_, state_, c, target_world);
  } else {
    state_.target_goal_world[c] = target_world;
    state_.target_effective_world[c] = target_world;
    state_.interp_steps_left[c] = 0;
  }
  // as take_step does when the schedule moves a target (engine.cpp)
  if (scene_.params.damping_auto) update_auto_damping(scene_, state_);
}

void PosingSession::check_target_bone(int bone, const char* method) const {
  if (bone < 0 || bone >= scene_.rig.nbone) {
    throw_input_error(method, "", "bone",
                      "no bone " + std::to_string(bone) + " (the rig has " +
                          std::to_string(scene_.rig.nbone) + ")");
  }
}

// as set_target: the damping of damping auto follows the forces
void PosingSession::targets_changed() {
  if (scene_.params.damping_auto) update_auto_damping(scene_, state_);
}

void PosingSession::set_orientation_target(const OrientationTarget& target) {
  check_target_bone(target.bone, "set_orientation_target");
  OrientationTarget t = target;
  const Quat& q = t.target_world;
  // normalised within the tolerance; Python's binding has read the user's value and said so
  std::vector<std::string> warnings;
  t.target_world =
      target_quaternion(q.w(), q.x(), q.y(), q.z(), {"set_orientation_target", ""}, warnings);
  set_bone_target(scene_.orientation_targets, t);
  targets_changed();
}

void PosingSession::set_aim_target(const AimTarget& target) {
  check_target_bone(target.bone, "set_aim_target");
  AimTarget t = target;
  check_aim_target(scene_, state_.frames, t, {"set_aim_target", ""});
  set_bone_target(scene_.aim_targets, t);
  targets_changed();
}

void PosingSession::set_pin(const Pin& pin) {
  check_target_bone(pin.bone, "set_pin");
  check_pin(scene_, pin, {"set_pin", ""});
  set_bone_target(scene_.pins, pin);
  targets_changed();
}

bool PosingSession::clear_orientation_target(int bone) {
  const bool had = clear_bone_target(scene_.orientation_targets, bone);
  if (had) targets_changed();
  return had;
}

bool PosingSession::clear_aim_target(int bone) {
  const bool had = clear_bone_target(scene_.aim_targets, bone);
  if (had) targets_changed();
  return had;
}

bool PosingSession::clear_pin(int bone) {
  const bool had = clear_bone_target(scene_.pins, bone);
  if (had) targets_changed();
  return had;
}

StepStats PosingSession::advance(int steps) {
  StepStats st;
  for (int k = 0; k < steps; ++k) st = step(scene_, state_);
  return st;
}

void PosingSession::set_pose(const Pose& pose) {
  const Rig& rig = scene_.rig;
  if (static_cast<int>(pose.bone_local_rotation.size()) != rig.nbone) {
    throw_input_error("set_pose", "", "pose",
                      std::to_string(pose.bone_local_rotation.size()) +
                          " bone rotations for a rig of " + std::to_string(rig.nbone) + " bones");
  }
  for (int i = 0; i < rig.nbone; ++i) {
    const Quat& q = pose.bone_local_rotation[i];
    if (!q.coeffs().allFinite() || std::abs(q.norm() - 1.0) > 1e-6) {
      throw_input_error(
          "set_pose", "", "pose",
          "bone '" + rig.bone_name[i] + "': its rotation is not a finite unit quaternion");
    }
  }
  physik::set_pose(scene_, state_, pose);
  // each pull starts again from the point on the new pose, as init_state starts a scene
  for (int c = 0; c < num_control_points(); ++c) {
    start_pull_from_attachment(scene_, state_, c, state_.target_goal_world[c]);
  }
}

double PosingSession::residual() const {
  return max_goal_residual(scene_, state_);
}

namespace {

// a rule out of range is the caller's bad input (physik solve checks its own flags first)
// a solve pulls toward something: a control point, an orientation target or an aim
void check_has_goal(const Scene& s) {
  if (s.control_points.empty() && s.orientation_targets.empty() && s.aim_targets.empty()) {
    throw_input_error(s.file, "control_points", "",
                      "a solve needs a goal: a control point, an orientation target or an aim "
                      "(pins hold, they do not pull)");
  }
}

void check_rule(const SolveRule& r) {
  const auto bad = [](const char* field, const std::string& why) {
    throw_input_error("SolveRule", "", field, why);
  };
  if (!(r.tolerance >= 0.0) || !std::isfinite(r.tolerance))
    bad("tolerance", "must be finite and >= 0");
  if (!(r.tolerance_fraction > 0.0) || !std::isfinite(r.tolerance_fraction)) {
    bad("tolerance_fraction", "must be finite and > 0");
  }
  if (r.max_steps < 0) bad("max_steps", "must not be negative");
  if (r.stall_steps < 0) bad("stall_steps", "must not be negative (0: the method's)");
  if (!(r.stall_fraction >= 0.0 && r.stall_fraction < 1.0))
    bad("stall_fraction", "must be in [0, 1)");
  if (!(r.dt_growth >= 1.0) || !std::isfinite(r.dt_growth))
    bad("dt_growth", "must be finite and >= 1");
  if (!(r.max_dt > 0.0) || !std::isfinite(r.max_dt)) bad("max_dt", "must be finite and > 0");
  if (!(r.tolerance_angle >= 0.0) || !std::isfinite(r.tolerance_angle))
    bad("tolerance_angle", "must be finite and >= 0");
  if (!(r.initial_step > 0.0) || !std::isfinite(r.initial_step))
    bad("initial_step", "must be finite and > 0");
  if (!(r.armature >= 0.0) || !std::isfinite(r.armature))
    bad("armature", "must be finite and >= 0");
}

}  // namespace

namespace {

// the implicit step's counts (implicit_advance.h): a summary's are its solve's
void reset_guard_counts(SimState& s) {
  s.implicit.split_steps = s.implicit.max_substeps = s.implicit.gauss_newton_steps = 0;
  s.implicit.retaken_steps = s.implicit.unresolved_steps = s.implicit.deepest_steps = 0;
}

}  // namespace

SolveResult PosingSession::solve(const SolveRule& rule, const StepObserver& observer) {
  check_has_goal(scene_);
  check_rule(rule);
  const bool grow = rule.method == SolveMethod::kSteps && rule.dt_growth > 1.0;
  if (grow && scene_.params.scheme != Scheme::kImplicit) {
    throw_input_error(scene_.file, "params", "scheme",
                      "a lengthening step (dt_growth > 1) needs scheme implicit");
  }
  SolveResult out;
  out.method = rule.method;
  // where the solve starts, for a divergence to return to (same sizes: no allocation)
  start_pose_ = state_.pose;
  start_step_ = state_.step;
  start_goal_world_ = state_.target_goal_world;
  start_effective_world_ = state_.target_effective_world;
  start_interp_left_ = state_.interp_steps_left;
  start_damping_auto_ = state_.damping_auto_value;
  // the summary's are this solve's
  reset_guard_counts(state_);
  const double reach = goals_reach(scene_);
  out.tolerance = rule.tolerance > 0.0 ? rule.tolerance : rule.tolerance_fraction * reach;
  out.tolerance_angle = rule.tolerance_angle > 0.0 ? rule.tolerance_angle
                        : reach > 0.0              ? out.tolerance / reach
                                                   : rule.tolerance_fraction;
  if (rule.method == SolveMethod::kEquilibrium) {
    solve_by_equilibrium(rule, observer, out);
  } else {
    solve_by_steps(rule, observer, out);
  }
  out.residual = residual();
  if (!out.converged && !out.diverged && rule.finish != SolveFinish::kNone) {
    finish_with(rule, out.tolerance, out);
  }
  return out;
}

// The time-stepping solve: the scene's engine (implicit lengthening by dt_growth, or at its dt),
// its divergence judged by the run monitor, its goals by their own measure (measures.h).
void PosingSession::solve_by_steps(const SolveRule& rule, const StepObserver& observer,
                                   SolveResult& out) {
  const bool grow = rule.dt_growth > 1.0;
  RunRules rules = scene_rules_;
  rules.stop_at_residual = false;           // the goals' stop rule is below
  monitor_.restart(scene_, state_, rules);  // energy ledger from the state as it is now
  const GoalTolerance tol = out.goal_tolerance();
  const int window = rule.stall_steps > 0 ? rule.stall_steps : kStallSteps;
  progress_.restart(scene_, state_.step, window, rule.stall_fraction);
  // the step h: the scene's dt at first; longer by dt_growth after a step whose kinetic energy
  // fell, shorter by it (not below dt) after one the energy guard had to split
  const StepLength length{scene_.params.dt, rule.max_dt, rule.dt_growth};
  double h = scene_.params.dt, previous_ke = kinetic_energy(scene_.rig, state_);
  bool stop = false;
  while (!stop && out.steps < rule.max_steps) {
    const StepStats st = grow ? step(scene_, state_, h) : step(scene_, state_);
    ++out.steps;
    out.final_dt = h;
    if (observer) observer(state_, st);
    stop = monitor_.observe(observe_step(scene_, state_, st));
    if (grow) h = length.next(h, st.substeps > 1, st.kinetic_energy, previous_ke);
    previous_ke = st.kinetic_energy;
    if (stop) break;
    // a target the schedule or the interpolation still moves is waited for
    bool moving = state_.step <= scene_rules_.last_event;
    for (int left : state_.interp_steps_left) moving = moving || left > 0;
    if (moving) {
      progress_.restart(scene_, state_.step, window, rule.stall_fraction);
      continue;
    }
    out.converged = goals_met(scene_, state_, tol);
    stop = out.converged || progress_.observe(scene_, state_, tol, state_.step);
  }
  out.diverged = monitor_.diverged();
  if (out.diverged) {
    physik::set_pose(scene_, state_, start_pose_);
    state_.step = start_step_;
    state_.target_goal_world = start_goal_world_;
    state_.target_effective_world = start_effective_world_;
    state_.interp_steps_left = start_interp_left_;
    state_.damping_auto_value = start_damping_auto_;
    out.converged = false;
  }
  out.out_of_steps = !out.converged && !out.diverged && !stop;
  out.stalled = !out.converged && !out.diverged && stop;  // the stall rule stopped it
}

// The equilibrium solve in the solve mode's engine settings (the scheme implicit's joint-space
// state, the gradient torsion torque), the session's put back after.
void PosingSession::solve_by_equilibrium(const SolveRule& rule, const StepObserver& observer,
                                         SolveResult& out) {
  EngineParams& p = scene_.params;
  const Scheme scheme = p.scheme;
  const TorsionTorque torque = p.torsion_torque;
  p.scheme = Scheme::kImplicit;
  p.torsion_torque = TorsionTorque::kGradient;
  if (scheme == Scheme::kGaussSeidel) init_joint_space(scene_.rig, state_);
  monitor_.restart(scene_, state_, scene_rules_);  // the summary's counts: this solve's
  EquilibriumRule er;
  er.tolerance = out.goal_tolerance();
  er.max_iterations = rule.max_steps;
  er.stall_iterations = rule.stall_steps > 0 ? rule.stall_steps : kStallIterations;
  er.stall_fraction = rule.stall_fraction;
  er.initial_step = rule.initial_step;
  er.armature = rule.armature;
  const EquilibriumResult r = equilibrium_solve(scene_, state_, equilibrium_, er, observer);
  p.scheme = scheme;
  p.torsion_torque = torque;
  state_.step += r.iterations;
  out.steps = r.iterations;
  out.refused = r.refused;
  out.final_dt = r.step;
  out.converged = r.converged;
  out.stalled = r.stalled;
  out.stationary = r.stationary;
  out.out_of_steps = r.out_of_iterations;
}

RunSummary PosingSession::summary(const SolveResult& result) const {
  RunSummary out = monitor_.summary();
  monitor_.fill_final(scene_, state_, out);
  out.converged = result.converged;
  if (result.method == SolveMethod::kEquilibrium) {
    out.steps_run = result.steps;
    out.steps_to_converge = result.converged ? result.steps : -1;
    out.mean_passes_per_step = result.steps > 0 ? 1.0 : 0.0;
    out.max_passes_in_a_step = result.steps > 0 ? 1 : 0;
    // in the joints it solved in: the equilibrium solve runs the implicit scheme's whatever the
    // session's own scheme (solve_by_equilibrium)
    out.max_limit_violation_deg =
        rad2deg(max_limit_violation(scene_.rig, LockedAxes::kRemoved, state_.pose));
  }
  return out;
}

// The classic finish: the physics' pose is the start; the solved pose is put in at rest.
bool PosingSession::finish_with(const SolveRule& rule, double tolerance, SolveResult& out) {
  for (std::size_t c = 0; c < goals_.size(); ++c)
    goals_[c].target_world = state_.target_goal_world[c];
  IkOptions opt = rule.finish_options;
  opt.tolerance = tolerance;
  Pose pose = state_.pose;
  const IkReport rep =
      solve_ik(rule.finish == SolveFinish::kCcd ? IkMethod::kCcd : IkMethod::kDampedLeastSquares,
               scene_.rig, goals_, pose, opt);
  out.finish_iterations = rep.iterations;
  if (rep.residual > out.residual) return false;  // never hand back a worse pose
  physik::set_pose(scene_, state_, pose);  // the targets stay met: their pulls are not restarted
  out.residual = residual();
  out.converged = out.residual < tolerance;
  return true;
}

}  // namespace physik
