// A scene's control points solved as IK goals, by a classic solver (physik/ik/ik_solver.h) or by
// the PhysIK engine run to its residual tolerance: what `physik solve` does, shared by the CLI
// and the Python module. The summary has `physik simulate`'s keys for the engine and the classic
// solvers' report keys otherwise, plus "solver", "iterations" and "time_s".
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "physik/ik/ik_solver.h"
#include "physik/model/scene.h"

namespace physik {

// The options of `physik solve`; errors name the CLI's flags (--solver, --tol, ...).
struct SceneSolveOptions {
  std::string solver;               // fabrik|ccd|jt|dls|mass-spring|rotation|physik
  double tol = 0.0;                 // rig units; 0 = 1e-4 of the reach
  int max_iterations = 1000;        // classic solvers
  double lambda = 0.0;              // rig units, DLS damping; 0 = 0.02 of the reach
  std::string jacobian = "analytic";   // analytic | fd
  std::vector<double> gravity;      // rig units/s^2, empty or three components (mass-spring)
  double rotation_damping = 0.8;    // rotation method, in [0, 1]
  std::string socket = "twist-bend";   // twist-bend | virtual-bone
  std::string cone = "elliptical";     // none | circular | elliptical
  bool no_limits = false;           // classic solvers ignore the rig's limits
};

extern const char* const kSceneSolvers;  // "fabrik|ccd|jt|dls|mass-spring|rotation|physik"

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
