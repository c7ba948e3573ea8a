#include "physik/model/params.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <type_traits>

#include "physik/model/errors.h"

namespace physik {

const std::vector<std::string>& choice_names(SpringLaw) {
  static const std::vector<std::string> names = {"linear", "capped"};
  return names;
}

const std::vector<std::string>& choice_names(Scheme) {
  static const std::vector<std::string> names = {"gauss-seidel", "exact", "implicit"};
  return names;
}

const std::vector<std::string>& choice_names(TorsionTorque) {
  static const std::vector<std::string> names = {"axes", "gradient"};
  return names;
}

const std::vector<std::string>& choice_names(ImplicitLinearisation) {
  static const std::vector<std::string> names = {"gauss-newton", "full"};
  return names;
}

const std::vector<std::string>& choice_names(Interpolation) {
  static const std::vector<std::string> names = {"none", "linear", "polar-head", "polar-com"};
  return names;
}

const char* to_string(SpringLaw s) {
  return choice_names(s)[static_cast<int>(s)].c_str();
}
const char* to_string(Scheme s) {
  return choice_names(s)[static_cast<int>(s)].c_str();
}
const char* to_string(Interpolation s) {
  return choice_names(s)[static_cast<int>(s)].c_str();
}
const char* to_string(TorsionTorque s) {
  return choice_names(s)[static_cast<int>(s)].c_str();
}
const char* to_string(ImplicitLinearisation s) {
  return choice_names(s)[static_cast<int>(s)].c_str();
}

const char* to_string(ParamKind k) {
  switch (k) {
    case ParamKind::kReal:
      return "real";
    case ParamKind::kInteger:
      return "integer";
    case ParamKind::kBoolean:
      return "boolean";
    case ParamKind::kChoice:
      return "choice";
  }
  return "?";
}

namespace {

// --- building a row from a field ---------------------------------------------------------------

template <auto Field>
using FieldType = std::remove_reference_t<decltype(std::declval<EngineParams&>().*Field)>;

template <class T>
ParamValue to_value(T v) {
  if constexpr (std::is_enum_v<T>)
    return static_cast<ParamValue>(static_cast<int>(v));
  else
    return static_cast<ParamValue>(v);
}

template <auto Field>
ParamValue get_field(const EngineParams& p) {
  return to_value(p.*Field);
}

template <auto Field>
void set_field(EngineParams& p, ParamValue v) {
  using T = FieldType<Field>;
  if constexpr (std::is_enum_v<T>)
    p.*Field = static_cast<T>(static_cast<int>(v));
  else if constexpr (std::is_same_v<T, bool>)
    p.*Field = v != 0.0;
  else
    p.*Field = static_cast<T>(v);
}

// A field's value in each preset, in kPresetNames order; the constructor takes one per preset,
// so a row that forgets one does not compile.
template <class T>
struct PerPreset {
  PerPreset(T original, T paper, T robust) : v{original, paper, robust} {}
  std::array<T, kPresetCount> v;
};

// A row for `Field`: its kind follows the field's type (double, int, bool, an enum with
// choice_names).
template <auto Field>
ParamRow row(const char* name, const char* unit, PerPreset<FieldType<Field>> defaults,
             ParamRange valid, const char* doc) {
  using T = FieldType<Field>;
  ParamRow r;
  r.name = name;
  r.unit = unit;
  r.valid = valid;
  r.doc = doc;
  r.get = &get_field<Field>;
  r.set = &set_field<Field>;
  if constexpr (std::is_enum_v<T>) {
    r.kind = ParamKind::kChoice;
    r.choices = choice_names(T{});
  } else if constexpr (std::is_same_v<T, bool>) {
    r.kind = ParamKind::kBoolean;
  } else if constexpr (std::is_same_v<T, int>) {
    r.kind = ParamKind::kInteger;
  } else {
    static_assert(std::is_same_v<T, double>, "a parameter is a double, int, bool or enum");
    r.kind = ParamKind::kReal;
  }
  for (int i = 0; i < kPresetCount; ++i) r.defaults[i] = to_value(defaults.v[i]);
  return r;
}

ParamRow tuned(ParamRow r, double lo, double hi) {
  r.tune = std::make_pair(lo, hi);
  return r;
}

ParamRow zero_means(ParamRow r, const char* text) {
  r.zero_means = text;
  return r;
}

ParamRow omitted_at_default(ParamRow r) {
  r.written_at_default = false;
  return r;
}

ParamRow conflicts(ParamRow r, std::string (*why)(const EngineParams&, const ParamScene&)) {
  r.conflict = why;
  return r;
}

constexpr ParamRange kAny{};
const ParamRange kPositive{0.0, std::nullopt, false, true};
const ParamRange kNonNegative{0.0, std::nullopt, true, true};
ParamRange closed(double lo, double hi) {
  return {lo, hi, true, true};
}  // [lo, hi]
ParamRange half_open(double lo, double hi) {
  return {lo, hi, true, false};
}  // [lo, hi)

using E = EngineParams;
using S = SpringLaw;
using T = TorsionTorque;

// --- settings the run would not use (ParamRow::conflict) ---------------------------------------

std::string gauss_seidel_only(const EngineParams& p, const ParamScene&) {
  if (p.scheme == Scheme::kGaussSeidel) return "";
  return std::string("applies to the gauss-seidel scheme only (this run: scheme ") +
         to_string(p.scheme) + ")";
}

std::string implicit_only(const EngineParams& p, const ParamScene&) {
  if (p.scheme == Scheme::kImplicit) return "";
  return std::string("applies to the implicit scheme only (this run: scheme ") +
         to_string(p.scheme) + ")";
}

std::string damping_conflict(const EngineParams& p, const ParamScene&) {
  return p.damping_auto ? "a damping value beside damping auto: give one or the other" : "";
}

std::string interpolation_steps_conflict(const EngineParams& p, const ParamScene&) {
  return p.interpolation == Interpolation::kNone
             ? "applies only with an interpolation (this run: none)"
             : "";
}

std::string polar_only(const EngineParams& p, const ParamScene&) {
  if (p.interpolation == Interpolation::kPolarHead || p.interpolation == Interpolation::kPolarCom) {
    return "";
  }
  return std::string("applies to polar interpolation only (this run: ") +
         to_string(p.interpolation) + ")";
}

std::string capped_torsion_only(const EngineParams& p, const ParamScene&) {
  return p.torsion_spring == S::kCapped
             ? ""
             : "applies to capped torsion springs only (this run: linear)";
}

// damping: a value given for it is the value used, so it turns damping_auto off
void set_damping(EngineParams& p, ParamValue v) {
  p.damping = v;
  p.damping_auto = false;
}

// The table, in groups. Columns: key and field, unit, {original, paper, robust}, valid range,
// doc; then tuning bounds (the tuner's defaults for --params), what 0 means where it is special,
// and why an explicit value would not be used.

// the step: its length and its damping
std::vector<ParamRow> step_rows() {
  ParamRow damping =
      tuned(conflicts(row<&E::damping>("damping", "N s/m", {3.0, 20.0, 3.0}, kNonNegative,
                                       "force -c v at the head and the tail of every bone (a value "
                                       "turns damping_auto off)"),
                      damping_conflict),
            0.01, 100.0);
  damping.set = &set_damping;
  return {
      row<&E::dt>("dt", "s", {0.05, 0.05, 0.05}, kPositive, "time step"),
      damping,
      omitted_at_default(row<&E::damping_auto>(
          "damping_auto", "", {false, false, true}, kAny,
          "damping chosen for critical damping of the slowest linearised mode at the start pose, "
          "again when the targets change (`damping` unused); \"damping\": \"auto\" in a scene")),
      tuned(row<&E::angular_velocity_factor>("angular_velocity_factor", "1", {0.5, 0.5, 0.5},
                                             closed(0.0, 1.0), "w <- f w + alpha dt every step"),
            0.01, 1.0),
      omitted_at_default(row<&E::flush_subnormals>(
          "flush_subnormals", "", {true, true, true}, kAny,
          "each step computes with numbers below 2.2e-308 (subnormals) as 0, the processor's "
          "flush-to-zero modes, set for the step and restored after: no slow arithmetic where a "
          "long chain's motion decays to nothing; false: IEEE gradual underflow")),
  };
}

// the paper's joint solve (gauss-seidel) and Newton-Euler's terms
std::vector<ParamRow> joint_solve_rows() {
  return {
      conflicts(row<&E::joint_eps>("joint_eps", "rig units/s^2", {1e-3, 1e-3, 1e-3}, kPositive,
                                   "joint passes stop below this acceleration mismatch"),
                gauss_seidel_only),
      conflicts(zero_means(row<&E::joint_eps_relative>(
                               "joint_eps_relative", "1", {0.0, 0.0, 0.0}, half_open(0.0, 1.0),
                               "> 0: passes also go on until every joint's mismatch is below this "
                               "fraction of its own accelerations (forces cross long chains)"),
                           "off, the paper's absolute eps"),
                gauss_seidel_only),
      conflicts(zero_means(row<&E::max_passes>("max_passes", "passes", {0, 0, 0}, kNonNegative,
                                               "joint passes per step at most; 0 = 5 n^2 (the "
                                               "original's cap)"),
                           "5 n^2"),
                gauss_seidel_only),
      conflicts(
          row<&E::centripetal>("centripetal", "", {false, false, false}, kAny,
                               "add w x (w x r) to joint-point accelerations (eq. 2 omits it)"),
          gauss_seidel_only),
      row<&E::gyroscopic>("gyroscopic", "", {true, true, true}, kAny, "the -w x I w term of eq. 1"),
  };
}

// the control and torsion springs
std::vector<ParamRow> spring_rows() {
  return {
      tuned(row<&E::control_k>("control_k", "N/m", {10.0, 30.0, 10.0}, kNonNegative,
                               "stiffness of the control points that give no k"),
            0.1, 1000.0),
      row<&E::control_spring>("control_spring", "", {S::kLinear, S::kLinear, S::kLinear}, kAny,
                              "spring law of the control points that give none"),
      tuned(
          row<&E::control_cap>("control_cap", "rig units", {1.0, 1.0, 1.0}, kPositive,
                               "cap c of capped control springs that give none (the original: 1)"),
          0.01, 100.0),
      tuned(row<&E::torsion_k>("torsion_k", "N m/rad", {10.0, 10.0, 10.0}, kNonNegative,
                               "stiffness of the joint-limit torsion springs"),
            0.1, 1000.0),
      row<&E::torsion_spring>("torsion_spring", "", {S::kLinear, S::kLinear, S::kLinear}, kAny,
                              "spring law of the joint-limit torsion springs"),
      tuned(conflicts(row<&E::torsion_cap>("torsion_cap", "rad", {0.5, 0.5, 0.5}, kPositive,
                                           "cap of capped torsion springs"),
                      capped_torsion_only),
            0.01, 3.2),
      row<&E::torsion_tolerance>(
          "torsion_tolerance", "1", {0.1, 0.1, 0.1}, half_open(0.0, 0.5),
          "the torsion spring engages this fraction of the range inside each "
          "limit"),
      omitted_at_default(row<&E::torsion_torque>(
          "torsion_torque", "", {T::kAxes, T::kAxes, T::kGradient}, kAny,
          "axes (the paper's: k x excess about each rest axis; not the gradient of the torsion "
          "potential at large bends) or gradient (its exact gradient: conservative)")),
  };
}

// which scheme, and its options
std::vector<ParamRow> scheme_rows() {
  return {
      row<&E::scheme>(
          "scheme", "", {Scheme::kGaussSeidel, Scheme::kGaussSeidel, Scheme::kImplicit}, kAny,
          "gauss-seidel (the paper's: joint passes, semi-implicit Euler), exact "
          "(articulated-body algorithm, MuJoCo's Euler) or implicit (linearised backward "
          "Euler over the exact solve, stable at any dt and damping). The keys it replaced "
          "are still read, as they were meant: integration (articulated, free-rods, implicit) "
          "and joint_solve (gauss-seidel, exact), joint_solve alone with integration "
          "articulated (joint_solve exact is scheme exact)"),
      conflicts(omitted_at_default(row<&E::free_rods>(
                    "free_rods", "", {false, false, false}, kAny,
                    "gauss-seidel: every bone integrates its own motion, joints may drift apart "
                    "(the paper's text); false: positions by FK from the root (the original's)")),
                gauss_seidel_only),
      conflicts(zero_means(omitted_at_default(row<&E::implicit_max_splits>(
                               "implicit_max_splits", "halvings", {8, 8, 8}, closed(0.0, 20.0),
                               "scheme implicit: a step that adds energy is taken again as "
                               "two half steps, at most this many halvings deep (the smallest "
                               "substep dt / 2^N)")),
                           "the bare linearised step, never split"),
                implicit_only),
      conflicts(omitted_at_default(row<&E::implicit_linearisation>(
                    "implicit_linearisation", "",
                    {ImplicitLinearisation::kGaussNewton, ImplicitLinearisation::kGaussNewton,
                     ImplicitLinearisation::kGaussNewton},
                    kAny,
                    "scheme implicit: gauss-newton (the elements' own stiffness) or full (also "
                    "how the forces and the inertia turn with the pose)")),
                implicit_only),
  };
}

// how target jumps are spread (eq. 12)
std::vector<ParamRow> interpolation_rows() {
  return {
      row<&E::interpolation>(
          "interpolation", "",
          {Interpolation::kLinear, Interpolation::kLinear, Interpolation::kLinear}, kAny,
          "how a target jump is spread over steps (eq. 12)"),
      conflicts(
          row<&E::interpolation_steps>("interpolation_steps", "steps", {12, 12, 12}, kNonNegative,
                                       "a target jump is spread over this many "
                                       "steps (the original: 25% of 50)"),
          interpolation_steps_conflict),
      conflicts(row<&E::interpolation_fallback>("interpolation_fallback", "rig units",
                                                {1e-3, 1e-3, 1e-3}, kPositive,
                                                "polar interpolation falls back to linear this "
                                                "close to its origin"),
                polar_only),
  };
}

// contacts: the ground's and the rig's own (not tuned; read only when the scene has them:
// scene_io.cpp refuses a value given for a scene without; written only when not at their
// default, so older scenes' summaries stay as they were). The defaults, the same in every preset: k
// such that a 1 kg bone under 9.81 sinks by about 1e-3 rig units; c the critical damping of a
// quarter of that mass on k (a bone's end point: 1/m_eff = 1/m + (L/2)^2 / (m L^2 / 12) = 4/m); mu
// 1 as MuJoCo's; below 0.01 rig units/s of slip the friction is viscous; no static friction
// (friction_stiffness 0: MuJoCo's soft friction creeps as the regularised law does, and the
// contacts experiment's drops agree with it so; k_t = k holds a tangential load T at T / k_t, as
// a normal load sinks by W / k). The explicit schemes are stable only for dt < 2 sqrt(m_eff / k)
// (0.01 s for these) and, for the friction's viscous slope c = mu F_n / friction_speed at rest,
// dt < 2 m_eff / c (0.001 s for a 1 kg bone lying on the floor); the implicit one at any dt.
std::string contacts_only(const EngineParams&, const ParamScene& scene) {
  return scene.contacts
             ? ""
             : "applies only to a scene with a ground, obstacles or \"self_collision\": true";
}

std::vector<ParamRow> contact_rows() {
  return {
      conflicts(
          omitted_at_default(row<&E::contact_k>(
              "contact_k", "N/m", {1e4, 1e4, 1e4}, kNonNegative,
              "contacts: stiffness k of each contact's penalty spring, force k d at depth d (at "
              "rest a load W sinks by W / k)")),
          contacts_only),
      conflicts(
          omitted_at_default(row<&E::contact_damping>(
              "contact_damping", "N s/m", {100.0, 100.0, 100.0}, kNonNegative,
              "contacts: normal damping c, force -c v_n while touching (the normal force never "
              "pulls)")),
          contacts_only),
      conflicts(
          omitted_at_default(row<&E::friction>("friction", "1", {1.0, 1.0, 1.0}, kNonNegative,
                                               "contacts: Coulomb coefficient mu, tangential force "
                                               "at most mu times the normal force")),
          contacts_only),
      conflicts(omitted_at_default(row<&E::friction_speed>(
                    "friction_speed", "rig units/s", {0.01, 0.01, 0.01}, kPositive,
                    "contacts: friction is viscous below this slip speed (mu F_n v / speed), full "
                    "Coulomb above")),
                contacts_only),
      conflicts(
          omitted_at_default(row<&E::friction_stiffness>(
              "friction_stiffness", "N/m", {0.0, 0.0, 0.0}, kNonNegative,
              "contacts: static friction, a tangential spring k_t from where the contact stuck, "
              "slipping beyond mu F_n (0: none, the viscous law alone)")),
          contacts_only),
  };
}

std::vector<ParamRow> build_table() {
  std::vector<ParamRow> table;
  for (auto group :
       {step_rows, joint_solve_rows, spring_rows, scheme_rows, interpolation_rows, contact_rows}) {
    for (ParamRow& r : group()) table.push_back(std::move(r));
  }
  return table;
}

std::string number_text(double v) {
  std::ostringstream o;
  o << v;  // %g: 0.05, 1e-05, 20
  return o.str();
}

[[noreturn]] void bad_value(const ParamRow& row, const std::string& source,
                            const std::string& reason) {
  throw_input_error(source, "params", row.name, reason);
}

// the whole text as a number of type T (no spaces, no sign prefix, no trailing characters):
// std::errc() when it is one, result_out_of_range when it does not fit, invalid_argument else
template <class T>
std::errc parse_whole(const std::string& text, T& out) {
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, out);
  if (ptr != end || text.empty()) return std::errc::invalid_argument;
  return ec;
}

// Levenshtein distance between two short names
std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> prev(b.size() + 1), cur(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) prev[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (a[i - 1] != b[j - 1])});
    }
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

}  // namespace

