// Scaling: microseconds per step against the number of bones for four solves side by
// side in one run, on chains and balanced binary trees of 10 to 10,000 bones (scaling.h):
//   gauss_seidel_paper  the paper's passes, eps 1e-3 rig units/s^2, cap 5 n^2 (joint_forces.h)
//   gauss_seidel_tight  the same with eps 1e-9
//   exact               scheme exact: the articulated-body algorithm (articulated_body.h)
//   mj_step             MuJoCo on the equivalent ball-joint model, same-forces replay
// Each is timed over the first steps from rest (whole step() for PhysIK, mj_step alone for
// MuJoCo), batches repeated while the time budget lasts, the fastest batch kept.
// Cost exponent p: least squares of log(us per step) on log(N) over the sizes 100..10,000 it ran.
// Accuracy against exact: the relative joint-force error of one solve on the same moving state
// (the exact run's after the timed steps), with the velocity terms both solves share
// (centripetal on, angular-velocity factor 1: the Gauss-Seidel fixed point is then the exact
// solution, so a tight solve's error is its eps and round-off),
//   e = sqrt(sum_i |F_i - F_i^exact|^2) / sqrt(sum_i |F_i^exact|^2)   (F = joint_force_world),
// and for mj_step the largest endpoint gap to the exact run after the same steps (rig units).
// Budget: a solve is skipped at a size where its projected time per step (the last two sizes'
// exponent, at least 1, extrapolated) passes a limit; the output says so.
#include "experiments/scaling.h"

#include <algorithm>
#include <cmath>
#include <ctime>
#include <map>

#include "experiments/common.h"
#include "experiments/report.h"
#include "experiments/table.h"
#include "physik/engine/forces.h"
#include "physik/engine/integrate_joint_space.h"
#include "physik/engine/joint_forces.h"
#include "physik/model/rig_generators.h"
#include "reference/compare.h"

