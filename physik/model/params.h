// Engine parameters, with the paper's and the original code's presets, and the one parameter
// table that describes them.
//
// Names are the scene file's "params" keys. Presets (docs/engine.md "The model", paper Sec. 4,
// original fwik.py):
//   original: dt 0.05 s, damping 3 N s/m, angular velocity x0.5 per step, eps 1e-3, pass cap
//             5 n^2, control k 10 N/m, torsion k 10 N m/rad engaging 10% inside each limit,
//             linear torsion, articulated integration, linear target interpolation
//   paper:    as original but damping 20 N s/m and control k 30 N/m (paper Sec. 4 / Fig 5)
//   robust:   as original but the implicit step (linearised backward Euler over the exact
//             articulated solve), damping chosen by the linearised modes (damping_auto) and the
//             gradient torsion torque (on the outside_rigs experiment's rigs and the paper's
//             scenes it converges as often as the paper's axes torque, in as few or fewer
//             steps); the default of a scene that names no preset
//
// The table (param_table(), its rows in params.cpp) holds, per parameter: the key, the field it
// drives, its kind, unit, default per preset, valid range, tuning bounds and a doc line. The
// scene reader and writer (physik/io/scene_io), `--set`, the tuner, the report's settings table
// and `physik params` all loop over it: adding a parameter is a field here, one row, and its use.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "physik/model/types.h"

namespace physik {

enum class SpringLaw { kLinear, kCapped };
// The scheme of a step: one switch, read once per step (engine.h step()).
enum class Scheme {
  kGaussSeidel,  // the paper's: Newton-Euler per bone, Gauss-Seidel joint passes (corrected eq.
                 // 11, joint_forces.h), semi-implicit Euler (integrate.h); articulated, or free
                 // rods
  kExact,        // Featherstone's articulated-body algorithm (articulated_body.h) with MuJoCo's
                 // Euler step in joint space (integrate_joint_space.h)
  kImplicit,     // linearised backward Euler over the same recursion (implicit_step.h), a step that
                 // adds energy taken again in halves (implicit_advance.h)
};
enum class Interpolation { kNone, kLinear, kPolarHead, kPolarCom };
// the torsion spring's torque (torsion_springs.h): the paper's k x excess about each rest axis, or
// the exact gradient of the same potential (conservative at every angle)
enum class TorsionTorque { kAxes, kGradient };
// what the implicit step linearises (implicit_step.h): the Gauss-Newton stiffness of its elements,
// or the full pose derivative of the rest dynamics (the forces' and the inertia's pose terms,
// implicit_pose_terms.h)
enum class ImplicitLinearisation { kGaussNewton, kFull };

// each enum's names in the scene format, in the enum's order (the table's choices)
const std::vector<std::string>& choice_names(SpringLaw);
const std::vector<std::string>& choice_names(Scheme);
const std::vector<std::string>& choice_names(Interpolation);
const std::vector<std::string>& choice_names(TorsionTorque);
const std::vector<std::string>& choice_names(ImplicitLinearisation);

const char* to_string(SpringLaw s);
const char* to_string(Scheme s);
const char* to_string(Interpolation s);
const char* to_string(TorsionTorque s);
const char* to_string(ImplicitLinearisation s);

struct EngineParams {
  EngineParams();                  // the default preset (kDefaultPreset)
  std::string preset;              // the preset the values started from
  double dt;                       // s, time step
  double damping;                  // N s/m, force -c v at each bone end
  bool damping_auto;               // choose damping for critical damping of the slowest
                                   // linearised mode (linear_modes.h) at the start pose
                                   // and whenever the targets change
  double angular_velocity_factor;  // 1, every bone's angular velocity is scaled by it each step
  bool flush_subnormals;           // each step computes with numbers below 2.2e-308 as 0 (the
                                   // processor's flush modes, physik/engine/subnormals.h)
  double joint_eps;                // rig units/s^2, stop the joint passes below this mismatch
  double joint_eps_relative;       // 1; > 0: the passes also go on until every joint's
                                   //    mismatch is below this fraction of its accelerations
                                   //    (joint_forces.h); 0 = off (the paper's absolute eps)
  int max_passes;                  // passes per step; 0 = 5 n^2 (the original's cap)
  bool centripetal;                // add w x (w x r) to joint-point accelerations (eq. 2 omits it)
  bool gyroscopic;                 // the -w x I w term of eq. 1
  bool factor_in_joint_solve;      // gauss-seidel: the factor f as the torque I (f - 1) w / dt on
                                   // each bone before the joint passes (as the exact scheme and
                                   // MuJoCo's reference apply it); false: w <- f w after them
                                   // (the paper's and the original's)
  double control_k;                // N/m, stiffness of control points that give none
  SpringLaw control_spring;        // law of control points that give none
  double control_cap;              // rig units, cap c of capped springs (original: 1)
  double torsion_k;                // N m/rad, joint-limit torsion springs
  SpringLaw torsion_spring;
  double torsion_cap;            // rad, cap of capped torsion springs
  double torsion_tolerance;      // 1, fraction of the range inside each limit where the
                                 //    torsion spring engages
  TorsionTorque torsion_torque;  // axes (the paper's) or gradient (torsion_springs.h)
  Scheme scheme;                 // gauss-seidel | exact | implicit
  bool free_rods;                // gauss-seidel: every bone integrates its own motion (the
                                 // paper's text); false: FK from the root (the original's)
  int implicit_max_splits;       // scheme implicit: a step that adds energy is taken
                                 // again in halves, at most this deep (implicit_advance.h);
                                 // 0 = the bare linearised step
  ImplicitLinearisation implicit_linearisation;  // scheme implicit: gauss-newton or full
                                                 // (implicit_step.h)
  Interpolation interpolation;
  int interpolation_steps;        // steps over which a target jump is spread
                                  // (original: 25% of its 50 iterations)
  double interpolation_fallback;  // rig units: polar falls back to linear this near the origin
  // contacts (physik/engine/ground_contacts.h, self_contacts.h), read only by scenes with a ground
  // or self_collision: a penalty spring and damper along the normal, regularised Coulomb friction
  double contact_k;           // N/m, normal stiffness of each contact
  double contact_damping;     // N s/m, normal damping of each contact
  double friction;            // 1, Coulomb coefficient mu
  double friction_speed;      // rig units/s, slip speed below which friction is viscous
                              //    (mu F_n / friction_speed per unit slip speed)
  double friction_stiffness;  // N/m, the static friction's tangential anchor spring k_t (0:
                              //    none, the regularised law alone)

