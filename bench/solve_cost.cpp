// physik_solve_cost: what a step of the solve mode costs beside the bare implicit step it takes.
// On one of ik_comparison's rigs (experiments/ik_cases.h) and its first `--targets` reachable
// targets, each target is solved from the rest pose as ik_comparison's physik row solves it (a
// PosingSession of effector_scene in the solve mode, the target jumped to at once, the root's
// head pinned, solve_mode_rule with the tolerance 1e-4 of the reach and at most 2000 steps;
// --linearisation full as its physik-full row):
// that is solve_cost_solve, the whole solve with its per-step bookkeeping (the energy guard's
// snapshot and energies, the step's measures, the run monitor's observation and rules). Then
// solve_cost_bare_steps takes, from the state that solve ended in, as many bare implicit steps
// (take_implicit_step: the forces, the O(n) solve and the joint-space update, nothing else) at
// the scene's dt as the solve took steps (from the solve's start, unguarded steps of dt whip
// chain50 to non-finite values). A bare step's instructions do not depend on the state (no
// contacts here): callgrind counts take_implicit_step inside a solve at the same count per call.
//
// The bookkeeping per step is (solve - bare) / bare. Two measures of it:
//   - thread CPU time of each loop (printed), a figure a busy machine moves;
//   - instructions, by callgrind, a count it does not move:
//       valgrind --tool=callgrind --toggle-collect='solve_cost_solve*' physik_solve_cost ...
//     (and 'solve_cost_bare_steps*'); instructions per step = the count over the steps printed.
//     callgrind_annotate --inclusive=yes on a run without --toggle-collect splits a solve step by
//     function (take_implicit_step inside the solve is its bare part).
// Last, solve_cost_dls solves each target with damped least squares from the rest pose, as
// ik_comparison's dls row: solve_over_dls is the solve mode's time against DLS's, and
// bare_over_dls the time of the bare steps alone (as many as the solves took) against it, a lower
// bound on what the solve mode's steps cost whatever its bookkeeping.
// Prints one JSON object: rig, targets, steps (total, and per target), converged targets, the
// largest final residual over the reach, a hash of every final pose (so two builds can be seen to
// solve alike), each loop's CPU seconds, microseconds per step and the ratios.
// Exit status: 0 success, 2 bad input (the option and the reason on stderr).
#include <time.h>

#include <algorithm>
#include <cinttypes>
#include <cstdio>
#include <exception>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "bench/tool_main.h"
#include "experiments/common.h"
#include "experiments/ik_cases.h"
#include "physik/engine/engine.h"
#include "physik/engine/implicit_advance.h"
#include "physik/engine/measures.h"
#include "physik/ik/ik_solver.h"
#include "physik/model/errors.h"
#include "physik/posing/posing_session.h"

namespace {

using physik::experiments::RigCase;

double thread_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// a target's solve, as ik_comparison's physik row sets it up (ik_comparison.cpp engine_solver)
void start_solve(const RigCase& rc, physik::PosingSession& session, const physik::Vec3& target) {
  session.set_pose(physik::rest_pose(rc.rig));
  session.set_target(0, target, false);
  session.set_target(1, rc.rig.bone_rest_head_world[0], false);
}

struct SolveOutcome {
  std::vector<int> steps;       // (targets) each solve's steps
  int converged = 0;            // targets converged
  double worst_residual = 0.0;  // rig units, the largest final residual
  std::uint64_t pose_hash = 0;  // of every final pose, in order
};

}  // namespace

// The counted functions: kept out of line and out of any namespace, so that their names are the
// patterns callgrind's --toggle-collect matches; nothing but a solve or the bare steps in them
__attribute__((noinline)) physik::SolveResult solve_cost_solve(const RigCase& rc,
                                                               physik::PosingSession& session,
                                                               const physik::Vec3& target,
                                                               const physik::SolveRule& rule) {
  start_solve(rc, session, target);
  return session.solve(rule);
}

__attribute__((noinline)) void solve_cost_bare_steps(const physik::Scene& scene,
                                                     physik::SimState& state, int steps) {
  for (int k = 0; k < steps; ++k) {
    physik::take_implicit_step(scene, state, scene.params.dt, nullptr);
  }
}

// damped least squares on the same target from the rest pose, as ik_comparison's dls row
__attribute__((noinline)) physik::IkReport solve_cost_dls(const RigCase& rc,
                                                          const physik::Vec3& target) {
  physik::Pose pose = physik::rest_pose(rc.rig);
  return physik::solve_ik(physik::IkMethod::kDampedLeastSquares, rc.rig, {{rc.bone, 1.0, target}},
                          pose);
}

