// A scene's control points solved as IK goals, by a classic solver (physik/ik/ik_solver.h) or by
// the PhysIK engine run to its residual tolerance: what `physik solve` does, shared by the CLI
// and the Python module (its summary.json: physik/io/summary_io.h solve_summary_to_json).
//
// The engine as a solver, both through physik::PosingSession (posing_session.h):
//   physik           the solve mode: scheme implicit (linearised backward Euler over the
//                    exact articulated solve) with torsion_torque gradient (the potential's own
//                    torque, whose rest poses are the potential's minima), the step starting at
//                    the scene's dt (the body follows with its secondary motion), lengthening by
//                    dt_growth every step the kinetic energy falls, up to max_dt, shorter again
//                    after a step the energy guard split (a long implicit step is a Gauss-Newton
//                    step on the spring and torsion potential: the quasi-static solve)
//   physik-explicit  the scene's own engine as it stands, at its dt
// Both stop at the residual tolerance (1e-4 of the chain's reach unless --tol), or when the
// residual stops improving (no 1% in 50 steps), and then, with finish ccd|dls, hand the pose
// to CCD or DLS (the paper's suggested hybrid). time_s is the solve's alone: the session (the
// rig, the state, every buffer) is built before the clock starts, as a tool holds it.
#pragma once

#include <string>
#include <vector>

#include "physik/engine/run_summary.h"
#include "physik/ik/ik_solver.h"
#include "physik/model/scene.h"
#include "physik/posing/posing_session.h"
#include "physik/posing/solve_options.h"

namespace physik {

// Every control point at its final target (the last scheduled change, if any).
std::vector<IkGoal> scene_goals(const Scene& scene);
// The goals of DLS and the Jacobian transpose: scene_goals, then every pin as a position goal
// (its point onto its world point), then every orientation target as an orientation-only goal
// (the solvers weigh every goal alike: a target's k, law and cap are the engine's alone).
std::vector<IkGoal> classic_goals(const Scene& scene);

struct SceneSolveResult {
  std::string solver;   // the options' solver
  bool engine = false;  // the engine solved (physik, physik-explicit), else a classic solver
  Scene scene;          // the scene as solved (the solve mode's settings applied)
  double time_s = 0.0;  // s, the solve's alone (the session is built before the clock)
  // the engine: the session's run summary (its final pose the solved one), the solve's result
  // and the rule it followed
  RunSummary run;
  SolveResult solve;
  SolveRule rule;
  // a classic solver's report: residuals one per control point (rig units), the residual the
  // largest over the control points and pins, orientation_residuals one per orientation target
  // (rad)
  IkReport classic;
  std::vector<double> pin_residuals;  // rig units, a classic solver's, one per pin
  BoneFrames frames;                  // the solved pose's frames
  Pose pose;                          // and its local rotations
  bool diverged = false;              // the engine's run diverged (the CLI exits 3)
  std::string warning;  // the engine's joint-solve warning (RunSummary::joint_solve_warning)
};

// A goal of the solved scene by its own measure (physik/engine/measures.h): its label, residual
// and tolerance (rig units for a control point, rad for an orientation target or an aim).
struct GoalReport {
  std::string goal;  // goal_label: "control point 0 on 'hand.L'", "aim of 'head'", ...
  GoalKind kind = GoalKind::kControlPoint;
  double residual = 0.0;   // rig units or rad
  double tolerance = 0.0;  // the same unit
  bool met() const { return residual < tolerance; }
};
// Every goal of the solve at its final pose, against the solve's tolerances (the engine's, or a
// classic solver's position and orientation tolerances).
std::vector<GoalReport> goal_reports(const SceneSolveResult& result);

// Why a solve that did not diverge stopped short of its tolerance, in one line ("" when it
// converged or diverged): the classic solver stalled or used its iterations, or the engine's
// physics stalled or used the scene's steps (and what a classic finish then left), with the
// residual and the tolerance (rig units), then every goal short of its tolerance and by how much
// ("short: aim of 'head' 0.012 rad (tolerance 0.0001 rad)"). `physik solve` prints it and exits
// 4; the summary gives it as "not_converged_reason", and the goals as "goals" and "short_goals".
std::string solve_shortfall(const SceneSolveResult& result);

// Solvers that live above the core (kdl/: Orocos KDL, `--solver kdl|kdl-nr`), registered by their
// layer (the CLI's and the Python module's start call kdl::register_solvers): the core never
// sees their libraries. InputError from solve_scene for a solver of kSceneSolvers that this
// program has not registered.
using OutsideSolver = SceneSolveResult (*)(const Scene& scene, const SceneSolveOptions& options);
void register_outside_solver(const std::string& name, OutsideSolver solver);

// Solve `scene` (taken by value: the engine's run changes its convergence settings).
// `observer`, when given, sees the engine's state after every physics step of its solve
// (PosingSession::solve; a classic solver has none). InputError for bad options (named as
// `spelling` says) or a scene without control points.
SceneSolveResult solve_scene(Scene scene, const SceneSolveOptions& options,
                             OptionSpelling spelling = OptionSpelling::kFlag,
                             const StepObserver& observer = nullptr);

}  // namespace physik