std::string unknown_param_reason(const std::string& key) {
  std::string best;
  std::size_t best_d = std::string::npos;
  for (const std::string& k : param_keys()) {
    const std::size_t d = edit_distance(key, k);
    if (d < best_d) best_d = d, best = k;
  }
  // close: a typo (a third of the name's letters at most, two at least)
  if (best_d <= std::max<std::size_t>(2, best.size() / 3)) {
    return "unknown parameter '" + key + "' (did you mean '" + best + "'?)";
  }
  std::string all;
  for (const std::string& k : param_keys()) all += (all.empty() ? "" : ", ") + k;
  return "unknown parameter '" + key + "' (known: " + all + ")";
}

EngineParams::EngineParams() {
  // every row's setter, in table order (damping's clears damping_auto, whose row comes after)
  const int i = preset_index(kDefaultPreset);
  for (const ParamRow& r : param_table()) r.set(*this, r.defaults[i]);
  preset = kDefaultPreset;
}

const std::vector<ParamRow>& param_table() {
  static const std::vector<ParamRow> table = build_table();
  return table;
}

const ParamRow* find_param(const std::string& name) {
  for (const ParamRow& r : param_table()) {
    if (r.name == name) return &r;
  }
  return nullptr;
}

const ParamRow& param_row(const std::string& name) {
  const ParamRow* r = find_param(name);
  if (!r) throw std::logic_error("no parameter '" + name + "' in the table");
  return *r;
}

