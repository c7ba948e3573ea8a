// Automatic tuning of engine coefficients with Ceres (docs/engine.md "Ceres").
//
// The problem. A scene's run is a map p -> trajectory. We choose p (damping, spring stiffnesses,
// ...) inside bounds [lo, hi] to minimise a least-squares objective over the run:
//
//   settle:  J(p) = 1/2 sum_{n=1..N} sum_c  rho_n,c(p)^2, one residual per step and control point,
//     log measure (default):  rho = sqrt(dt) ln(1 + e/eps)
//     linear measure:         rho = sqrt(dt) e / H
//   e = min(|a_c(x_n) - t_c|, R H): control point c on its bone after step n to its goal target
//   (rig units), H the rig's height, eps the scene's residual tolerance (1e-3 H by default),
//   dt the time step (s). Slow settling keeps residuals up for many steps, oscillation brings
//   them back: both cost. The log measure counts every decade of error alike, so J is about
//   (time to reach eps) x ln^2 of the error ratio: it sees the slow tail of a run, where the
//   linear measure (the integral of squared error, ISE) is dominated by the first steps of the
//   approach and prefers little damping (in 1 DOF: damping ratio 1/2, see tests/tune). R =
//   kResidualCap caps an error; a run that diverges (non-finite state or energy past the scene's
//   bound) gets the cap for every remaining step: a large but finite penalty.
//
//   mujoco:  system identification. MuJoCo's same-forces run of the scene with its own
//   coefficients (reference/mujoco_runner.h: exact articulated dynamics under PhysIK's control,
//   torsion and damping forces) is recorded once, for the steps it lasts (N_ref); then
//     rho_n,e = sqrt(dt) min(|x_n,e(PhysIK; p) - x_n,e(MuJoCo)| / H, R)
//   over every bone endpoint e (head, tail) for n = 1..N_ref: the coefficients with which the
//   joint-force heuristic best follows the exact trajectory. Divergence gets the cap as above.
//
// Why this method. The run is explicit Euler with an iterative joint solve whose pass count
// jumps with its stopping rule, and a divergence cliff beyond a parameter-dependent bound: J(p)
// is continuous almost everywhere but only piecewise smooth, its derivatives are useless at
// machine-precision steps and meaningless across the cliff, and automatic differentiation
// through the engine is not available (nor wanted in the core). So:
//   1. coarse scan: every tuned parameter on a log-spaced grid over its bounds (coordinate-wise,
//      the others held at their current best), which finds the basin and stays off the cliff;
//   2. Ceres refine: Levenberg-Marquardt on the residual vector rho(u), u = ln p, started at the
//      scan's best point, with the bounds as Ceres parameter bounds on u. The Jacobian is a
//      central difference with a deliberately large step (du = fd_step, 2% of p by default),
//      which averages over the small jumps of the joint solver (a smoothed objective) — Ceres'
//      NumericDiffCostFunction only offers steps relative to |u|, which degenerate at p = 1.
// Least squares fits: J is a sum of squares of per-step errors, LM uses J^T J as the Hessian.
// Working in ln p makes the bounds positive by construction and the steps relative.
//
// The baseline. The tuned values are compared with the scene as it runs: J of the scene itself
// (initial_cost), not of a stand-in. A scene with "damping": "auto" runs at damping auto's choice
// (physik/engine/linear_modes.h), not at params.damping (which it never reads): the search starts
// at that choice, and a tuned damping replaces auto with a fixed value. Auto chooses again when
// the targets change; a fixed value cannot, so then the start's J (start_cost) may differ from
// the scene's and only initial_cost is the baseline.
#pragma once

#include <string>
#include <vector>

#include "physik/engine/engine.h"
#include "physik/model/scene.h"

