// PhysIK embedded in an animation tool: a session owns a scene's rig, parameters and simulation
// state, takes target updates as the tool sends them (once per frame, as a user drags a control
// point), and either advances the physics a few steps (live, with its secondary motion) or solves
// the pose.
//
//   PosingSession session(scene);                 // allocates every buffer, once
//   session.set_target(0, p);                     // no allocation
//   session.advance(k);                           // k steps of the scene's engine; no allocation
//   SolveResult r = session.solve(rule);          // until the residual rule says stop
//
// solve() has two methods (SolveRule::method). The equilibrium solve (the default, and `physik
// solve --solver physik`) minimises the potential with a trust region whose steps are implicit
// steps at rest (physik/engine/equilibrium_solve.h): the rest pose, in about as many O(n)
// recursions as DLS takes iterations, never diverging. The time-stepping solve (`--solver
// physik-steps`, and the scene's own engine at its dt, `physik-explicit`) runs the physics:
// solve() by time steps is the paper's run-to-convergence used as an IK solver (Choi 2019, Sec. 6:
// "it may be beneficial to pair the physical simulation with CCD or some other fast IK solver. The
// challenge here would be figuring out when to stop the physical simulation and switch over"): the
// physics runs until every control point is within the tolerance of its target, or until the
// residual stops improving (the run monitor's stall rule, physik/engine/run_monitor.h), and then,
// when the rule names a finish, hands the pose to CCD or DLS (physik/ik/ik_solver.h) to close the
// rest. The switch-over rule is therefore the stall rule: "the residual stopped improving by
// stall_fraction of itself over stall_steps steps".
//
// Frames and units: targets and poses are world frame, rig units; the state is the engine's
// SimState (physik/engine/state.h). Nothing is allocated by set_target, set_pose, advance, or a
// solve without a finish (tests/engine_alloc_test.cpp counts allocations; the behaviour is tested
// in tests/posing_session_test.cpp); a classic finish allocates inside the IK solver, and so does
// set_target under damping auto (it recomputes the linearised modes).
#pragma once

#include <vector>

#include "physik/engine/equilibrium_solve.h"
#include "physik/engine/measures.h"
#include "physik/engine/run_monitor.h"
#include "physik/engine/run_summary.h"
#include "physik/engine/state.h"
#include "physik/ik/ik_solver.h"

