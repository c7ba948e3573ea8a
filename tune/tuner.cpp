#include "tune/tuner.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <limits>
#include <sstream>

#include <ceres/ceres.h>

#include "physik/model/errors.h"
#include "reference/compare.h"
#include "reference/mujoco_runner.h"

namespace physik::tune {

const std::vector<TunableSpec>& tunable_parameters() {
  // the parameter table's rows with tuning bounds, in its order
  static const std::vector<TunableSpec> list = [] {
    std::vector<TunableSpec> out;
    for (const ParamRow& r : param_table()) {
      if (r.tune) out.push_back({r.name, r.tune->first, r.tune->second, r.unit.c_str()});
    }
    return out;
  }();
  return list;
}

namespace {

std::string tunable_names() {
  std::string s;
  for (const TunableSpec& t : tunable_parameters()) s += (s.empty() ? "" : ", ") + t.name;
  return s;
}

const TunableSpec* find_spec(const std::string& name) {
  for (const TunableSpec& t : tunable_parameters()) {
    if (t.name == name) return &t;
  }
  return nullptr;
}

double parse_number(const std::string& text, const std::string& source, const std::string& field) {
  try {
    std::size_t used = 0;
    const double v = std::stod(text, &used);
    if (used == text.size() && std::isfinite(v)) return v;
  } catch (const std::exception&) {
  }
  throw_input_error(source, "", field, "'" + text + "' is not a number");
}

}  // namespace

Objective objective_from_string(const std::string& name, const std::string& source) {
  if (name == "settle") return Objective::kSettle;
  if (name == "mujoco") return Objective::kMujoco;
  throw_input_error(source, "", "objective",
                    "unknown objective '" + name + "' (known: settle, mujoco)");
}

const char* to_string(Objective o) {
  return o == Objective::kSettle ? "settle" : "mujoco";
}

SettleMeasure measure_from_string(const std::string& name, const std::string& source) {
  if (name == "log") return SettleMeasure::kLog;
  if (name == "linear") return SettleMeasure::kLinear;
  throw_input_error(source, "", "measure", "unknown measure '" + name + "' (known: log, linear)");
}

const char* to_string(SettleMeasure m) {
  return m == SettleMeasure::kLog ? "log" : "linear";
}

std::vector<TuneParam> parse_tune_params(const std::string& csv, const std::string& source) {
  std::vector<TuneParam> out;
  std::stringstream ss(csv);
  std::string name;
  while (std::getline(ss, name, ',')) {
    if (name.empty()) continue;
    const TunableSpec* spec = find_spec(name);
    if (!spec) {
      throw_input_error(source, "", name,
                        "unknown tunable parameter (known: " + tunable_names() + ")");
    }
    for (const TuneParam& p : out) {
      if (p.name == name) throw_input_error(source, "", name, "listed twice");
    }
    out.push_back({spec->name, spec->lo, spec->hi});
  }
  if (out.empty()) throw_input_error(source, "", "", "no parameter to tune");
  return out;
}

void apply_bounds(std::vector<TuneParam>& params, const std::string& spec,
                  const std::string& source) {
  const auto eq = spec.find('='), colon = spec.find(':');
  if (eq == std::string::npos || colon == std::string::npos || colon < eq) {
    throw_input_error(source, "", spec, "expected name=lo:hi");
  }
  const std::string name = spec.substr(0, eq);
  const double lo = parse_number(spec.substr(eq + 1, colon - eq - 1), source, name);
  const double hi = parse_number(spec.substr(colon + 1), source, name);
  if (!(lo > 0.0) || !(hi > lo)) throw_input_error(source, "", name, "bounds need 0 < lo < hi");
  for (TuneParam& p : params) {
    if (p.name == name) {
      p.lo = lo;
      p.hi = hi;
      return;
    }
  }
  throw_input_error(source, "", name, "not among the tuned parameters");
}

namespace {

const ParamRow& tunable_row(const std::string& name) {
  if (!find_spec(name)) {
    throw_input_error("", "params", name,
                      "unknown tunable parameter (known: " + tunable_names() + ")");
  }
  return param_row(name);
}

}  // namespace

double get_param(const Scene& s, const std::string& name) {
  return tunable_row(name).get(s.params);
}

void set_param(Scene& s, const std::string& name, double value) {
  tunable_row(name).set(s.params, value);
}

RunSummary settle_residuals(const Scene& scene_in, SettleMeasure measure,
                            std::vector<double>& residuals) {
  Scene scene = scene_in;
  scene.convergence.stop_when_converged = false;  // every step counts: fixed residual count
  const std::size_t nc = scene.control_points.size();
  const double h = scene.rig.height() > 0.0 ? scene.rig.height() : 1.0;
  const double eps = scene.residual_tol() > 0.0 ? scene.residual_tol() : 1e-3 * h;
  const double w = std::sqrt(scene.params.dt);
  const auto rho = [&](double e) {
    e = std::isfinite(e) ? std::min(e, kResidualCap * h) : kResidualCap * h;
    return w * (measure == SettleMeasure::kLog ? std::log1p(e / eps) : e / h);
  };
  // after a divergence the remaining entries keep the cap
  residuals.assign(static_cast<std::size_t>(scene.steps) * nc, rho(kResidualCap * h));
  std::vector<double> r;
  std::size_t at = 0;
  const auto observer = [&](const SimState& s, const StepStats&) {
    control_residuals(scene, s, r);
    for (std::size_t c = 0; c < nc && at < residuals.size(); ++c, ++at) residuals[at] = rho(r[c]);
  };
  return run_scene(scene, observer);
}

std::vector<BoneFrames> mujoco_reference_trajectory(const Scene& scene_in) {
  Scene scene = scene_in;
  scene.convergence.stop_when_converged = false;
  RecordOptions every_frame;
  every_frame.all_frames = true;
  RecordedRun run = record_mujoco(scene, ReferenceMode::kSameForces, every_frame);
  if (run.summary.diverged) {
    throw DivergedRun(
        "MuJoCo's same-forces run of " +
        (scene.file.empty() ? std::string("the scene") : scene.file) +
        ", the objective's reference, ended after " + std::to_string(run.summary.steps_run) +
        " of " + std::to_string(scene.steps) + " steps (" + run.summary.divergence_reason +
        "): no reference to tune against; " + mujoco_hint(scene, run.summary.divergence_reason));
  }
  return std::move(run.frames);
}

RunSummary mujoco_residuals(const Scene& scene_in, const std::vector<BoneFrames>& reference,
                            std::vector<double>& residuals) {
  Scene scene = scene_in;
  scene.convergence.stop_when_converged = false;
  scene.steps = std::max<int>(1, static_cast<int>(reference.size()));
  const int nb = scene.rig.nbone;
  const double h = scene.rig.height() > 0.0 ? scene.rig.height() : 1.0;
  const double w = std::sqrt(scene.params.dt);
  const auto rho = [&](double e) {
    return w * (std::isfinite(e) ? std::min(e / h, kResidualCap) : kResidualCap);
  };
  residuals.assign(reference.size() * 2 * nb, w * kResidualCap);
  std::size_t n = 0;
  const auto observer = [&](const SimState& s, const StepStats&) {
    if (n >= reference.size()) return;
    const BoneFrames& ref = reference[n];
    for (int i = 0; i < nb; ++i) {
      residuals[(n * nb + i) * 2] = rho((s.frames.head_world[i] - ref.head_world[i]).norm());
      residuals[(n * nb + i) * 2 + 1] = rho((s.frames.tail_world[i] - ref.tail_world[i]).norm());
    }
    ++n;
  };
  return run_scene(scene, observer);
}

double cost_of(const std::vector<double>& residuals) {
  double j = 0.0;
  for (double r : residuals) j += r * r;
  return 0.5 * j;
}

namespace {

// Everything one evaluation of the objective needs: the base scene and what is tuned.
class Objective_ {
 public:
  Objective_(const Scene& base, const TuneOptions& opt) : base_(base), opt_(opt) {
    if (opt.objective == Objective::kMujoco) {
      reference_ = mujoco_reference_trajectory(opt.mujoco_scene ? *opt.mujoco_scene : base);
    }
  }