namespace physik::tune {

// Names accepted by --params, with their default bounds: the parameter table's rows with tuning
// bounds (physik/model/params.h).
struct TunableSpec {
  std::string name;
  double lo = 0.0;  // default lower bound (same unit as the parameter)
  double hi = 0.0;  // default upper bound
  const char* unit = "";
};
const std::vector<TunableSpec>& tunable_parameters();

enum class Objective { kSettle, kMujoco };
enum class SettleMeasure { kLog, kLinear };
Objective objective_from_string(const std::string& name, const std::string& source);
const char* to_string(Objective o);
SettleMeasure measure_from_string(const std::string& name, const std::string& source);
const char* to_string(SettleMeasure m);

struct TuneParam {
  std::string name;
  double lo = 0.0, hi = 0.0;  // bounds, > 0
};

// "damping,control_k" -> parameters with default bounds; throws InputError naming `source`
// for an unknown or repeated name.
std::vector<TuneParam> parse_tune_params(const std::string& csv, const std::string& source);
// "damping=0.1:10" overrides the bounds of a listed parameter.
void apply_bounds(std::vector<TuneParam>& params, const std::string& spec,
                  const std::string& source);

// The parameter's value in a scene, and a scene with it set (through the parameter table).
// Control points that give no k (cap) take params.control_k (control_cap) at use, so they follow;
// a k or cap a point gives itself stays fixed.
double get_param(const Scene& scene, const std::string& name);
void set_param(Scene& scene, const std::string& name, double value);

constexpr double kResidualCap = 10.0;  // R: a residual never exceeds 10 rig heights

struct TuneOptions {
  std::vector<TuneParam> params;  // what to tune
  Objective objective = Objective::kSettle;
  SettleMeasure measure = SettleMeasure::kLog;
  int scan_points = 13;                 // per parameter in the coarse scan (0: no scan)
  int scan_sweeps = 1;                  // coordinate-wise sweeps over the parameters
  int max_iterations = 50;              // Ceres iterations
  double fd_step = 0.02;                // central-difference step in ln p
  bool verbose = false;                 // progress lines on stderr
  const Scene* mujoco_scene = nullptr;  // mujoco objective: the scene MuJoCo runs (same rig and
                                        // control points; default: the tuned scene as given)
};

struct ScanPoint {
  std::vector<double> values;  // parameter values (in params order)
  double cost = 0.0;           // J
  bool diverged = false;
  int steps_to_converge = -1;
};

struct TuneResult {
  std::vector<std::string> names;
  // before / after; before = the values the scene runs with (damping auto: its choice at the
  // start pose), which the search starts from (clamped into the bounds)
  std::vector<double> initial_values, values;
  double initial_cost = 0.0;  // J of the scene as it runs (the baseline: damping auto stays auto)
  double start_cost = 0.0;    // J where the search starts: initial_values clamped into the bounds
                              // and fixed (equal to initial_cost unless clamped, or unless damping
                              // auto chose again at a target change)
  bool damping_auto = false;  // the scene chooses its damping ("damping": "auto")
  double damping_auto_value = 0.0;  // N s/m, damping auto's choice at the start pose
  int damping_auto_updates = 0;     // how often the scene's run chose it (start + target changes)
  double scan_cost = 0.0;           // J at the scan's best point
  double final_cost = 0.0;          // J after Ceres
  int evaluations = 0;  // simulations run at values within the bounds (the tuned run's included)
  int diverged_evaluations = 0;  // of them, those that diverged (the tuned run's included)
  int scene_evaluations = 0;     // simulations of the scene as it is (baseline, scene_run)
  double wall_time_s = 0.0;
  std::string ceres_brief, ceres_full;
  bool ceres_usable = false;    // Ceres' termination was not a failure
  std::vector<ScanPoint> scan;  // the coarse scan, in order
  int reference_steps = 0;      // mujoco objective: steps of the MuJoCo reference compared
  RunSummary scene_run;         // the scene run as it is (the baseline's convergence)
  RunSummary tuned_run;         // the scene run with the tuned values
  Scene tuned_scene;
};

// The settle objective's residual vector (size steps x control points) for a scene as it is.
// Returns the run's summary as well (diverged, steps_to_converge).
RunSummary settle_residuals(const Scene& scene, SettleMeasure measure,
                            std::vector<double>& residuals);
double cost_of(const std::vector<double>& residuals);  // 1/2 sum r^2

// The mujoco objective's reference: every bone's head and tail after each step of MuJoCo's
// same-forces run of `scene` (as it is). A run that diverged, or raised a MuJoCo warning (its
// buffers full: mujoco_runner.h mujoco_warning), is no reference: every candidate would be
// compared with a run that stopped (J the same at every value); throws DivergedRun with the
// reason and what to try (mujoco_hint).
std::vector<BoneFrames> mujoco_reference_trajectory(const Scene& scene);
// Its residual vector (size reference steps x 2 nbone) for a scene as it is.
RunSummary mujoco_residuals(const Scene& scene, const std::vector<BoneFrames>& reference,
                            std::vector<double>& residuals);

// InputError when a tuned parameter cannot change the run (the scheme does not read it, or every
// control point overrides it). Check the result with tune_failure: every run may have
// diverged, or the tuned one.
TuneResult tune_scene(const Scene& scene, const TuneOptions& options);

// True when the tuned values are no better than the scene as it runs (J not below initial_cost):
// then there is no improvement to report.
bool no_improvement(const TuneResult& result);

// "" when the tuning found a value worth using; else why not, in one line (every candidate
// diverged, or the tuned run did).
std::string tune_failure(const TuneResult& result);

// True when the tuned run converges and no later than the scene's (which may not converge at
// all): the one outcome `physik tune` exits 0 with.
bool converges_no_later(const TuneResult& result);

// "" when the objective and the convergence step agree (both better, or both no better); else the
// two measures side by side, e.g. "objective lower, convergence later: step 52 -> 61" (a run that
// never converges: "never").
std::string measures_disagree(const TuneResult& result);

}  // namespace physik::tune
