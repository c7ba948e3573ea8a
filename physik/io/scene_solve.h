// A scene's control points solved as IK goals, by a classic solver (physik/ik/ik_solver.h) or by
// the PhysIK engine run to its residual tolerance: what `physik solve` does, shared by the CLI
// and the Python module. The summary has `physik simulate`'s keys for the engine and the classic
// solvers' report keys otherwise, plus "solver", "iterations" and "time_s".
//
// The engine as a solver (issue 15), both through physik::PosingSession (physik/posing):
//   physik           the solve mode: scheme implicit (linearised backward Euler over the
//                    exact articulated solve) with torsion_torque gradient (the potential's own
//                    torque, whose rest poses are the potential's minima), the step starting at the scene's dt
//                    (the body follows with its secondary motion) and lengthening by dt_growth
//                    every step the kinetic energy falls, up to max_dt, shorter again after a
//                    step the energy guard split (a long implicit step is a Gauss-Newton step on
//                    the spring and torsion potential: the quasi-static solve)
//   physik-explicit  the scene's engine as it stands (by default the paper's scheme) at its dt
// Both stop at the residual tolerance (1e-4 of the chain's reach unless --tol), or when the
// residual stops improving (no 1% in 50 steps), and then, with finish ccd|dls, hand the pose
// to CCD or DLS (the paper's suggested hybrid). time_s is the solve's alone: the session (the
// rig, the state, every buffer) is built before the clock starts, as a tool holds it.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "physik/ik/ik_solver.h"
#include "physik/model/scene.h"
#include "physik/posing/posing_session.h"

namespace physik {

// The options of `physik solve`; errors name the CLI's flags (--solver, --tol, ...).
struct SceneSolveOptions {
  std::string solver;               // fabrik|ccd|jt|dls|mass-spring|rotation|physik|physik-explicit
  double tol = 0.0;                 // rig units; 0 = 1e-4 of the reach
  int max_iterations = 1000;        // classic solvers
  double lambda = 0.0;              // rig units, DLS damping; 0 = 0.02 of the reach
  std::string jacobian = "analytic";   // analytic | fd
  std::vector<double> gravity;      // rig units/s^2, empty or three components (mass-spring)
  double rotation_damping = 0.8;    // rotation method, in [0, 1]
  std::string socket = "twist-bend";   // twist-bend | virtual-bone
  std::string cone = "elliptical";     // none | circular | elliptical
  bool no_limits = false;           // classic solvers ignore the rig's limits
  // the engine's solvers (physik, physik-explicit)
  double dt_growth = kSolveDtGrowth;  // 1, physik: the step's growth per settling step
  double max_dt = kSolveMaxDt;        // s, physik: the longest step
  std::string finish = "none";        // none | ccd | dls: the classic finish after a stall
};

extern const char* const kSceneSolvers;  // "fabrik|...|rotation|physik|physik-explicit"

// The checks that need no scene (solver name, tolerance, iterations, gravity); InputError.
void check_solve_options(const SceneSolveOptions& options);

// Every control point at its final target (the last scheduled change, if any).
std::vector<IkGoal> scene_goals(const Scene& scene);

struct SceneSolveResult {
  nlohmann::json summary;  // summary.json of `physik solve`
  BoneFrames frames;       // the solved pose's frames
  Pose pose;               // and its local rotations
  bool diverged = false;   // the engine's run diverged (the CLI exits 3)
  std::string warning;     // the engine's joint-solve warning (RunSummary::joint_solve_warning)
};

// Solve `scene` (taken by value: the engine's run changes its convergence settings).
// InputError for bad options or a scene without control points.
SceneSolveResult solve_scene(Scene scene, const SceneSolveOptions& options);

}  // namespace physik