std::vector<std::string> param_keys() {
  std::vector<std::string> keys = {"preset"};
  for (const ParamRow& r : param_table()) keys.push_back(r.name);
  return keys;
}

int preset_index(const std::string& name) {
  for (int i = 0; i < kPresetCount; ++i) {
    if (name == kPresetNames[i]) return i;
  }
  return -1;
}

EngineParams preset_params(const std::string& name, const std::string& source) {
  const int i = preset_index(name);
  if (i < 0) {
    std::string all;
    for (const char* n : kPresetNames) all += (all.empty() ? "" : "|") + std::string(n);
    throw_input_error(source, "params", "preset", "unknown preset '" + name + "' (" + all + ")");
  }
  EngineParams p;
  for (const ParamRow& r : param_table()) r.set(p, r.defaults[i]);
  p.preset = name;
  return p;
}

std::string range_violation(const ParamRow& row, ParamValue v) {
  if (!std::isfinite(v)) return "not a finite number";
  const ParamRange& g = row.valid;
  if (g.lo && (v < *g.lo || (v == *g.lo && !g.lo_allowed))) {
    std::string why =
        *g.lo == 0.0 ? (g.lo_allowed ? "must not be negative" : "must be positive")
                     : (g.lo_allowed ? "must be at least " : "must be above ") + number_text(*g.lo);
    if (!row.zero_means.empty() && *g.lo == 0.0) why += " (0 = " + row.zero_means + ")";
    return why;
  }
  if (g.hi && (v > *g.hi || (v == *g.hi && !g.hi_allowed))) {
    if (!g.lo) return (g.hi_allowed ? "must be at most " : "must be below ") + number_text(*g.hi);
    return "must lie in " + std::string(g.lo_allowed ? "[" : "(") + number_text(*g.lo) + ", " +
           number_text(*g.hi) + (g.hi_allowed ? "]" : ")");
  }
  return "";
}