namespace physik {

enum class SolveFinish {
  kNone,  // physics only
  kCcd,   // physics for the transient, then CCD
  kDls,   // physics for the transient, then damped least squares
};

// The time-stepping solve mode's defaults (physik solve --solver physik-steps): chosen on
// the ik_comparison targets (docs/ik.md "The time-stepping solve mode")
constexpr double kSolveDtGrowth = 2.0;  // 1, per settling step
constexpr double kSolveMaxDt = 1000.0;  // s

// The reach of a scene's goals (physik/ik chain_reach), rig units: the longest chain from the root
// to a control point's attachment, or to the tail of a bone with an orientation target, an aim or
// (at its point) a pin.
double goals_reach(const Scene& scene);

enum class SolveMethod {
  kEquilibrium,  // the equilibrium solve (physik/engine/equilibrium_solve.h): `--solver physik`
  kSteps,        // time steps of the scene's engine (`physik-steps` with dt_growth,
                 // `physik-explicit` at the scene's dt)
};

struct SolveRule {
  SolveMethod method = SolveMethod::kEquilibrium;
  double tolerance = 0.0;            // rig units, the position goals'; 0 = tolerance_fraction *
                                     // goals_reach
  double tolerance_fraction = 1e-4;  // 1, of the goals' reach (as the classic solvers)
  double tolerance_angle = 0.0;      // rad, the orientation targets' and aims'; 0 = the position
                                     // tolerance over the goals' reach (as DLS's orientation rows)
  int max_steps = 2000;              // physics steps, or the equilibrium's iterations, at most
  int stall_steps = 0;               // steps or iterations; 0 = the method's (kStallSteps,
                                     // kStallIterations): stalled when no goal short of its
                                     // tolerance improved by stall_fraction of itself over them
  double stall_fraction = 0.01;      // 1
  // The equilibrium solve's first trial step, s (its trust region lengthens and shortens it),
  // and its joints' armature, a fraction of the rig's inertia about its root (equilibrium_solve.h:
  // 0 = the rig's own inertia and dampers as the metric; more moves the joints more alike, as DLS
  // does, fewer iterations on long chains and less secondary motion).
  double initial_step = 1.0;
  double armature = kArmature;
  // The time-stepping solve mode on the implicit step: the step starts at the scene's dt, so the
  // body follows with its secondary motion, and lengthens by dt_growth each step the kinetic
  // energy falls, up to max_dt, carrying the dynamics into a quasi-static solve (a large implicit
  // step is a Gauss-Newton step on the spring and torsion potential, damped by the rig's own
  // inertia and dampers, docs/DESIGN.md). A step the energy guard had to split
  // (physik/engine/implicit_advance.h) shortens the next by dt_growth, not below dt: a trust
  // region, as Levenberg-Marquardt's damping. The equations of motion stay the scene's (its
  // dampers are set by its dt: physik::step(scene, state, h)); only the step changes. 1 = off.
  // InputError unless implicit. solve() throws InputError for a rule out of range (tolerances
  // negative or not finite, max_steps < 0, stall_steps < 0, stall_fraction outside [0, 1),
  // dt_growth < 1, max_dt or initial_step not positive, armature negative, any NaN).
  double dt_growth = 1.0;  // 1, per settling step
  double max_dt = 1.0;     // s
  SolveFinish finish = SolveFinish::kNone;
  IkOptions finish_options;  // the classic finish's options (its tolerance is ours)
};

// The stall windows of the two methods when the rule gives none.
constexpr int kStallSteps = 50;      // time steps
constexpr int kStallIterations = 6;  // equilibrium iterations

struct SolveResult {
  SolveMethod method = SolveMethod::kEquilibrium;
  bool converged = false;        // every goal within its tolerance at the end (measures.h: by its
                                 // own measure)
  bool diverged = false;         // the physics diverged; the session is back where the solve
                                 // started: its pose at rest, step count, targets and their
                                 // interpolation (a retry is the same solve)
  bool stalled = false;          // the physics stopped improving short of the tolerance (the stall
                                 // rule stopped it)
  bool out_of_steps = false;     // the physics reached rule.max_steps short of the tolerance, still
                                 // improving (a classic finish may then have converged)
  bool stationary = false;       // the equilibrium solve stopped at a stationary point of the
                                 // potential short of a goal (out of reach, against a limit)
  int steps = 0;                 // physics steps, or equilibrium iterations (trials), of this solve
  int refused = 0;               // the equilibrium's trials its trust region refused (of steps)
  int finish_iterations = 0;     // iterations of the classic finish (0 = none ran)
  double residual = 0.0;         // rig units, the goal residual at the end (measures.h)
  double final_dt = 0.0;         // s, the length of the last step taken (equilibrium: its h)
  double tolerance = 0.0;        // rig units, the one used
  double tolerance_angle = 0.0;  // rad, the one used
  GoalTolerance goal_tolerance() const { return {tolerance, tolerance_angle}; }
};

// The solve mode's step length, a trust region as Levenberg-Marquardt's damping: after a step
// that the energy guard split, shorter by `growth` (not below dt); after one whose kinetic energy
// did not grow, longer by it (up to max_dt, or dt if that is longer); else the same. s.
struct StepLength {
  double dt = 0.0;      // s, the scene's step: the shortest
  double max_dt = 0.0;  // s, the longest
  double growth = 1.0;  // 1, per step
  double next(double h, bool split, double ke, double previous_ke) const;
};

// The engine settings of the solve mode: scheme implicit, and the potential's own torsion
// torque (torsion_torque gradient), so that a solved pose with loaded torsion springs is a
// minimum of the potential `physik equilibrium` minimises (the paper's per-axis torque is not
// its gradient at large bends; with its tangent in the step it solves as fast:
// physik/engine/torsion_springs.h).
void use_solve_mode(EngineParams& params);
// The same for a loaded scene, where a torsion torque the scene file or an override gave
// explicitly (Scene::params_given) stays the one used; InputError when they gave an integration
// other than implicit (the solve mode is the implicit step).
void use_solve_mode(Scene& scene);

// The rule of the time-stepping solve mode (physik-steps): method kSteps, the step growing by
// kSolveDtGrowth up to kSolveMaxDt.
SolveRule steps_mode_rule();
// The rule of the solve mode (physik): the equilibrium solve, SolveRule's defaults.
SolveRule solve_mode_rule();

class PosingSession {
 public:
  // Copies the scene and puts its initial pose in (init_state). Throws InputError for a scene
  // whose control points name bones the rig does not have.
  explicit PosingSession(const Scene& scene);

