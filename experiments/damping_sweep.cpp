// The discussion's damping sensitivity: steps to converge against the damping coefficient c on
// pinhead, showing where explicit Euler diverges. Stability bounds per bone end (engine_test.cpp
// derives them): translation c < m/dt, transverse rotation c < ((1 + f)/2)(m/dt)(r^2/L^2 + 1/3),
// f the angular-velocity factor.
#include <algorithm>

#include "experiments/columns.h"
#include "experiments/common.h"

namespace physik::experiments {

namespace {

// scene counts over the sweep
struct Counts {
  int paper_diverged, slow_when_small, diverge_when_large, scenes;
};

// best: per scene, the fastest-settling damping and its steps
void add_claims(Report& report, const std::vector<double>& cs, const nlohmann::json& best,
                const Counts& n) {
  report
      .claim(
          "Sec. 4: damping c = 20 with dt = 0.05 (the paper's settings) poses the rig",
          "c = 20 diverged on " + std::to_string(n.paper_diverged) + " of " +
              std::to_string(n.scenes) + " pinhead scenes; fastest settling: " +
              [&] {
                std::string t;
                for (auto it = best.begin(); it != best.end(); ++it) {
                  const double c = it.value()[columns::kDamping.name].get<double>();
                  t += (t.empty() ? "" : ", ") + it.key() +
                       (c < 0 ? std::string(": no damping converged")
                              : " c = " + num(c) + " (" +
                                    std::to_string(
                                        it.value()[columns::kStepsToConverge.name].get<int>()) +
                                    " steps)");
                }
                return t;
              }(),
          n.paper_diverged == 0 ? "yes" : "no")
      .named("paper-damping-poses");
  report.claim(
      "Sec. 5: the damping must be hand-picked; too large diverges, too small converges slowly",
      "scenes where the smallest c (" + num(cs.front()) +
          ") takes over twice the fastest settling: " + std::to_string(n.slow_when_small) + " of " +
          std::to_string(n.scenes) + "; scenes that diverge at large c: " +
          std::to_string(n.diverge_when_large) + " of " + std::to_string(n.scenes) + " (sweep.csv)",
      n.slow_when_small == n.scenes && n.diverge_when_large == n.scenes ? "yes"
      : n.slow_when_small + n.diverge_when_large > 0                    ? "partly"
                                                                        : "no");
}

// The sweep: per scene, one run per damping value.
struct SceneSweep {
  std::string name;
  std::vector<RunSummary> runs;  // one per c, in the grid's order
  int steps = 0;                 // the step cap
};

std::vector<SceneSweep> measure(const Context& ctx, const std::vector<double>& cs) {
  std::vector<SceneSweep> out;
  for (const std::string name : {"pinhead_two_hands", "fig5_running", "fig9_outstretched"}) {
    Scene base = scene_named(ctx, name);
    base.steps = ctx.quick ? 100 : 1500;
    base.convergence.stop_when_converged = true;
    SceneSweep sweep{name, {}, base.steps};
    for (double c : cs) {
      Scene s = base;
      s.params.damping = c;
      sweep.runs.push_back(run_scene(s));
    }
    out.push_back(std::move(sweep));
  }
  return out;
}

double max_final_residual(const RunSummary& r) {
  return r.final_residuals.empty()
             ? 0.0
             : *std::max_element(r.final_residuals.begin(), r.final_residuals.end());
}

Table tabulate(const std::vector<SceneSweep>& sweeps, const std::vector<double>& cs) {
  using namespace columns;
  Table t("sweep", "sweep.csv",
          {kScene, kDamping, kConverged, kStepsToConverge, kDiverged, kStepsRun, kPeakKineticEnergy,
           kMaxFinalResidual});
  for (const SceneSweep& sw : sweeps) {
    for (std::size_t k = 0; k < cs.size(); ++k) {
      const RunSummary& r = sw.runs[k];
      t.add({sw.name, cs[k], r.converged, r.steps_to_converge, r.diverged, r.steps_run,
             r.peak_kinetic_energy, max_final_residual(r)});
    }
  }
  return t;
}

// per scene, the fastest-settling damping and its steps (-1: none settled), and the counts
Counts count(const std::vector<SceneSweep>& sweeps, const std::vector<double>& cs,
             nlohmann::json& best, std::ostream* log) {
  Counts n{0, 0, 0, 0};
  for (const SceneSweep& sw : sweeps) {
    double best_c = -1;
    int best_steps = 1 << 30;
    int smallest_c_steps = -1;  // steps to converge at the smallest c
    bool any_diverged = false;
    ++n.scenes;
    for (std::size_t k = 0; k < cs.size(); ++k) {
      const RunSummary& r = sw.runs[k];
      const double c = cs[k];
      if (r.converged && r.steps_to_converge < best_steps) {
        best_steps = r.steps_to_converge;
        best_c = c;
      }
      if (c == 20.0 && r.diverged) ++n.paper_diverged;
      if (c == cs.front()) smallest_c_steps = r.converged ? r.steps_to_converge : sw.steps;
      // "too large diverges": a divergence above the fastest-settling damping
      if (r.diverged && best_c > 0 && c > best_c) any_diverged = true;
    }
    if (best_c > 0 && smallest_c_steps > 2 * best_steps) ++n.slow_when_small;
    if (any_diverged) ++n.diverge_when_large;
    best[sw.name] = {{columns::kDamping.name, best_c},
                     {columns::kStepsToConverge.name, best_steps}};
    if (log)
      *log << "  " << sw.name << ": fastest at c = " << best_c << " (" << best_steps << " steps)\n";
  }
  return n;
}

void run(const Context& ctx) {
  const std::vector<double> cs =
      ctx.quick
          ? std::vector<double>{1, 3, 20}
          : std::vector<double>{0.25, 0.5, 1, 1.5, 2, 2.5, 3, 3.5, 4, 5, 6, 8, 10, 15, 20, 30};
  const std::vector<SceneSweep> sweeps = measure(ctx, cs);
  const Table sweep = tabulate(sweeps, cs);
  sweep.write_csv(ctx.out_dir);
  nlohmann::json best;
  const Counts n = count(sweeps, cs, best, ctx.log);
  Report report("Damping sensitivity");
  add_claims(report, cs, best, n);
  report
      .note(
          "Each run stops once at rest (10 steps with rms speed < 1e-3 of the rig height per "
          "second) "
          "or after 1500 steps; divergence = non-finite state or kinetic energy above 1e6 M h^2.")
      .figures({"damping_sweep.png"});
  write_summary(ctx,
                {{"experiment", "damping_sweep"}, {"rows", sweep.rows_json()}, {"fastest", best}},
                report, {&sweep});
}

const Registration registered{220,
                              {"damping_sweep", "Sec. 4-5 damping",
                               "steps to converge against damping; divergence region", run}};

}  // namespace

}  // namespace physik::experiments