std::string valid_text(const ParamRow& row) {
  if (row.kind == ParamKind::kBoolean) return "true|false";
  if (row.kind == ParamKind::kChoice) {
    std::string all;
    for (const std::string& c : row.choices) all += (all.empty() ? "" : "|") + c;
    return all;
  }
  const ParamRange& g = row.valid;
  if (g.lo && g.hi) {
    return (g.lo_allowed ? "[" : "(") + number_text(*g.lo) + ", " + number_text(*g.hi) +
           (g.hi_allowed ? "]" : ")");
  }
  if (g.lo) return (g.lo_allowed ? ">= " : "> ") + number_text(*g.lo);
  if (g.hi) return (g.hi_allowed ? "<= " : "< ") + number_text(*g.hi);
  return "any";
}

std::string format_param(const ParamRow& row, ParamValue v) {
  switch (row.kind) {
    case ParamKind::kReal:
      return number_text(v);
    case ParamKind::kInteger:
      return std::to_string(static_cast<int>(v));
    case ParamKind::kBoolean:
      return v != 0.0 ? "true" : "false";
    case ParamKind::kChoice:
      return row.choices.at(static_cast<std::size_t>(v));
  }
  return "?";
}

ParamValue parse_param_text(const ParamRow& row, const std::string& text,
                            const std::string& source) {
  ParamValue v = 0.0;
  switch (row.kind) {
    case ParamKind::kReal: {
      const std::errc ec = parse_whole(text, v);
      if (ec == std::errc::result_out_of_range || (ec == std::errc() && !std::isfinite(v))) {
        bad_value(row, source, "not a finite number");
      }
      if (ec != std::errc()) bad_value(row, source, "expected a number, got '" + text + "'");
      break;
    }
    case ParamKind::kInteger: {
      long long i = 0;
      const std::errc ec = parse_whole(text, i);
      if (ec == std::errc::invalid_argument) {
        bad_value(row, source, "expected an integer, got '" + text + "'");
      }
      if (ec != std::errc() || i < std::numeric_limits<int>::min() ||
          i > std::numeric_limits<int>::max()) {
        bad_value(row, source, "integer out of range");
      }
      v = static_cast<ParamValue>(i);
      break;
    }
    case ParamKind::kBoolean: {
      if (text != "true" && text != "false") {
        bad_value(row, source, "expected true or false, got '" + text + "'");
      }
      v = text == "true" ? 1.0 : 0.0;
      break;
    }
    case ParamKind::kChoice: {
      std::string all;
      for (std::size_t i = 0; i < row.choices.size(); ++i) {
        if (text == row.choices[i]) return static_cast<ParamValue>(i);
        all += (all.empty() ? "" : "|") + row.choices[i];
      }
      bad_value(row, source, "unknown value '" + text + "' (expected " + all + ")");
    }
  }
  const std::string why = range_violation(row, v);
  if (!why.empty()) bad_value(row, source, why);
  return v;
}

