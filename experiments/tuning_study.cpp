// Tuning study: steps to converge against the damping coefficient c for pinhead pulling
// both hands (models/scenes/pinhead_two_hands.json, capped springs k = 30) at scales 0.1x, 1x,
// 10x and mass densities 1 and 10 kg per rig unit; the Ceres optimum of the settle objective
// (tune/tuner.h, log measure) on each curve; a closed-form rule for c, and steps to converge at
// the paper's c = 20, the original's c = 3, the rule's and the tuned value.
// Beside them: damping auto's c at the start pose (critical damping of the slowest
// linearised mode, physik/engine/linear_modes.h), run explicit at that c and implicit with auto.
//
// Scaled rigs are built in code: every head and tail (world, about the origin), the cylinder
// radius, the targets, the spring caps and the initial root position are multiplied by the
// scale s; every bone's mass is density x length. k and dt stay as the user gives them.
//
// The rule (derived, not fitted). Slowest mode model: the whole rig (mass M, n bones) translates
// as one body under the control springs (total stiffness K = sum k, linear near the target) and
// the damping of its 2n bone ends (2 n c). Semi-implicit Euler with step h turns it into the map
// of tests/tune/tuner_test.cpp with a = K h^2 / M, b = 2 n c h / M, whose eigenvalues have the
// smallest modulus (fastest decay, no oscillation: the discrete critical damping) at the double
// root b = 2 sqrt(a) - a:
//     c_crit = (2 sqrt(K M) - K h) / (2 n)      (-> sqrt(K M)/n, critical damping, as h -> 0)
// Stability per bone end (explicit Euler, engine_test.cpp): translation c < m/h, transverse
// rotation c < ((1 + f)/2)(m/h)(r^2/L^2 + 1/3) with f the angular-velocity factor;
// c_stab = the smallest over bones. The rule keeps a factor
// 2 of margin:  c_rule = min(c_crit, c_stab / 2).
// Units: c in N s/m, k in N/m, masses in kg, h in s, lengths in rig units.
#include <algorithm>
#include <chrono>
#include <cmath>

#include "experiments/columns.h"
#include "experiments/common.h"
#include "physik/io/rig_io.h"
#include "tune/tuner.h"

