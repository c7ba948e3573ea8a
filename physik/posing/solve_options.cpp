#include "physik/posing/solve_options.h"

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "physik/ik/ik_solver.h"
#include "physik/model/errors.h"

namespace physik {

const char* const kSceneSolvers =
    "fabrik|ccd|jt|dls|mass-spring|rotation|kdl|kdl-nr|physik|physik-steps|physik-explicit";

namespace {

using V = SolveOptionValue;
using O = SceneSolveOptions;

std::vector<std::string> split_choices(const std::string& all) {
  std::vector<std::string> out;
  std::istringstream in(all);
  for (std::string c; std::getline(in, c, '|');) out.push_back(c);
  return out;
}

// --- checks: "" when the value is valid --------------------------------------------------------

std::string finite_non_negative(const V& v) {
  return v.number >= 0.0 && std::isfinite(v.number) ? "" : "must be a finite number >= 0";
}
std::string at_least_one(const V& v) {
  return v.number >= 1.0 && std::isfinite(v.number) ? "" : "must be a finite number >= 1";
}
std::string positive(const V& v) {
  return v.number > 0.0 && std::isfinite(v.number) ? "" : "must be a positive finite number";
}
std::string unit_interval(const V& v) {
  return v.number >= 0.0 && v.number <= 1.0 ? "" : "must lie in [0, 1]";
}
std::string non_negative_integer(const V& v) {
  return v.number >= 0.0 ? "" : "must not be negative";
}
std::string three_finite(const V& v) {
  if (v.vec.size() != 3) return "expected three numbers";
  for (double x : v.vec) {
    if (!std::isfinite(x)) return "not a finite number";
  }
  return "";
}

// --- rows ----------------------------------------------------------------------------------------

template <auto Field>
SolveOptionRow number_row(const char* name, SolveOptionKind kind, const char* unit,
                          std::string (*check)(const V&), const char* doc) {
  SolveOptionRow r;
  r.name = name;
  r.kind = kind;
  r.unit = unit;
  r.check = check;
  r.doc = doc;
  r.get = [](const O& o) {
    V v;
    v.number = static_cast<double>(o.*Field);
    return v;
  };
  r.set = [](O& o, const V& v) {
    using T = std::remove_reference_t<decltype(o.*Field)>;
    o.*Field = static_cast<T>(v.number);
  };
  return r;
}

template <auto Field>
SolveOptionRow choice_row(const char* name, const char* choices, const char* doc) {
  SolveOptionRow r;
  r.name = name;
  r.kind = SolveOptionKind::kChoice;
  r.choices = split_choices(choices);
  r.doc = doc;
  r.get = [](const O& o) {
    V v;
    v.text = o.*Field;
    return v;
  };
  r.set = [](O& o, const V& v) { o.*Field = v.text; };
  return r;
}

SolveOptionRow gravity_row() {
  SolveOptionRow r;
  r.name = "gravity";
  r.kind = SolveOptionKind::kVec3;
  r.unit = "rig units/s^2";
  r.check = three_finite;
  r.doc = "mass-spring: gravity, three numbers";
  r.get = [](const O& o) {
    V v;
    v.vec = o.gravity;
    return v;
  };
  r.set = [](O& o, const V& v) { o.gravity = v.vec; };
  return r;
}

std::vector<SolveOptionRow> build_table() {
  using K = SolveOptionKind;
  return {
      choice_row<&O::solver>(
          "solver", kSceneSolvers,
          "the classic solvers, Orocos KDL (kdl: its Levenberg-Marquardt; kdl-nr: its "
          "joint-limited Newton-Raphson), or the engine: physik (the equilibrium solve: the "
          "rest pose by a trust region of implicit steps at rest), physik-steps (the "
          "time-stepping solve mode: the implicit step lengthening from the scene's dt) or "
          "physik-explicit (the scene's own engine at its dt)"),
      number_row<&O::tol>("tol", K::kReal, "rig units", finite_non_negative,
                          "position goals' tolerance; 0 = 1e-4 of the reach"),
      number_row<&O::tol_angle>("tol_angle", K::kReal, "rad", positive,
                                "orientation targets' and aims' tolerance, an angle (--tol is the "
                                "position goals')"),
      number_row<&O::max_iterations>(
          "max_iterations", K::kInteger, "iterations", non_negative_integer,
          "iteration cap of the classic solvers, KDL and the equilibrium solve (physik)"),
      number_row<&O::lambda>("lambda", K::kReal, "rig units", finite_non_negative,
                             "DLS damping; 0 = 0.02 of the reach"),
      choice_row<&O::jacobian>("jacobian", "analytic|fd", "jt/dls Jacobian"),
      gravity_row(),
      number_row<&O::rotation_damping>(
          "rotation_damping", K::kReal, "1", unit_interval,
          "rotation method: damping factor per joint up the hierarchy"),
      choice_row<&O::socket>("socket", "twist-bend|virtual-bone", "rotation method sockets"),
      choice_row<&O::cone>("cone", "none|circular|elliptical", "rotation method cone limits"),
      number_row<&O::no_limits>("no_limits", K::kBoolean, "", nullptr,
                                "classic solvers ignore the rig's joint limits"),
      number_row<&O::armature>("armature", K::kReal, "1", finite_non_negative,
                               "physik: the joints' armature in the equilibrium solve's metric, a "
                               "fraction of the rig's inertia about its root (0: the rig's inertia "
                               "and dampers alone)"),
      number_row<&O::dt_growth>("dt_growth", K::kReal, "1", at_least_one,
                                "physik-steps: the implicit step lengthens by this factor every "
                                "step the kinetic energy falls (1 = the scene's dt throughout)"),
      number_row<&O::max_dt>("max_dt", K::kReal, "s", positive, "physik-steps: the longest step"),
      choice_row<&O::finish>("finish", "none|ccd|dls",
                             "physik, physik-steps, physik-explicit: when the goals stop "
                             "improving, finish with ccd or dls (the paper's hybrid)"),
  };
}

std::string choice_check(const SolveOptionRow& row, const V& v) {
  for (const std::string& c : row.choices) {
    if (v.text == c) return "";
  }
  std::string all;
  for (const std::string& c : row.choices) all += (all.empty() ? "" : "|") + c;
  return "unknown value '" + v.text + "' (expected " + all + ")";
}

// "" when valid: the row's check, or its choices
std::string why_invalid(const SolveOptionRow& row, const V& v) {
  if (row.kind == SolveOptionKind::kChoice) return choice_check(row, v);
  return row.check ? row.check(v) : "";
}

bool parse_number(const std::string& text, double& out) {
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, out);
  if (ec == std::errc::result_out_of_range && ptr == end) {
    out = std::strtod(text.c_str(), nullptr);  // +-HUGE_VAL or 0: the row's check judges it
    return true;
  }
  return ec == std::errc() && ptr == end && !text.empty();
}

}  // namespace