std::vector<std::pair<std::string, std::string>> param_conflicts(
    const EngineParams& p, const std::vector<std::string>& given, const ParamScene& scene) {
  std::vector<std::pair<std::string, std::string>> out;
  const int preset = std::max(0, preset_index(p.preset));
  for (const ParamRow& row : param_table()) {
    if (!row.conflict || std::find(given.begin(), given.end(), row.name) == given.end()) continue;
    // the preset's own value, where the scene writer lists it, changes nothing whether it
    // takes part or not (a row the writer leaves out at that value is given on purpose)
    if (row.written_at_default && row.get(p) == row.defaults[preset]) continue;
    std::string why = row.conflict(p, scene);
    if (!why.empty()) out.emplace_back(row.name, std::move(why));
  }
  return out;
}

void apply_old_scheme_keys(EngineParams& p, const std::string& integration,
                           const std::string& joint_solve, const std::string& source,
                           const std::string& element) {
  const auto fail = [&](const char* key, const std::string& why) {
    throw_input_error(source, element, key, why);
  };
  if (!joint_solve.empty() && joint_solve != "gauss-seidel" && joint_solve != "exact") {
    fail("joint_solve", "unknown value '" + joint_solve + "' (expected gauss-seidel|exact)");
  }
  // joint_solve without integration keeps the meaning it had: integration articulated, its
  // default then (joint_solve exact is scheme exact, whatever the preset's scheme)
  if (integration == "implicit") {
    if (joint_solve == "gauss-seidel") {
      fail("joint_solve",
           "gauss-seidel cannot run with integration implicit, which solves the "
           "joints exactly");
    }
    p.scheme = Scheme::kImplicit;
    p.free_rods = false;
  } else if (integration == "free-rods") {
    if (joint_solve == "exact") fail("integration", "free-rods needs joint_solve gauss-seidel");
    p.scheme = Scheme::kGaussSeidel;
    p.free_rods = true;
  } else if (integration == "articulated" || integration.empty()) {
    if (!integration.empty()) p.free_rods = false;
    if (!joint_solve.empty()) {
      p.scheme = joint_solve == "exact" ? Scheme::kExact : Scheme::kGaussSeidel;
    } else if (p.scheme == Scheme::kImplicit) {
      p.scheme = Scheme::kGaussSeidel;  // integration articulated alone: the paper's scheme
    }
  } else {
    fail("integration",
         "unknown value '" + integration + "' (expected articulated|free-rods|implicit)");
  }
}