  int num_residuals() const {
    if (opt_.objective == Objective::kMujoco)
      return static_cast<int>(reference_.size()) * 2 * base_.rig.nbone;
    return base_.steps * static_cast<int>(std::max<std::size_t>(1, base_.control_points.size()));
  }
  int reference_steps() const { return static_cast<int>(reference_.size()); }

  // residuals at parameter values p (not logs)
  RunSummary eval(const double* p, std::vector<double>& res) const {
    Scene s = base_;
    for (std::size_t i = 0; i < opt_.params.size(); ++i) set_param(s, opt_.params[i].name, p[i]);
    ++evaluations;
    RunSummary sum = opt_.objective == Objective::kSettle ? settle_residuals(s, opt_.measure, res)
                                                          : mujoco_residuals(s, reference_, res);
    if (sum.diverged) ++diverged;
    return sum;
  }

  // residuals of the base scene as it is (damping auto stays auto); not a candidate: not counted
  RunSummary eval_scene(std::vector<double>& res) const {
    return opt_.objective == Objective::kSettle ? settle_residuals(base_, opt_.measure, res)
                                                : mujoco_residuals(base_, reference_, res);
  }

  Scene scene_with(const std::vector<double>& p) const {
    Scene s = base_;
    for (std::size_t i = 0; i < opt_.params.size(); ++i) set_param(s, opt_.params[i].name, p[i]);
    return s;
  }

