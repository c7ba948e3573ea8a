// The options of a solve: `physik solve` flags, physik.solve's keywords and a scene file's "solve"
// object, all from one table (as the engine parameters are, physik/model/params.h): each row is
// the option's name (the scene key and the Python keyword; the flag is --name with dashes),
// kind, unit, default, valid values and a doc line; the CLI, Python and the scene reader loop over
// it, and the messages name the option as its caller spells it.
#pragma once

#include <string>
#include <vector>

#include "physik/posing/posing_session.h"

namespace physik {

// The orientation targets' and aims' tolerance unless --tol-angle: DLS's orientation tolerance at
// the default --tol (1e-4 of the reach over the reach: ik_solver.h)
constexpr double kDefaultTolAngle = 1e-4;  // rad

// The solver and its settings. Units: rig units, s, rad.
struct SceneSolveOptions {
  std::string solver;  // fabrik|ccd|jt|dls|mass-spring|rotation|kdl|kdl-nr|physik|physik-steps|
                       // physik-explicit
  double tol = 0.0;    // rig units, the position goals'; 0 = 1e-4 of the reach
  double tol_angle = kDefaultTolAngle;  // rad, the orientation targets' and aims' (positive)
  int max_iterations = 1000;            // classic solvers and the equilibrium solve (physik)
  double lambda = 0.0;                  // rig units, DLS damping; 0 = 0.02 of the reach
  std::string jacobian = "analytic";    // analytic | fd
  std::vector<double> gravity;          // rig units/s^2, empty or three components (mass-spring)
  double rotation_damping = 0.8;        // rotation method, in [0, 1]
  std::string socket = "twist-bend";    // twist-bend | virtual-bone
  std::string cone = "elliptical";      // none | circular | elliptical
  bool no_limits = false;               // classic solvers ignore the rig's limits
  // the engine's solvers (physik, physik-steps, physik-explicit)
  double armature = kArmature;        // 1, physik: the joints' armature (SolveRule::armature)
  double dt_growth = kSolveDtGrowth;  // 1, physik-steps: the step's growth per settling step
  double max_dt = kSolveMaxDt;        // s, physik-steps: the longest step
  std::string finish = "none";        // none | ccd | dls: the classic finish after a stall
};

enum class SolveOptionKind { kReal, kInteger, kBoolean, kChoice, kVec3 };

// A value of any kind: a number (real, integer, boolean 0/1), a name (choice) or three numbers.
struct SolveOptionValue {
  double number = 0.0;
  std::string text;
  std::vector<double> vec;
};

struct SolveOptionRow {
  std::string name;  // scene "solve" key, Python keyword, --flag with dashes
  SolveOptionKind kind = SolveOptionKind::kReal;
  std::string unit;                  // "1" for ratios, "" for names and flags
  std::vector<std::string> choices;  // kChoice
  std::string doc;
  // "" when `v` is valid, else why not
  std::string (*check)(const SolveOptionValue& v) = nullptr;
  SolveOptionValue (*get)(const SceneSolveOptions&) = nullptr;
  void (*set)(SceneSolveOptions&, const SolveOptionValue&) = nullptr;
};

// Every option, in the order `physik solve --help` lists them.
const std::vector<SolveOptionRow>& solve_option_table();
const SolveOptionRow* find_solve_option(const std::string& name);  // nullptr if none

// How the caller spells an option in a message: the CLI's --flag, or the name (Python, a scene).
enum class OptionSpelling { kFlag, kName };
std::string option_label(const std::string& name, OptionSpelling spelling);  // "--max-iterations"

// The option's value from its text ("1e-4", "true", "dls", "0 0 -9.8"), checked; InputError
// "<label>: <reason>" (the label as `spelling` says).
SolveOptionValue parse_solve_option(const SolveOptionRow& row, const std::string& text,
                                    OptionSpelling spelling);
// Set a checked value; InputError as above when it is not valid.
void set_solve_option(SceneSolveOptions& o, const SolveOptionRow& row, const SolveOptionValue& v,
                      OptionSpelling spelling);
// The default's text, for --help and docs ("" for none).
std::string solve_option_default_text(const SolveOptionRow& row);

// Every option's check, then that a solver is named; InputError naming the first bad option.
void check_solve_options(const SceneSolveOptions& options,
                         OptionSpelling spelling = OptionSpelling::kFlag);

extern const char* const kSceneSolvers;  // "fabrik|...|rotation|kdl|...|physik-explicit"

}  // namespace physik