  int num_control_points() const { return static_cast<int>(scene_.control_points.size()); }
  // Move control point c's target. interpolate = false jumps (a drag: the spring pulls toward
  // the new point at once); true moves it along the scene's interpolation, as a schedule would
  // (from where its pull is now: the old target, or after set_pose the point on the new pose).
  // Under damping auto the damping is chosen again for the new targets, as a run does when its
  // schedule moves one (allocates). Throws InputError for a bad index or a non-finite target.
  void set_target(int c, const Vec3& target_world, bool interpolate = false);

  // Bone targets (scene.h OrientationTarget, AimTarget, Pin), at most one of each kind per bone:
  // set adds the bone's target or replaces it, clear removes it (false when it had none). The
  // engine reads them from the session's scene at every step, so a change between steps is
  // the next step's. Checked as a scene file's (physik/model/bone_targets.h, InputError naming
  // the method): the bone in the rig, a unit quaternion, an aim point off its bone's head in the
  // pose now, no pin on a welded bone, not under implicit_linearisation full. Under damping auto
  // the damping is chosen again, as set_target does. They allocate (the scene's lists); the step
  // does not. A solve's residual and convergence stay the control points'.
  void set_orientation_target(const OrientationTarget& target);
  void set_aim_target(const AimTarget& target);
  void set_pin(const Pin& pin);
  bool clear_orientation_target(int bone);
  bool clear_aim_target(int bone);
  bool clear_pin(int bone);

  // `steps` steps of the scene's engine (its integration, joint solve and dt).
  StepStats advance(int steps = 1);

  // Run to the rule (see the top of this file). The session continues from the result (the
  // equilibrium solve leaves it at rest). The equilibrium solve runs in the solve mode's engine
  // settings (use_solve_mode) whatever the session's, and puts the session's back after.
  // `observer`, when given, sees the state after every physics step of the solve (as
  // run_scene's; not the classic finish). Throws InputError when the scene has no control point.
  SolveResult solve(const SolveRule& rule = {}, const StepObserver& observer = nullptr);

  // Put a pose in, at rest (velocities zero). The targets stay; each control point's pull
  // starts again from its point on the new pose and moves to its target along the scene's
  // interpolation, as at the scene's start, so a solve from here is a fresh session's with this
  // initial pose (the step count goes on: a scene's schedule, keyed by step, is not replayed).
  // Throws InputError for a pose of the wrong size or a non-unit rotation.
  void set_pose(const Pose& pose);

  // The goal residual (physik/engine/measures.h), rig units: the largest distance of any control
  // point from its target, or arc of an orientation target or aim (its turn times its bone's
  // length); what solve() stops on.
  double residual() const;

  // The run monitor's summary of the last solve (its steps, energy ledger, limit violation, the
  // energy guard's split steps, ...) with the session's state as the final one, as run_scene's
  // summary of the same run; after a classic finish the final pose is the finished one and
  // `converged` the solve's verdict. Allocates (the summary's vectors).
  RunSummary summary(const SolveResult& result) const;

  const Scene& scene() const { return scene_; }
  const SimState& state() const { return state_; }
  const BoneFrames& frames() const { return state_.frames; }
  const Pose& pose() const { return state_.pose; }

 private:
  bool finish_with(const SolveRule& rule, double tolerance, SolveResult& out);
  void solve_by_steps(const SolveRule& rule, const StepObserver& observer, SolveResult& out);
  void solve_by_equilibrium(const SolveRule& rule, const StepObserver& observer, SolveResult& out);
  void check_target_bone(int bone, const char* method) const;
  void targets_changed();

  Scene scene_;
  SimState state_;
  std::vector<IkGoal> goals_;      // (ncontrol) the control points as IK goals
  std::vector<double> residuals_;  // (ncontrol) scratch, rig units
  // where the current solve started (a divergence returns there): the pose, the state's step,
  // and the targets with their interpolation (a schedule may move them during the solve)
  Pose start_pose_;
  int start_step_ = 0;
  std::vector<Vec3> start_goal_world_, start_effective_world_;  // (ncontrol) rig units
  std::vector<int> start_interp_left_;                          // (ncontrol) steps
  double start_damping_auto_ = 0.0;                             // N s/m
  RunMonitor monitor_{RunRules{}};    // the solve's verdicts, restarted from the state each solve
  GoalProgress progress_;             // the time-stepping solve's stall rule, per goal
  EquilibriumWorkspace equilibrium_;  // the equilibrium solve's, sized once
  RunRules scene_rules_;              // run_rules(scene_), taken once (its start energy allocates)
};

}  // namespace physik