  mutable int evaluations = 0;
  mutable int diverged = 0;  // evaluations whose run diverged

 private:
  const Scene& base_;
  const TuneOptions& opt_;
  std::vector<BoneFrames> reference_;  // mujoco objective
};

// Ceres cost over u = ln p with a central-difference Jacobian of step fd_step (one-sided at
// a bound), see the header for why not NumericDiffCostFunction.
class SmoothedCost : public ceres::CostFunction {
 public:
  SmoothedCost(const Objective_& obj, const TuneOptions& opt) : obj_(obj), opt_(opt) {
    set_num_residuals(obj.num_residuals());
    mutable_parameter_block_sizes()->push_back(static_cast<int>(opt.params.size()));
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const int n = static_cast<int>(opt_.params.size()), m = num_residuals();
    std::vector<double> u(parameters[0], parameters[0] + n), p(n), res;
    const auto values = [&](const std::vector<double>& uu) {
      for (int i = 0; i < n; ++i) p[i] = std::exp(uu[i]);
      return p.data();
    };
    obj_.eval(values(u), res);
    std::copy(res.begin(), res.end(), residuals);
    if (!jacobians || !jacobians[0]) return true;
    std::vector<double> plus, minus;
    for (int j = 0; j < n; ++j) {
      const double lo = std::log(opt_.params[j].lo), hi = std::log(opt_.params[j].hi);
      std::vector<double> up = u, um = u;
      up[j] = std::min(hi, u[j] + opt_.fd_step);
      um[j] = std::max(lo, u[j] - opt_.fd_step);
      obj_.eval(values(up), plus);
      if (um[j] < u[j])
        obj_.eval(values(um), minus);
      else
        minus = res;
      const double du = up[j] - um[j];
      for (int r = 0; r < m; ++r)
        jacobians[0][r * n + j] = du > 0.0 ? (plus[r] - minus[r]) / du : 0.0;
    }
    return true;
  }