namespace physik::experiments {

namespace {

struct Variant {
  double scale = 1.0;          // 1
  double density = 1.0;        // kg per rig unit
  bool scale_torsion = false;  // torsion k scaled with the inertia (density x scale^3)
  std::string label() const {
    // no commas: it is a CSV cell
    return num(scale, 2) + "x / " + num(density, 2) + " kg/unit" +
           (scale_torsion ? " / k_t scaled" : "");
  }
};

struct Rule {
  double K = 0, M = 0, m_min = 0, c_crit = 0, c_stab = 0, c_rule = 0;
  double torsion_a = 0;      // k_t dt^2 / I_min (transverse): stable below 2 (1 + f)
  double torsion_limit = 0;  // 2 (1 + f), f the angular-velocity factor
};

Rule damping_rule(const Scene& scene) {
  const Rig& rig = scene.rig;
  const double h = scene.params.dt;
  Rule r;
  for (const ControlPoint& cp : scene.control_points) r.K += cp.k_in(scene.params);
  r.M = rig.total_mass();
  r.m_min = *std::min_element(rig.bone_mass.begin(), rig.bone_mass.end());
  r.c_crit = std::max(0.0, (2.0 * std::sqrt(r.K * r.M) - r.K * h) / (2.0 * rig.nbone));
  r.c_stab = 1e300;
  for (int i = 0; i < rig.nbone; ++i) {
    const double L = rig.bone_length[i], rad = rig.bone_radius[i];
    const double f = scene.params.angular_velocity_factor;
    const double bound =
        rig.bone_mass[i] / h * std::min(1.0, 0.5 * (1.0 + f) * (rad * rad / (L * L) + 1.0 / 3.0));
    r.c_stab = std::min(r.c_stab, bound);
  }
  r.c_rule = std::min(r.c_crit, 0.5 * r.c_stab);
  // torsion springs on the lightest bone: w' = f w - (k_t h / I) theta, theta' = theta + h w'
  // has trace 1 + f - a_t and det f: stable iff a_t = k_t h^2 / I < 2 (1 + f), whatever c is
  double i_min = 1e300;
  for (int i = 0; i < rig.nbone; ++i) i_min = std::min(i_min, rig.bone_inertia_local[i].x());
  r.torsion_a = scene.params.torsion_k * h * h / i_min;
  r.torsion_limit = 2.0 * (1.0 + scene.params.angular_velocity_factor);
  return r;
}

struct Point {
  int steps = -1;  // steps to settle, -1 = not within the run
  bool diverged = false;
};

// Steps to settle: the first step from which every later step of the run has every control
// point within the residual tolerance and the rig at rest (rms speed below the speed tolerance).
// (The engine's steps_to_converge asks only for rest, which a heavily over-damped rig crawling
// toward its targets also satisfies.)
// implicit_auto: the implicit step with damping auto instead (c is then only the fallback).
Point run_at(const Scene& scene, double c, bool implicit_auto = false) {
  Scene s = scene;
  s.params.damping = c;
  if (implicit_auto) {
    s.params.scheme = Scheme::kImplicit;
    s.params.damping_auto = true;
  }
  s.convergence.stop_when_converged = false;
  const double rtol = s.residual_tol(), vtol = s.speed_tol(), mass = s.rig.total_mass();
  int last_unsettled = 0;
  const auto observer = [&](const SimState& st, const StepStats& stats) {
    const bool settled =
        stats.max_residual <= rtol && std::sqrt(2.0 * stats.kinetic_energy / mass) < vtol;
    if (!settled) last_unsettled = st.step;
  };
  const RunSummary r = run_scene(s, observer);
  Point p;
  p.diverged = r.diverged;
  if (!r.diverged && last_unsettled < r.steps_run) p.steps = last_unsettled + 1;
  return p;
}

std::string steps_text(const Point& p) {
  return p.diverged ? "diverged" : p.steps < 0 ? "not converged" : std::to_string(p.steps);
}

std::vector<Variant> make_variants(bool quick) {
  std::vector<Variant> variants;
  for (double s : quick ? std::vector<double>{1.0} : std::vector<double>{0.1, 1.0, 10.0}) {
    for (double d : quick ? std::vector<double>{1.0} : std::vector<double>{1.0, 10.0}) {
      variants.push_back({s, d, false});
    }
  }
  // at 0.1x the torsion springs (N m/rad, not scaled) outgrow explicit Euler whatever the
  // damping (see Rule::torsion_a): the same rigs again with k_t scaled like the inertia
  if (!quick) {
    variants.push_back({0.1, 1.0, true});
    variants.push_back({0.1, 10.0, true});
  }
  return variants;
}

// damping grid: log-spaced over 1e-3 .. 1e3 N s/m
std::vector<double> damping_grid(bool quick) {
  const int per_decade = quick ? 1 : 6;
  std::vector<double> grid;
  for (int i = 0; i <= 6 * per_decade; ++i)
    grid.push_back(std::pow(10.0, -3.0 + double(i) / per_decade));
  return grid;
}

// One variant: the damping sweep, the Ceres optimum, the rule, and steps at c = 20, 3, rule, tuned.
struct VariantResult {
  Variant v;
  double torsion_k = 0, dt = 0;
  Rule rule;
  int best_steps = 1 << 30;            // fewest steps to settle on the grid
  double best_c = -1, first_div = -1;  // -1 = none
  tune::TuneResult tuned;
  double c_tuned = 0;
  Point at20, at3, at_rule, at_tuned;
  // damping: auto (physik/engine/linear_modes.h): its c at the start pose, the explicit run at
  // that c, and the implicit run with damping auto (scheme implicit)
  double c_auto = 0;
  Point at_auto, at_auto_implicit;
  std::vector<std::pair<double, Point>> grid;  // the sweep: (c, its run) over the grid
  int best_grid_steps() const { return best_c > 0 ? best_steps : -1; }
};

// the sweep over the grid: one sweep.csv row per damping. first_div is the first c that diverges
// above every settling c ("too large diverges"; a grid also diverges at its small end, where the
// dampers are too weak for the springs), or the first diverging c when none settles.
void sweep_grid(VariantResult& r, const Scene& scene, const std::vector<double>& grid) {
  double last_settled = -1;
  std::vector<double> diverged;
  for (double c : grid) {
    const Point p = run_at(scene, c);
    r.grid.emplace_back(c, p);
    if (p.diverged) diverged.push_back(c);
    if (!p.diverged && p.steps >= 0) last_settled = c;
    if (!p.diverged && p.steps >= 0 && p.steps < r.best_steps) {
      r.best_steps = p.steps;
      r.best_c = c;
    }
  }
  for (double c : diverged) {
    if (c > last_settled) {
      r.first_div = c;
      break;
    }
  }
}

// damping_auto's choice at the start pose
double auto_damping(const Scene& scene) {
  Scene with_auto = scene;
  with_auto.params.damping_auto = true;
  SimState st;
  init_state(with_auto, st);
  return st.damping_auto_value;
}

VariantResult study_variant(const Context& ctx, const Scene& base, const Variant& v,
                            const std::vector<double>& grid) {
  const Scene scene = scaled_scene(base, v.scale, v.density, v.scale_torsion);
  VariantResult r;
  r.v = v;
  r.torsion_k = scene.params.torsion_k;
  r.dt = scene.params.dt;
  r.rule = damping_rule(scene);
  sweep_grid(r, scene, grid);
  // Ceres: the settle objective (log measure), damping bounded to the grid's range
  tune::TuneOptions opt;
  opt.params = tune::parse_tune_params("damping", "tuning_study");
  opt.params[0].lo = grid.front();
  opt.params[0].hi = grid.back();
  opt.scan_points = ctx.quick ? 7 : 13;
  opt.max_iterations = ctx.quick ? 5 : 50;
  r.tuned = tune::tune_scene(scene, opt);
  r.c_tuned = r.tuned.values[0];
  r.at20 = run_at(scene, 20.0);
  r.at3 = run_at(scene, 3.0);
  r.at_rule = run_at(scene, r.rule.c_rule);
  r.at_tuned = run_at(scene, r.c_tuned);
  r.c_auto = auto_damping(scene);
  r.at_auto = run_at(scene, r.c_auto);
  r.at_auto_implicit = run_at(scene, r.c_auto, true);
  if (ctx.log) {
    *ctx.log << "  " << v.label() << ": rule " << num(r.rule.c_rule) << ", tuned " << num(r.c_tuned)
             << ", best grid " << num(r.best_c) << " (" << r.best_grid_steps()
             << " steps), diverges from " << num(r.first_div)
             << "; steps at 20/3/rule/tuned: " << steps_text(r.at20) << "/" << steps_text(r.at3)
             << "/" << steps_text(r.at_rule) << "/" << steps_text(r.at_tuned) << "; auto "
             << num(r.c_auto) << ": " << steps_text(r.at_auto) << " (implicit "
             << steps_text(r.at_auto_implicit) << ")"
             << "  (tune " << num(r.tuned.wall_time_s) << " s)\n";
  }
  return r;
}

const Column kVariant = text("variant", "the rig: scale x / density kg/unit (/ k_t scaled)");
const Column kScale = real("scale", "", "every rig length times this");
const Column kDensity = real("density", "kg per rig unit", "every bone's mass over its length");

// sweep.csv: every variant's run at every c of the grid
Table sweep_table(const std::vector<VariantResult>& results) {
  Column settle = columns::kStepsToConverge;
  settle.doc =
      "steps to settle: every later step within the residual tolerance and at rest (-1: never)";
  Table t("sweep", "sweep.csv",
          {kVariant, kScale, kDensity, columns::kDamping, settle, columns::kDiverged});
  for (const VariantResult& r : results) {
    for (const auto& [c, p] : r.grid)
      t.add({r.v.label(), r.v.scale, r.v.density, c, p.steps, p.diverged});
  }
  return t;
}

// steps to settle at a damping (-1: not settled)
Column steps_at(const std::string& name, const std::string& at) {
  return integer(name, "steps", "steps to settle at " + at + " (-1: diverged or not settled)");
}

// table.csv: one row per variant (the summary's rows say the same with the steps as text)
Table variant_table(const std::vector<VariantResult>& results) {
  const auto c = [](const std::string& name, const std::string& doc) {
    return real(name, "N s/m", doc);
  };
  Table t("table", "table.csv",
          {kVariant,
           kScale,
           kDensity,
           columns::kTorsionK,
           real("torsion_a", "", "k_t dt^2 / I_min: explicit Euler is stable below 2 (1 + f)"),
           real("total_mass", "kg", "M"),
           real("min_bone_mass", "kg", "the lightest bone's mass"),
           real("K", "N/m", "the control springs' total stiffness"),
           c("c_crit", "the rule's discrete critical damping"),
           c("c_stab", "the rule's stability bound"),
           c("c_rule", "min(c_crit, c_stab / 2)"),
           c("c_tuned", "the Ceres optimum"),
           c("c_best_grid", "the grid's fastest-settling c (-1: none)"),
           c("c_first_diverged", "the grid's smallest diverging c (-1: none)"),
           steps_at("steps_paper_20", "c = 20"),
           steps_at("steps_original_3", "c = 3"),
           steps_at("steps_rule", "c_rule"),
           steps_at("steps_tuned", "c_tuned"),
           steps_at("steps_best_grid", "c_best_grid"),
           real("tune_wall_time_s", "s", "the Ceres tuning's wall time"),
           integer("tune_runs", "", "simulations the tuning ran"),
           c("c_auto", "damping auto's c at the start pose"),
           steps_at("steps_auto", "c_auto"),
           steps_at("steps_auto_implicit", "damping auto, scheme implicit")});
  for (const VariantResult& r : results) {
    const Rule& rule = r.rule;
    t.add({r.v.label(),
           r.v.scale,
           r.v.density,
           r.torsion_k,
           rule.torsion_a,
           rule.M,
           rule.m_min,
           rule.K,
           rule.c_crit,
           rule.c_stab,
           rule.c_rule,
           r.c_tuned,
           r.best_c,
           r.first_div,
           r.at20.steps,
           r.at3.steps,
           r.at_rule.steps,
           r.at_tuned.steps,
           r.best_grid_steps(),
           r.tuned.wall_time_s,
           r.tuned.evaluations,
           r.c_auto,
           r.at_auto.steps,
           r.at_auto_implicit.steps});
  }
  return t;
}

nlohmann::json row_json(const VariantResult& r) {
  const Rule& rule = r.rule;
  return {{"variant", r.v.label()},
          {"scale", r.v.scale},
          {"density", r.v.density},
          {"torsion_k", r.torsion_k},
          {"torsion_a", rule.torsion_a},
          {"torsion_stable", rule.torsion_a < rule.torsion_limit},
          {"any_stable_damping", r.best_c > 0},
          {"total_mass", rule.M},
          {"min_bone_mass", rule.m_min},
          {"c_crit", rule.c_crit},
          {"c_stab", rule.c_stab},
          {"c_rule", rule.c_rule},
          {"c_tuned", r.c_tuned},
          {"c_best_grid", r.best_c},
          {"c_first_diverged", r.first_div},
          {"steps_paper_20", steps_text(r.at20)},
          {"steps_original_3", steps_text(r.at3)},
          {"steps_rule", steps_text(r.at_rule)},
          {"steps_tuned", steps_text(r.at_tuned)},
          {"steps_best_grid", r.best_grid_steps()},
          {"tune_cost_initial", r.tuned.initial_cost},
          {"tune_cost_final", r.tuned.final_cost},
          {"tune_wall_time_s", r.tuned.wall_time_s},
          {"tune_runs", r.tuned.evaluations},
          {"c_auto", r.c_auto},
          {"steps_auto", steps_text(r.at_auto)},
          {"steps_auto_implicit", steps_text(r.at_auto_implicit)}};
}

// The counts the claims state, over the variants.
struct Tally {
  int variants = 0, rule_within_2 = 0, tuned_not_worse_than_3 = 0, paper_diverged = 0,
      div_bound_ok = 0;
  int stable_n = 0, torsion_unstable_n = 0, torsion_unstable_all_diverged = 0;
  double worst_rule_ratio = 1.0, tune_time_1x = 0.0;
  int tune_runs_1x = 0;
};

void tally(Tally& t, const VariantResult& r) {
  ++t.variants;
  if (r.at20.diverged) ++t.paper_diverged;
  const bool torsion_unstable = r.rule.torsion_a >= r.rule.torsion_limit;
  if (torsion_unstable) {
    ++t.torsion_unstable_n;
    if (r.best_c < 0) ++t.torsion_unstable_all_diverged;
  }
  if (r.best_c > 0) {  // comparisons only where some damping settles
    ++t.stable_n;
    const double ratio = r.rule.c_rule / r.c_tuned;
    if (ratio >= 0.5 && ratio <= 2.0) ++t.rule_within_2;
    if (std::abs(std::log(ratio)) > std::abs(std::log(t.worst_rule_ratio)))
      t.worst_rule_ratio = ratio;
    if (!r.at_tuned.diverged && r.at_tuned.steps >= 0 &&
        (r.at3.diverged || r.at3.steps < 0 || r.at_tuned.steps <= r.at3.steps)) {
      ++t.tuned_not_worse_than_3;
    }
    const double bound = r.rule.m_min / r.dt;
    if (r.first_div > 0 && r.first_div / bound > 0.25 && r.first_div / bound < 4.0)
      ++t.div_bound_ok;
  }
  if (r.v.scale == 1.0 && r.v.density == 1.0) {
    t.tune_time_1x = r.tuned.wall_time_s;
    t.tune_runs_1x = r.tuned.evaluations;
  }
}

void add_claims(Report& report, const Tally& t) {
  const int nv = t.variants;
  const auto frac_of = [](int k, int n) { return std::to_string(k) + " of " + std::to_string(n); };
  const auto frac = [&](int k) { return frac_of(k, nv); };
  const auto holds = [](int k, int n) {
    return n == 0 ? "n/a" : k == n ? "yes" : k ? "partly" : "no";
  };
  report.claim(
      "Prediction: where the torsion springs on the lightest bone exceed explicit Euler's bound "
      "k_t dt^2 / I_min < 2 (1 + f), no damping can help: every c diverges",
      "every c diverged in " + frac_of(t.torsion_unstable_all_diverged, t.torsion_unstable_n) +
          " torsion-unstable variants",
      holds(t.torsion_unstable_all_diverged, t.torsion_unstable_n));
  report.claim(
      "Discussion: the damping must be picked per rig scale and mass; too large diverges under "
      "explicit Euler. The first diverging c on the grid lies within a factor 4 of the per-bone "
      "bound m_min/dt",
      frac_of(t.div_bound_ok, t.stable_n) + " variants with a settling c",
      holds(t.div_bound_ok, t.stable_n));
  report.claim("Sec. 4: the paper's c = 20 (dt = 0.05) diverges on pinhead-like rigs",
               "diverges in " + frac(t.paper_diverged) + " variants",
               t.paper_diverged == nv ? "yes"
               : t.paper_diverged     ? "partly"
                                      : "no");
  report.claim(
      "Closed-form rule c = min((2 sqrt(K M) - K dt)/(2 n), c_stab/2) lands within a factor 2 of "
      "the Ceres optimum",
      frac_of(t.rule_within_2, t.stable_n) +
          " variants with a settling c; worst rule/tuned ratio " + num(t.worst_rule_ratio),
      holds(t.rule_within_2, t.stable_n));
  report.claim("The tuned c converges in no more steps than the original's c = 3 (or c = 3 fails)",
               frac_of(t.tuned_not_worse_than_3, t.stable_n) + " variants with a settling c",
               holds(t.tuned_not_worse_than_3, t.stable_n));
}

// damping: auto beside the Ceres optimum and the closed-form rule, per variant
void add_auto_row(Report& report, const nlohmann::json& rows) {
  std::string text;
  for (const auto& r : rows) {
    text += (text.empty() ? "" : "; ") + r["variant"].get<std::string>() + ": auto " +
            num(r["c_auto"].get<double>()) + " (" + r["steps_auto"].get<std::string>() +
            ", implicit " + r["steps_auto_implicit"].get<std::string>() + ") / Ceres " +
            num(r["c_tuned"].get<double>()) + " (" + r["steps_tuned"].get<std::string>() +
            ") / rule " + num(r["c_rule"].get<double>()) + " (" +
            r["steps_rule"].get<std::string>() + ")";
  }
  report.claim(
      "damping: auto (critical damping of the slowest linearised mode at the start pose, "
      "physik/engine/linear_modes.h) beside the Ceres optimum and the closed-form rule: c (steps "
      "to "
      "settle, explicit at that c; implicit with damping auto)",
      text, "n/a");
}

// The grid's best c and first diverging c in words: "none" where the grid has no such c (the
// table's -1), never the placeholder itself.
std::string grid_text(const nlohmann::json& r) {
  const double best = r["c_best_grid"].get<double>(),
               diverged = r["c_first_diverged"].get<double>();
  std::string text = best > 0 ? "best grid c " + num(best) + " (" +
                                    std::to_string(r["steps_best_grid"].get<int>()) + " steps)"
                              : "no grid c settles";
  return text + (diverged > 0 ? ", first diverging c " + num(diverged) : ", no grid c diverges");
}

void add_notes(Report& report, const Tally& t, int steps, const nlohmann::json& rows) {
  report.note("One Ceres tuning run of the damping on pinhead (1x / 1 kg/unit, " +
              std::to_string(steps) + " steps per run): " + num(t.tune_time_1x) + " s, " +
              std::to_string(t.tune_runs_1x) + " simulations.");
  report.note(
      "Steps to settle = the first step from which every later step has every control point within "
      "1e-3 of the rig's height of its target and the rig at rest (rms speed below 1e-3 height/s). "
      "The settle objective (log measure) weighs control-point errors only, not the body's rest, "
      "so its optimum and the fewest steps to settle need not coincide.");
  for (const auto& r : rows) {
    report.note(r["variant"].get<std::string>() + ": c_rule " + num(r["c_rule"].get<double>()) +
                " (c_crit " + num(r["c_crit"].get<double>()) + ", c_stab " +
                num(r["c_stab"].get<double>()) + "), c_tuned " + num(r["c_tuned"].get<double>()) +
                ", " + grid_text(r) +
                "; steps at c = 20 / 3 / rule / tuned: " + r["steps_paper_20"].get<std::string>() +
                " / " + r["steps_original_3"].get<std::string>() + " / " +
                r["steps_rule"].get<std::string>() + " / " + r["steps_tuned"].get<std::string>());
  }
}

void run(const Context& ctx) {
  Scene base = scene_named(ctx, "pinhead_two_hands");
  base.steps = ctx.quick ? 300 : 4000;  // the 10x, 10 kg/unit rig needs about 1000
  const std::vector<double> grid = damping_grid(ctx.quick);
  std::vector<VariantResult> results;
  for (const Variant& v : make_variants(ctx.quick))
    results.push_back(study_variant(ctx, base, v, grid));
  const Table sweep = sweep_table(results), table = variant_table(results);
  sweep.write_csv(ctx.out_dir);
  table.write_csv(ctx.out_dir);
  nlohmann::json rows = nlohmann::json::array();
  Tally t;
  for (const VariantResult& r : results) {
    rows.push_back(row_json(r));
    tally(t, r);
  }
  Report report("Tuning study: damping vs scale and mass, Ceres optimum, a closed-form rule");
  add_claims(report, t);
  add_auto_row(report, rows);
  add_notes(report, t, base.steps, rows);
  report.figures({"tuning_study.png"});
  write_summary(ctx,
                {{"experiment", "tuning_study"},
                 {"steps", base.steps},
                 {"dt", base.params.dt},
                 {"rows", rows}},
                report, {&sweep, &table});
}

const Registration registered{
    250,
    {"tuning_study", "Discussion (damping sensitivity)",
     "steps to converge vs damping at 0.1x/1x/10x and two densities; Ceres optimum; "
     "closed-form rule",
     run}};

}  // namespace

}  // namespace physik::experiments