bool ParamOverrides::has(const std::string& name) const {
  if (name == "scheme" && (!integration.empty() || !joint_solve.empty())) return true;
  if (name == "free_rods" && integration == "free-rods") return true;
  for (const auto& [row, v] : values) {
    if (row->name == name) return true;
  }
  return false;
}

void ParamOverrides::apply(EngineParams& p) const {
  if (!integration.empty() || !joint_solve.empty()) {
    apply_old_scheme_keys(p, integration, joint_solve, source, "");
  }
  for (const auto& [row, v] : values) row->set(p, v);
}

ParamOverrides parse_param_overrides(const std::vector<std::string>& assignments,
                                     const std::string& source) {
  ParamOverrides out;
  out.source = source;
  for (const std::string& kv : assignments) {
    const auto eq = kv.find('=');
    if (eq == std::string::npos || eq == 0) throw_input_error(source, "", kv, "expected key=value");
    const std::string key = kv.substr(0, eq), value = kv.substr(eq + 1);
    if (key == "preset") {
      preset_params(value, source);  // an unknown preset fails here, naming `source`
      out.preset = value;
      continue;
    }
    if (key == "integration" || key == "joint_solve") {  // the keys scheme replaced
      (key == "integration" ? out.integration : out.joint_solve) = value;
      const bool known = key == "integration"
                             ? value == "articulated" || value == "free-rods" || value == "implicit"
                             : value == "gauss-seidel" || value == "exact";
      if (!known) {  // the message of apply_old_scheme_keys, here before the scene is read
        EngineParams check;
        apply_old_scheme_keys(check, out.integration, out.joint_solve, source, "");
      }
      continue;
    }
    if (key == "damping" && value == "auto") {  // sugar for damping_auto=true
      out.values.emplace_back(&param_row("damping_auto"), 1.0);
      continue;
    }
    const ParamRow* row = find_param(key);
    if (!row) throw InputError(source + ": " + unknown_param_reason(key));
    out.values.emplace_back(row, parse_param_text(*row, value, source));
  }
  return out;
}

}  // namespace physik