 private:
  const Objective_& obj_;
  const TuneOptions& opt_;
};

std::string values_text(const std::vector<TuneParam>& params, const std::vector<double>& v) {
  std::ostringstream o;
  for (std::size_t i = 0; i < params.size(); ++i)
    o << (i ? ", " : "") << params[i].name << " " << v[i];
  return o.str();
}

}  // namespace

namespace {

// damping auto's choice at the scene's start pose (N s/m): the damping the scene starts with
double auto_damping_at_start(const Scene& scene) {
  SimState s;
  init_state(scene, s);
  return s.damping_auto_value;
}

// The values the scene runs with: a parameter's own value, damping auto's choice for damping.
double scene_value(const Scene& scene, const std::string& name, const TuneResult& out) {
  return name == "damping" && out.damping_auto ? out.damping_auto_value : get_param(scene, name);
}

// The start: the scene's values clamped into the bounds (out.start_cost is J there); and the
// baseline, the scene as it runs (out.initial_cost; damping auto resolved in out.damping_auto*),
// run apart only when the start differs from it. Returns the start.
std::vector<double> start_values(const Scene& scene, const TuneOptions& opt, const Objective_& obj,
                                 TuneResult& out) {
  const int n = static_cast<int>(opt.params.size());
  std::vector<double> start(n), res;
  out.damping_auto = scene.params.damping_auto;
  if (out.damping_auto) out.damping_auto_value = auto_damping_at_start(scene);
  bool same_as_scene = !out.damping_auto;  // setting a value the scene has changes nothing
  for (int i = 0; i < n; ++i) {
    out.names.push_back(opt.params[i].name);
    out.initial_values.push_back(scene_value(scene, opt.params[i].name, out));
    start[i] = std::clamp(out.initial_values[i], opt.params[i].lo, opt.params[i].hi);
    same_as_scene = same_as_scene && start[i] == out.initial_values[i];
  }
  obj.eval(start.data(), res);
  out.start_cost = cost_of(res);
  out.initial_cost = out.start_cost;
  if (!same_as_scene) {
    obj.eval_scene(res);
    out.initial_cost = cost_of(res);
    out.scene_evaluations += 1;
  }
  if (opt.verbose)
    std::cerr << "tune: scene J " << out.initial_cost << "; start "
              << values_text(opt.params, start) << "  J " << out.start_cost << "\n";
  return start;
}

// Stage 1: a coarse scan, coordinate-wise on a log grid; best and best_cost move to the best
// point seen, every trial is kept in out.scan.
void scan_log_grid(const TuneOptions& opt, const Objective_& obj, std::vector<double>& best,
                   double& best_cost, TuneResult& out) {
  const int n = static_cast<int>(opt.params.size());
  std::vector<double> res;
  for (int sweep = 0; sweep < opt.scan_sweeps && opt.scan_points > 1; ++sweep) {
    for (int i = 0; i < n; ++i) {
      const double lo = std::log(opt.params[i].lo), hi = std::log(opt.params[i].hi);
      std::vector<double> trial = best;
      double arg_best = best[i];
      for (int g = 0; g < opt.scan_points; ++g) {
        trial[i] = std::exp(lo + (hi - lo) * g / (opt.scan_points - 1));
        const RunSummary sum = obj.eval(trial.data(), res);
        const double j = cost_of(res);
        out.scan.push_back({trial, j, sum.diverged, sum.converged ? sum.steps_to_converge : -1});
        if (j < best_cost) {
          best_cost = j;
          arg_best = trial[i];
        }
      }
      best[i] = arg_best;
      if (opt.verbose)
        std::cerr << "tune: scan " << values_text(opt.params, best) << "  J " << best_cost << "\n";
    }
  }
}

// Stage 2: Levenberg-Marquardt in u = ln p within the bounds, from the scan's best point;
// returns the refined values (clamped into the bounds) and Ceres' reports in out.
std::vector<double> refine_with_ceres(const TuneOptions& opt, const Objective_& obj,
                                      const std::vector<double>& from, TuneResult& out) {
  const int n = static_cast<int>(opt.params.size());
  std::vector<double> u(n);
  for (int i = 0; i < n; ++i) u[i] = std::log(from[i]);
  ceres::Problem problem;
  problem.AddResidualBlock(new SmoothedCost(obj, opt), nullptr, u.data());
  for (int i = 0; i < n; ++i) {
    problem.SetParameterLowerBound(u.data(), i, std::log(opt.params[i].lo));
    problem.SetParameterUpperBound(u.data(), i, std::log(opt.params[i].hi));
  }
  ceres::Solver::Options so;
  so.minimizer_type = ceres::TRUST_REGION;
  so.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  so.linear_solver_type = ceres::DENSE_QR;
  so.max_num_iterations = opt.max_iterations;
  so.function_tolerance = 1e-7;
  so.parameter_tolerance = 1e-5;
  so.gradient_tolerance = 1e-12;
  so.num_threads = 1;
  so.minimizer_progress_to_stdout = false;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  out.ceres_brief = summary.BriefReport();
  out.ceres_full = summary.FullReport();
  out.ceres_usable = summary.IsSolutionUsable();
  std::vector<double> refined(n);
  for (int i = 0; i < n; ++i)
    refined[i] = std::clamp(std::exp(u[i]), opt.params[i].lo, opt.params[i].hi);
  return refined;
}

}  // namespace

namespace {

// A tuned parameter must change the run: not one the scheme never reads (ParamRow::conflict),
// not a control point default that every control point overrides with its own.
void check_tunable_in(const Scene& scene, const TuneParam& p) {
  const ParamRow& row = param_row(p.name);
  Scene s = scene;
  set_param(s, p.name, p.lo);  // as every evaluation sets it (damping: auto off)
  if (row.conflict) {
    const std::string why = row.conflict_reason(s.params, param_scene(s));
    if (!why.empty())
      throw_input_error("--params", "", p.name, why + ": tuning it changes nothing");
  }
  const auto own = [&](const ControlPoint& cp) {
    return p.name == "control_k" ? cp.k.has_value() : cp.cap.has_value();
  };
  if ((p.name == "control_k" || p.name == "control_cap") && !scene.control_points.empty() &&
      std::all_of(scene.control_points.begin(), scene.control_points.end(), own)) {
    throw_input_error("--params", "", p.name,
                      "every control point of " + scene.file + " gives its own " +
                          (p.name == "control_k" ? "k" : "cap") + ": tuning it changes nothing");
  }
}

}  // namespace

TuneResult tune_scene(const Scene& scene, const TuneOptions& opt) {
  if (opt.params.empty()) throw_input_error("--params", "", "", "no parameter to tune");
  for (const TuneParam& p : opt.params) check_tunable_in(scene, p);
  if (scene.control_points.empty() && opt.objective == Objective::kSettle) {
    throw_input_error(scene.file, "control_points", "",
                      "the settle objective needs a control point");
  }
  const auto t0 = std::chrono::steady_clock::now();
  Objective_ obj(scene, opt);
  TuneResult out;
  std::vector<double> best = start_values(scene, opt, obj, out), res;
  double best_cost = out.start_cost;
  scan_log_grid(opt, obj, best, best_cost, out);
  out.scan_cost = best_cost;

  const std::vector<double> refined = refine_with_ceres(opt, obj, best, out);
  obj.eval(refined.data(), res);
  const double refined_cost = cost_of(res);
  // keep the scan's point if Ceres could not improve on it (it never should get worse)
  out.values = refined_cost <= best_cost ? refined : best;
  out.final_cost = std::min(refined_cost, best_cost);
  out.tuned_scene = obj.scene_with(out.values);
  out.reference_steps = obj.reference_steps();
  out.scene_run = run_scene(scene);
  out.scene_evaluations += 1;
  if (out.damping_auto) out.damping_auto_updates = out.scene_run.damping_auto_updates;
  out.tuned_run = run_scene(out.tuned_scene);
  out.evaluations = obj.evaluations + 1;
  out.diverged_evaluations = obj.diverged + (out.tuned_run.diverged ? 1 : 0);
  out.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (opt.verbose) {
    std::cerr << "tune: ceres " << values_text(opt.params, out.values) << "  J " << out.final_cost
              << "  (" << out.evaluations << " runs, " << out.wall_time_s << " s)\n";
  }
  return out;
}

bool no_improvement(const TuneResult& r) {
  return !(r.final_cost < r.initial_cost);
}

bool converges_no_later(const TuneResult& r) {
  const RunSummary &scene = r.scene_run, &tuned = r.tuned_run;
  return tuned.converged &&
         (!scene.converged || tuned.steps_to_converge <= scene.steps_to_converge);
}

std::string measures_disagree(const TuneResult& r) {
  const auto step = [](const RunSummary& run) {
    return run.converged ? std::to_string(run.steps_to_converge) : std::string("never");
  };
  const RunSummary &scene = r.scene_run, &tuned = r.tuned_run;
  const bool lower = !no_improvement(r);
  const bool later = scene.converged ? !converges_no_later(r) : false;  // never -> never: not later
  const bool earlier =
      tuned.converged && (!scene.converged || tuned.steps_to_converge < scene.steps_to_converge);
  if (lower && later) {
    return "objective lower, convergence later: step " + step(scene) + " -> " + step(tuned);
  }
  if (!lower && earlier) {
    return "objective not lower, convergence earlier: step " + step(scene) + " -> " + step(tuned);
  }
  return "";
}

std::string tune_failure(const TuneResult& r) {
  if (r.evaluations > 0 && r.diverged_evaluations >= r.evaluations) {
    return "every one of the " + std::to_string(r.evaluations) +
           " runs diverged: no value within the bounds is stable";
  }
  if (r.tuned_run.diverged) {
    return "the run with the tuned values diverged (" + r.tuned_run.divergence_reason + ")";
  }
  return "";
}

}  // namespace physik::tune