namespace {

int run(const std::string& models_dir, const std::string& rig_name, int n_targets,
        const std::string& linearisation) {
  std::vector<RigCase> rigs = physik::experiments::make_ik_rigs(models_dir, false);
  const RigCase* rc = nullptr;
  for (const RigCase& r : rigs) {
    if (r.name == rig_name) rc = &r;
  }
  const std::vector<physik::Vec3> targets =
      physik::experiments::make_ik_targets(*rc, n_targets, 0, 0).reach;
  physik::Scene scene = physik::experiments::effector_scene("solve_cost", rc->rig, rc->bone, true);
  const std::vector<std::string>& names = physik::choice_names(physik::ImplicitLinearisation{});
  scene.params.implicit_linearisation = static_cast<physik::ImplicitLinearisation>(
      std::find(names.begin(), names.end(), linearisation) - names.begin());
  physik::PosingSession session(scene);
  physik::SolveRule rule = physik::solve_mode_rule();
  rule.tolerance = 1e-4 * rc->reach;
  rule.max_steps = 2000;
  SolveOutcome o;
  double solve_s = 0.0, bare_s = 0.0, dls_s = 0.0, ke = 0.0;
  int dls_converged = 0;
  physik::SimState bare;
  for (const physik::Vec3& t : targets) {
    const double t0 = thread_seconds();
    const physik::SolveResult r = solve_cost_solve(*rc, session, t, rule);
    solve_s += thread_seconds() - t0;
    o.steps.push_back(r.steps);
    o.converged += r.converged;
    o.worst_residual = std::max(o.worst_residual, r.residual);
    o.pose_hash = o.pose_hash * 1000003u ^ physik::state_hash(session.frames());
    // as many bare steps from where the solve ended (the rig near rest at its targets)
    bare = session.state();
    const double t1 = thread_seconds();
    solve_cost_bare_steps(scene, bare, r.steps);
    bare_s += thread_seconds() - t1;
    ke += physik::kinetic_energy(scene.rig, bare);
    const double t2 = thread_seconds();
    const physik::IkReport dls = solve_cost_dls(*rc, t);
    dls_s += thread_seconds() - t2;
    dls_converged += dls.converged;
  }
  long total = 0;
  std::string per;
  for (int s : o.steps) {
    total += s;
    per += (per.empty() ? "" : ", ") + std::to_string(s);
  }
  std::printf(
      "{\"rig\": \"%s\", \"targets\": %d, \"steps\": %ld, \"steps_per_target\": [%s], "
      "\"converged\": %d, \"worst_residual_over_reach\": %.9g, \"pose_hash\": \"%016" PRIx64
      "\", \"solve_cpu_s\": %.6f, \"bare_cpu_s\": %.6f, \"solve_us_per_step\": %.4g, "
      "\"bare_us_per_step\": %.4g, \"solve_over_bare\": %.4g, \"bare_final_ke_sum\": %.6g, "
      "\"dls_converged\": %d, \"dls_cpu_s\": %.6f, \"solve_over_dls\": %.4g, "
      "\"bare_over_dls\": %.4g}\n",
      rc->name.c_str(), n_targets, total, per.c_str(), o.converged, o.worst_residual / rc->reach,
      o.pose_hash, solve_s, bare_s, 1e6 * solve_s / total, 1e6 * bare_s / total, solve_s / bare_s,
      ke, dls_converged, dls_s, solve_s / dls_s, bare_s / dls_s);
  return physik::kExitOk;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "physik_solve_cost: ik_comparison's solve mode on one rig's first targets, then as many bare "
      "implicit steps; CPU time per step of each (bench/solve_cost.cpp; count them with "
      "callgrind's --toggle-collect='solve_cost_solve*' or 'solve_cost_bare_steps*')."};
  std::string models = "models", rig = "chain50";
  int targets = 20;
  std::string linearisation = "gauss-newton";
  app.add_option("--models", models, "the models folder (pinhead's rig)");
  app.add_option("--rig", rig, "chain3, chain10, chain50 or pinhead")
      ->check(CLI::IsMember({"chain3", "chain10", "chain50", "pinhead"}));
  app.add_option("--targets", targets, "the first N reachable targets")->check(CLI::Range(1, 1000));
  app.add_option("--linearisation", linearisation,
                 "the step's implicit_linearisation (gauss-newton, the solve mode's, or full)")
      ->check(CLI::IsMember(physik::choice_names(physik::ImplicitLinearisation{})));
  app.footer("Exit status: 0 success, 1 an unexpected failure, 2 bad input.");
  return physik::bench::tool_main("physik_solve_cost", app, argc, argv,
                                  [&] { return run(models, rig, targets, linearisation); });
}