namespace physik::experiments {

Scene scaling_scene(const std::string& kind, int nbone, Scheme solve, double joint_eps) {
  const Rig rig = kind == "chain" ? make_chain_rig(nbone) : make_tree_rig(nbone, 2);
  Scene s;
  s.file = "<scaling " + kind + " " + std::to_string(nbone) + ">";
  s.rig = rig;
  s.params = preset_params("original");
  s.params.scheme = solve;
  s.params.joint_eps = joint_eps;
  s.steps = 100;
  s.initial_pose = rest_pose(rig);
  ControlPoint c;
  c.bone = nbone - 1;
  c.alpha = 1.0;
  c.target_world = rig.bone_rest_tail_world[nbone - 1] + Vec3(3.0, 1.0, 0.0);
  c.k = 10.0;
  c.spring = SpringLaw::kCapped;
  s.control_points.push_back(c);
  return s;
}

double thread_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

MjStepReplay record_mj_step_replay(const Scene& scene, int steps) {
  const double t0 = thread_seconds();
  MujocoReference ref(scene, ReferenceMode::kSameForces);
  MjStepReplay r;
  r.compile_s = thread_seconds() - t0;
  const mjModel* m = ref.model();
  r.model.reset(mj_copyModel(nullptr, m));
  r.start = make_mjdata(m);
  mj_copyData(r.start.get(), m, ref.data());
  r.xfrc.resize(steps);
  for (int k = 0; k < steps; ++k) {
    ref.step();
    r.xfrc[k].assign(ref.data()->xfrc_applied, ref.data()->xfrc_applied + 6 * m->nbody);
  }
  r.final_frames = ref.state().frames;
  r.data = make_mjdata(m);
  return r;
}

double time_mj_step_replay(MjStepReplay& r) {
  const mjModel* m = r.model.get();
  mjData* d = r.data.get();
  mj_copyData(d, m, r.start.get());
  const double t0 = thread_seconds();
  for (const auto& f : r.xfrc) {
    std::copy(f.begin(), f.end(), d->xfrc_applied);
    mj_step(m, d);
  }
  return 1e6 * (thread_seconds() - t0) / static_cast<double>(r.xfrc.size());
}

// One solve's joint forces on `state`, with the velocity terms both solves share (centripetal
// on, angular-velocity factor 1), N per bone, world axes.
std::vector<Vec3> joint_forces_at(Scene scene, const SimState& state) {
  scene.params.centripetal = true;
  scene.params.angular_velocity_factor = 1.0;
  SimState s = state;
  apply_forces(scene, s);
  if (scene.params.scheme == Scheme::kExact) {
    solve_articulated(scene.rig, scene.params, s);
  } else {
    solve_joint_forces(scene.rig, scene.params, s);
  }
  return s.joint_force_world;
}

namespace {

constexpr const char* kMethods[] = {"gauss_seidel_paper", "gauss_seidel_tight", "exact", "mj_step"};
constexpr double kTightEps = 1e-9;  // rig units/s^2

struct Budget {
  double limit_s;  // skip a solve whose projected time per step passes this
  double total_s;  // repeat batches while under this
  int steps;       // a batch: the first `steps` steps from rest (every solve, every size)
};

struct Measured {
  std::string status = "ok";  // or "skipped: ..." / "diverged"
  double us_per_step = NAN;
  int steps = 0, batches = 0;
  double passes_per_step = NAN;
  double force_error = NAN;   // relative, step 1, against exact
  double gap_vs_exact = NAN;  // rig units, mj_step only
  double compile_s = NAN;     // s, mj_step only
  BoneFrames final_frames;    // after the first `steps` steps
  SimState end_state;         // PhysIK: the state after the first `steps` steps
};

// PhysIK's step() over `steps` steps from rest, batches while the budget lasts
Measured time_physik(const Scene& scene, int steps, const Budget& b) {
  Measured out;
  SimState initial;
  init_state(scene, initial);
  double best = INFINITY, spent = 0.0;
  long passes = 0;
  while (out.batches == 0 || (spent < b.total_s && out.batches < 20)) {
    SimState s = initial;
    double t = 0.0;
    for (int k = 0; k < steps; ++k) {
      const double t0 = thread_seconds();
      const StepStats st = step(scene, s);
      t += thread_seconds() - t0;
      if (out.batches == 0) passes += st.iterations();
      if (!std::isfinite(st.kinetic_energy)) out.status = "diverged";
    }
    if (out.batches == 0) {
      out.final_frames = s.frames;
      out.end_state = s;
    }
    best = std::min(best, t / steps);
    spent += t;
    ++out.batches;
  }
  out.steps = steps;
  out.us_per_step = 1e6 * best;
  out.passes_per_step = static_cast<double>(passes) / steps;
  return out;
}

double relative_force_error(const std::vector<Vec3>& f, const std::vector<Vec3>& exact) {
  double num = 0.0, den = 0.0;
  for (std::size_t i = 0; i < exact.size(); ++i) {
    num += (f[i] - exact[i]).squaredNorm();
    den += exact[i].squaredNorm();
  }
  return den > 0.0 ? std::sqrt(num / den) : std::sqrt(num);
}

Measured time_mj_step(const Scene& exact_scene, int steps, const Budget& b) {
  Measured out;
  MjStepReplay r = record_mj_step_replay(exact_scene, steps);
  out.compile_s = r.compile_s;
  out.final_frames = r.final_frames;
  double best = INFINITY, spent = 0.0;
  while (out.batches == 0 || (spent < b.total_s && out.batches < 20)) {
    const double us = time_mj_step_replay(r);
    best = std::min(best, us);
    spent += 1e-6 * us * steps;
    ++out.batches;
  }
  out.steps = steps;
  out.us_per_step = best;
  return out;
}

// the last measured sizes of one solve on one rig kind, for projecting the next
struct History {
  std::vector<double> n, us;
  bool stopped = false;
  double projected_us(double nbone, double prior_exponent) const {
    if (n.empty()) return 0.0;
    double p = prior_exponent;
    if (n.size() >= 2) {
      const std::size_t k = n.size() - 1;
      p = std::max(1.0, std::log(us[k] / us[k - 1]) / std::log(n[k] / n[k - 1]));
    }
    return us.back() * std::pow(nbone / n.back(), p);
  }
};

// least-squares slope of log(us) on log(n) over n in [lo, hi]; NAN with fewer than 2 points
double fit_exponent(const History& h, double lo, double hi) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int m = 0;
  for (std::size_t i = 0; i < h.n.size(); ++i) {
    if (h.n[i] < lo || h.n[i] > hi) continue;
    const double x = std::log(h.n[i]), y = std::log(h.us[i]);
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
    ++m;
  }
  if (m < 2) return NAN;
  return (m * sxy - sx * sy) / (m * sxx - sx * sx);
}

nlohmann::json number_or_null(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json();
}

struct Row {
  std::string kind, method;
  int nbone = 0;
  Measured m;
};

// per solve: the prior cost exponent for the first projection
double prior_exponent(const std::string& method) {
  if (method == "exact") return 1.0;
  if (method == "gauss_seidel_paper") return 2.0;
  return 3.0;
}

// the frames after `steps` exact steps from rest (for mj_step's gap)
BoneFrames exact_frames_after(const Scene& scene, int steps) {
  SimState s;
  init_state(scene, s);
  for (int k = 0; k < steps; ++k) step(scene, s);
  return s.frames;
}

struct Study {
  Budget budget;
  std::map<std::string, History> history;  // key: kind + method
  std::map<std::string, History> compile;  // key: kind, mj_step's compile seconds
  std::vector<Row> rows;
  std::ostream* log = nullptr;
};

// One solve at one size: skip it if its projection passes the budget, else time it.
Measured measure(Study& st, const std::string& kind, int n, const std::string& method,
                 const Measured* exact) {
  History& h = st.history[kind + method];
  Measured m;
  const double projected_s = 1e-6 * h.projected_us(n, prior_exponent(method));
  const double compile_s = method == "mj_step" ? st.compile[kind].projected_us(n, 3.0) : 0.0;
  if (h.stopped || projected_s > st.budget.limit_s || compile_s > 5.0 * st.budget.limit_s) {
    h.stopped = true;
    m.status = "skipped: projected " + num(std::max(projected_s, compile_s), 2) + " s per " +
               (compile_s > projected_s ? "compile" : "step") + " > " +
               num(compile_s > projected_s ? 5.0 * st.budget.limit_s : st.budget.limit_s, 2) + " s";
    return m;
  }
  const int steps = st.budget.steps;
  if (method == "mj_step") {
    const Scene scene = scaling_scene(kind, n, Scheme::kExact);
    m = time_mj_step(scene, steps, st.budget);
    m.gap_vs_exact = pose_gap(m.final_frames, exact_frames_after(scene, steps));
    st.compile[kind].n.push_back(n);
    st.compile[kind].us.push_back(m.compile_s);  // seconds, in the same projection
  } else {
    const bool gs = method != "exact";
    const Scene scene = scaling_scene(kind, n, gs ? Scheme::kGaussSeidel : Scheme::kExact,
                                      method == "gauss_seidel_tight" ? kTightEps : 1e-3);
    m = time_physik(scene, steps, st.budget);
    if (gs && exact) {
      const std::vector<Vec3> ref = joint_forces_at(scaling_scene(kind, n), exact->end_state);
      m.force_error = relative_force_error(joint_forces_at(scene, exact->end_state), ref);
    }
  }
  h.n.push_back(n);
  h.us.push_back(m.us_per_step);
  return m;
}

void log_row(std::ostream* log, const Row& r) {
  if (!log) return;
  *log << "  " << r.kind << " " << r.nbone << " " << r.method << ": ";
  if (r.m.status.rfind("skipped", 0) == 0) {
    *log << r.m.status << "\n";
    return;
  }
  *log << num(r.m.us_per_step) << " us/step (" << num(r.m.us_per_step / r.nbone) << " us/bone), "
       << r.m.steps << " steps x " << r.m.batches << " batches";
  if (std::isfinite(r.m.force_error)) *log << ", force error " << num(r.m.force_error);
  if (std::isfinite(r.m.gap_vs_exact)) *log << ", gap to exact " << num(r.m.gap_vs_exact);
  if (std::isfinite(r.m.compile_s)) *log << ", compile " << num(r.m.compile_s) << " s";
  *log << (r.m.status == "ok" ? "" : " [" + r.m.status + "]") << "\n";
  log->flush();
}

void run_sizes(Study& st, const std::vector<int>& sizes) {
  for (const std::string kind : {"chain", "tree2"}) {
    for (int n : sizes) {
      const Measured exact = measure(st, kind, n, "exact", nullptr);
      for (const char* method : kMethods) {
        Row r{kind, method, n,
              method == std::string("exact") ? exact : measure(st, kind, n, method, &exact)};
        r.m.end_state = SimState{};  // only the exact one's is needed, and only for this size
        log_row(st.log, r);
        st.rows.push_back(std::move(r));
      }
    }
  }
}

// scaling.csv: one row per rig kind, size and solve; an unmeasured number is an empty cell
Table scaling_table(const Study& st) {
  const auto measure = [](std::string name, std::string unit, std::string doc) {
    return real(std::move(name), std::move(unit), std::move(doc)).blank_if_nonfinite();
  };
  Table t("scaling", "scaling.csv",
          {text("kind", "the rig: chain or tree2 (a balanced binary tree)"),
           integer("nbone", "", "bones"),
           text("method", "the solve: gauss_seidel_paper, gauss_seidel_tight, exact or mj_step"),
           text("status", "ok, diverged, or skipped: and why").in_quotes(),
           measure("us_per_step", "us", "thread CPU time per step, the fastest batch"),
           measure("us_per_bone", "us", "us_per_step / nbone"),
           integer("steps", "steps", "steps per batch"), integer("batches", "", "batches timed"),
           measure("passes_per_step", "", "Gauss-Seidel passes per step (first batch)"),
           measure("force_error", "", "relative joint-force error against exact, same state"),
           measure("gap_vs_exact", "rig units", "mj_step: largest endpoint gap to the exact run"),
           measure("compile_s", "s", "mj_step: thread time compiling the MJCF")});
  for (const Row& r : st.rows) {
    t.add({r.kind, r.nbone, r.method, r.m.status, r.m.us_per_step, r.m.us_per_step / r.nbone,
           r.m.steps, r.m.batches, r.m.passes_per_step, r.m.force_error, r.m.gap_vs_exact,
           r.m.compile_s});
  }
  return t;
}

// the pinhead target: the exact step against mj_step on the equivalent model, in this run
nlohmann::json pinhead_ratio(const Context& ctx, const Budget& b) {
  Scene exact = scene_named(ctx, "pinhead_two_hands");
  const Scene gs = exact;
  exact.params.scheme = Scheme::kExact;
  const int steps = ctx.quick ? 20 : 100;
  const Budget longer{b.limit_s, 4.0 * b.total_s, steps};
  const Measured e = time_physik(exact, steps, longer), g = time_physik(gs, steps, longer);
  const Measured mj = time_mj_step(exact, steps, longer);
  const double ratio = e.us_per_step / mj.us_per_step;
  if (ctx.log) {
    *ctx.log << "  pinhead_two_hands: exact " << num(e.us_per_step) << " us/step, Gauss-Seidel "
             << num(g.us_per_step) << ", mj_step " << num(mj.us_per_step) << ": exact/mj_step "
             << num(ratio) << "\n";
  }
  return {{"scene", "pinhead_two_hands"}, {"steps", steps},
          {"exact_us", e.us_per_step},    {"gauss_seidel_us", g.us_per_step},
          {"mj_step_us", mj.us_per_step}, {"exact_over_mj_step", ratio}};
}

// the fitted exponents, per rig kind and solve, over 100..10,000 bones
nlohmann::json exponents(const Study& st) {
  nlohmann::json out = nlohmann::json::array();
  for (const std::string kind : {"chain", "tree2"}) {
    for (const char* method : kMethods) {
      const auto it = st.history.find(kind + method);
      if (it == st.history.end()) continue;
      const History& h = it->second;
      // over 100..10,000 (the targets' range); a solve that ran there at one size or none is
      // fitted over every size it ran, and its sizes say so
      double lo = 100;
      if (std::count_if(h.n.begin(), h.n.end(), [](double n) { return n >= 100; }) < 2) lo = 0;
      std::vector<int> fitted;
      for (double n : h.n) {
        if (n >= lo) fitted.push_back(static_cast<int>(n));
      }
      out.push_back({{"kind", kind},
                     {"method", method},
                     {"exponent", number_or_null(fit_exponent(h, lo, 10000))},
                     {"sizes", fitted}});
    }
  }
  return out;
}

const Row* find_row(const Study& st, const std::string& kind, int n, const std::string& method) {
  for (const Row& r : st.rows) {
    if (r.kind == kind && r.nbone == n && r.method == method) return &r;
  }
  return nullptr;
}

std::string cell(const Row* r, double v, int digits = 3) {
  if (!r) return "";
  if (r->m.status.rfind("skipped", 0) == 0) return "skipped";
  return std::isfinite(v) ? num(v, digits) : "";
}

nlohmann::json time_table(const Study& st, const std::vector<int>& sizes) {
  nlohmann::json rows = nlohmann::json::array();
  for (const std::string kind : {"chain", "tree2"}) {
    for (int n : sizes) {
      const Row* r[4];
      for (int k = 0; k < 4; ++k) r[k] = find_row(st, kind, n, kMethods[k]);
      rows.push_back({kind, n, cell(r[0], r[0]->m.us_per_step), cell(r[1], r[1]->m.us_per_step),
                      cell(r[2], r[2]->m.us_per_step), cell(r[3], r[3]->m.us_per_step),
                      cell(r[2], r[2]->m.us_per_step / n), cell(r[0], r[0]->m.force_error, 2),
                      cell(r[1], r[1]->m.force_error, 2), cell(r[3], r[3]->m.gap_vs_exact, 2),
                      cell(r[0], r[0]->m.passes_per_step, 4)});
    }
  }
  return {{"title", "Microseconds per step (thread CPU time), and each solve against exact"},
          {"columns",
           {"rig", "bones", "GS eps 1e-3", "GS eps 1e-9", "exact", "mj_step", "exact us/bone",
            "GS 1e-3 force error", "GS 1e-9 force error", "mj_step gap to exact",
            "GS 1e-3 passes/step"}},
          {"rows", rows}};
}

double exponent_of(const nlohmann::json& fits, const std::string& kind, const std::string& method) {
  for (const auto& f : fits) {
    if (f["kind"] == kind && f["method"] == method && !f["exponent"].is_null())
      return f["exponent"];
  }
  return NAN;
}

void add_target_claims(Report& report, const Study& st, const nlohmann::json& fits,
                       const nlohmann::json& pin, int largest) {
  const double ratio = pin["exact_over_mj_step"];
  report.claim("Target: on pinhead the exact step takes at most 0.5x mj_step (same run)",
               "exact " + num(pin["exact_us"].get<double>()) + " us/step (whole step), mj_step " +
                   num(pin["mj_step_us"].get<double>()) + " us: ratio " + num(ratio),
               ratio <= 0.5 ? "yes" : "no");
  if (const Row* r = find_row(st, "chain", largest, "exact")) {
    const double per_bone = r->m.us_per_step / largest;
    report.claim(
        "Target: " + num(largest, 6) + "-bone chain at most 0.5 us per bone per step (exact)",
        num(per_bone) + " us per bone per step (" + num(r->m.us_per_step) + " us/step)",
        largest < 10000   ? "n/a (quick run)"
        : per_bone <= 0.5 ? "yes"
                          : "no");
  }
  for (const std::string kind : {"chain", "tree2"}) {
    const double p = exponent_of(fits, kind, "exact");
    const std::string others = "Gauss-Seidel 1e-3 " +
                               num(exponent_of(fits, kind, "gauss_seidel_paper"), 3) + ", 1e-9 " +
                               num(exponent_of(fits, kind, "gauss_seidel_tight"), 3) +
                               ", mj_step " + num(exponent_of(fits, kind, "mj_step"), 3);
    report.claim("Target: exact cost exponent at most 1.1 from 100 to " + std::to_string(largest) +
                     " bones (" + kind + ")",
                 "exact " + num(p, 3) + "; " + others + " (their fits: the table below)",
                 largest < 10000 || !std::isfinite(p) ? "n/a (quick run)"
                 : p <= 1.1                           ? "yes"
                                                      : "no");
  }
}

void add_notes(Report& report, const Budget& b) {
  report
      .note(
          "Scenario: a chain or balanced binary tree from rest, pulled at its last bone's tail by "
          "a "
          "capped spring (k 10 N/m), `original` preset; every solve timed over the same first " +
          std::to_string(b.steps) + " steps from rest, batches repeated while under " +
          num(b.total_s, 2) + " s, the fastest batch kept. Table: results/scaling/scaling.csv.")
      .note(
          "Times are thread CPU time: PhysIK's whole step (force stages included), mj_step alone "
          "on the ball-joint model replaying the same forces. The machine may be shared.")
      .note(
          "Force error: relative joint-force error of one solve against exact on the exact run's "
          "state after the timed steps (moving), with centripetal terms on and the "
          "angular-velocity "
          "factor 1 in both (then the Gauss-Seidel fixed point is the exact solution). mj_step "
          "gap: "
          "largest endpoint distance to the exact run after the same steps (rig units).")
      .note("A solve is skipped where its projected time per step passes " + num(b.limit_s, 2) +
            " s (or MuJoCo's compile " + num(5.0 * b.limit_s, 2) + " s); the row says so.")
      .note(
          "Benchmark with repetitions: build/physik_bench "
          "--benchmark_filter='BM_Exact|BM_MjStep|BM_ExactVsMjStep'.");
}

void add_tables(Report& report, const Study& st, const std::vector<int>& sizes,
                const nlohmann::json& fits) {
  const nlohmann::json t = time_table(st, sizes);
  report.table(t["title"], t["columns"].get<std::vector<std::string>>(), t["rows"]);
  nlohmann::json fit_rows = nlohmann::json::array();
  for (const auto& f : fits) {
    fit_rows.push_back({f["kind"], f["method"],
                        f["exponent"].is_null() ? "n/a" : num(f["exponent"].get<double>(), 3),
                        f["sizes"].dump()});
  }
  report.table(
      "Cost exponents: us per step ~ N^p, least squares over 100..10,000 bones (over every "
      "size run where fewer than two of those ran)",
      {"rig", "solve", "p", "sizes fitted"}, fit_rows);
}

void run(const Context& ctx) {
  const std::vector<int> sizes = ctx.quick ? std::vector<int>{10, 30, 100}
                                           : std::vector<int>{10, 30, 100, 300, 1000, 3000, 10000};
  Study st;
  st.budget = ctx.quick ? Budget{0.05, 0.02, 5} : Budget{1.5, 0.25, 10};
  st.log = ctx.log;
  run_sizes(st, sizes);
  const Table table = scaling_table(st);
  table.write_csv(ctx.out_dir);
  const nlohmann::json fits = exponents(st);
  const nlohmann::json pin = pinhead_ratio(ctx, st.budget);
  Report report("Scaling: Gauss-Seidel, exact and mj_step from 10 to 10,000 bones");
  add_target_claims(report, st, fits, pin, sizes.back());
  add_tables(report, st, sizes, fits);
  add_notes(report, st.budget);
  report.figures({"scaling.png"});
  write_summary(
      ctx,
      {{"experiment", "scaling"}, {"table", "scaling.csv"}, {"exponents", fits}, {"pinhead", pin}},
      report, {&table});
}

const Registration registered{
    260,
    {"scaling", "study: scaling",
     "us per step vs bones (10..10,000): Gauss-Seidel (eps 1e-3, 1e-9), exact, mj_step", run}};

}  // namespace

}  // namespace physik::experiments