  int passes_cap(int nbone) const { return max_passes > 0 ? max_passes : 5 * nbone * nbone; }
  // the state is the joint-space one of the articulated-body recursion (exact and implicit)
  bool joint_space() const { return scheme != Scheme::kGaussSeidel; }
  // the scheme's joint model: locked axes removed (exact, implicit) or held by torsion springs
  LockedAxes locked_axes() const {
    return joint_space() ? LockedAxes::kRemoved : LockedAxes::kSprings;
  }
};

// --- the parameter table ---------------------------------------------------------------------

// The presets, in the order of each row's defaults.
constexpr int kPresetCount = 3;
constexpr std::array<const char*, kPresetCount> kPresetNames = {"original", "paper", "robust"};

// The preset of a scene that names none, and of EngineParams(): the one that converges on rigs
// from outside the project (the outside_rigs experiment). The paper's scenes name theirs.
constexpr const char* kDefaultPreset = "robust";

enum class ParamKind { kReal, kInteger, kBoolean, kChoice };
const char* to_string(ParamKind k);

// A parameter's value in one type for every kind: reals and integers as they are, booleans 0/1,
// choices the index into the row's `choices`.
using ParamValue = double;

// Valid values: an optional lower and upper bound, each allowed or not (0 < dt; 0 <= damping;
// 0 <= angular_velocity_factor <= 1; 0 <= torsion_tolerance < 0.5).
struct ParamRange {
  std::optional<double> lo, hi;
  bool lo_allowed = true;  // is lo itself valid
  bool hi_allowed = true;  // is hi itself valid
};

// What a parameter row's conflict rule sees of the scene that runs the parameters (the Scene
// itself is above this file: physik/model/scene.h param_scene). The default is a scene that has
// every element, so a rule judged without a scene refuses nothing on its account.
struct ParamScene {
  bool contacts = true;  // a ground, obstacles or self_collision (physik/model/contact_model.h)
};

struct ParamRow {
  std::string name;  // the scene's "params" key, the --set key, the EngineParams field
  ParamKind kind = ParamKind::kReal;
  std::string unit;                                 // "1" for ratios, "" for booleans and choices
  std::array<ParamValue, kPresetCount> defaults{};  // per preset, in kPresetNames order
  ParamRange valid;
  std::string zero_means;  // what 0 stands for, when it is special ("5 n^2" for max_passes)
  std::optional<std::pair<double, double>> tune;  // tuning bounds lo < hi, both > 0 (reals)
  std::vector<std::string> choices;               // kChoice: the names, in the enum's order
  std::string doc;                                // one line
  bool written_at_default =
      true;  // false: the scene writer leaves it out while it has its
             // preset's default (a newer row keeps older summaries as they were)
  ParamValue (*get)(const EngineParams&) = nullptr;
  void (*set)(EngineParams&, ParamValue) = nullptr;
  // Why a value given explicitly for this row (by a scene file or an override) would not be the
  // value the run uses, with the other parameters as `p` and the scene as `scene` ("" when it
  // would be): a setting another one overrides, one the run's scheme never reads, or one the
  // scene has nothing for (a contact row without contacts). The scene reader refuses such a
  // value (param_conflicts); nullptr = the row always takes part.
  std::string (*conflict)(const EngineParams& p, const ParamScene& scene) = nullptr;
  // the rule's reason ("" without a rule); `scene` left out: a scene that has every element
  std::string conflict_reason(const EngineParams& p, const ParamScene& scene = {}) const {
    return conflict ? conflict(p, scene) : "";
  }
};

// Every parameter, in the order scene files document and check them.
const std::vector<ParamRow>& param_table();
const ParamRow* find_param(const std::string& name);  // nullptr if there is none
const ParamRow& param_row(const std::string& name);   // std::logic_error if there is none
// "preset, dt, damping, ...": every key a scene's "params" or --set accepts
std::vector<std::string> param_keys();
// "unknown parameter 'dampng' (did you mean 'damping'?)", or the known keys when none is close
std::string unknown_param_reason(const std::string& key);
// the index of a preset in kPresetNames, or -1
int preset_index(const std::string& name);

// A preset by name ("paper" or "original"); throws InputError naming `source` otherwise.
EngineParams preset_params(const std::string& name, const std::string& source = "");

// "" when `v` is valid for the row, else the reason ("must be positive", "must lie in [0, 1]").
std::string range_violation(const ParamRow& row, ParamValue v);
// The valid values as text: "> 0", ">= 0", "[0, 1]", "[0, 0.5)", "true|false", "linear|capped".
std::string valid_text(const ParamRow& row);
// The value as text: 0.05, 12, true, capped (parse_param_text reads it back).
std::string format_param(const ParamRow& row, ParamValue v);
// Text by the row's kind (a number, an integer, true/false, one of the choices), range-checked;
// throws InputError "<source>: params: field '<name>': <reason>".
ParamValue parse_param_text(const ParamRow& row, const std::string& text,
                            const std::string& source);

// The rows among `given` (explicitly given names) whose value the run would not use with
// params `p`, each as (row name, reason); empty when every given value takes part. A row at its
// preset's value is never among them: it changes nothing either way.
std::vector<std::pair<std::string, std::string>> param_conflicts(
    const EngineParams& p, const std::vector<std::string>& given, const ParamScene& scene = {});

// The two keys `scheme` replaced, still read in scene files and overrides: integration
// (articulated|free-rods|implicit) and joint_solve (gauss-seidel|exact). Sets p.scheme and
// p.free_rods as the pair meant (implicit implied the exact solve; "" = not given, the other
// then decides with p's scheme); InputError "<source>: <element>: field '<key>': ..." for an
// unknown value or a pair that cannot run together.
void apply_old_scheme_keys(EngineParams& p, const std::string& integration,
                           const std::string& joint_solve, const std::string& source,
                           const std::string& element);

// `--set key=value` overrides: applied after a scene's own params (so they win), and a preset
// override swaps the base preset under them. Control points that give no k, spring or cap take
// the params' at use, so they follow the overrides too.
struct ParamOverrides {
  std::string source = "--set";                                // where they came from, for messages
  std::string preset;                                          // "" = the scene's own
  std::vector<std::pair<const ParamRow*, ParamValue>> values;  // in the order given; later wins
  std::string integration, joint_solve;  // the old scheme keys (apply_old_scheme_keys), "" = none
  bool empty() const {
    return preset.empty() && values.empty() && integration.empty() && joint_solve.empty();
  }
  bool has(const std::string& name) const;
  void apply(EngineParams& p) const;
};
// "key=value" strings into overrides; an unknown key or a bad value is an InputError naming
// `source` (e.g. "--set") and the key.
ParamOverrides parse_param_overrides(const std::vector<std::string>& assignments,
                                     const std::string& source);

}  // namespace physik