const std::vector<SolveOptionRow>& solve_option_table() {
  static const std::vector<SolveOptionRow> table = build_table();
  return table;
}

const SolveOptionRow* find_solve_option(const std::string& name) {
  for (const SolveOptionRow& r : solve_option_table()) {
    if (r.name == name) return &r;
  }
  return nullptr;
}

std::string option_label(const std::string& name, OptionSpelling spelling) {
  if (spelling == OptionSpelling::kName) return name;
  std::string flag = "--" + name;
  for (char& c : flag) c = c == '_' ? '-' : c;
  return flag;
}

SolveOptionValue parse_solve_option(const SolveOptionRow& row, const std::string& text,
                                    OptionSpelling spelling) {
  const std::string label = option_label(row.name, spelling);
  V v;
  switch (row.kind) {
    case SolveOptionKind::kChoice:
      v.text = text;
      break;
    case SolveOptionKind::kBoolean:
      if (text != "true" && text != "false") {
        throw_input_error(label, "", "", "expected true or false, got '" + text + "'");
      }
      v.number = text == "true" ? 1.0 : 0.0;
      break;
    case SolveOptionKind::kVec3: {
      std::istringstream in(text);
      for (std::string part; in >> part;) {
        double x = 0.0;
        if (!parse_number(part, x))
          throw_input_error(label, "", "", "expected a number, got '" + part + "'");
        v.vec.push_back(x);
      }
      break;
    }
    case SolveOptionKind::kReal:
    case SolveOptionKind::kInteger:
      if (!parse_number(text, v.number)) {
        throw_input_error(label, "", "", "expected a number, got '" + text + "'");
      }
      if (row.kind == SolveOptionKind::kInteger && v.number != std::floor(v.number)) {
        throw_input_error(label, "", "", "expected an integer, got '" + text + "'");
      }
      break;
  }
  const std::string why = why_invalid(row, v);
  if (!why.empty()) throw_input_error(label, "", "", why);
  return v;
}

void set_solve_option(SceneSolveOptions& o, const SolveOptionRow& row, const SolveOptionValue& v,
                      OptionSpelling spelling) {
  const std::string why = why_invalid(row, v);
  if (!why.empty()) throw_input_error(option_label(row.name, spelling), "", "", why);
  row.set(o, v);
}

std::string solve_option_default_text(const SolveOptionRow& row) {
  const V v = row.get(SceneSolveOptions{});
  std::ostringstream o;
  switch (row.kind) {
    case SolveOptionKind::kChoice:
      return v.text;
    case SolveOptionKind::kBoolean:
      return v.number != 0.0 ? "true" : "false";
    case SolveOptionKind::kVec3:
      for (double x : v.vec) o << (o.tellp() > 0 ? " " : "") << x;
      return o.str();
    default:
      o << v.number;
      return o.str();
  }
}

void check_solve_options(const SceneSolveOptions& options, OptionSpelling spelling) {
  for (const SolveOptionRow& row : solve_option_table()) {
    const V v = row.get(options);
    if (row.name == "solver" && v.text.empty()) {
      throw_input_error(option_label("solver", spelling), "", "",
                        std::string("no solver given (one of ") + kSceneSolvers + ")");
    }
    if (row.kind == SolveOptionKind::kVec3 && v.vec.empty()) continue;  // no gravity
    const std::string why = why_invalid(row, v);
    if (!why.empty()) throw_input_error(option_label(row.name, spelling), "", "", why);
  }
}

}  // namespace physik
