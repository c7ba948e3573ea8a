// physik_solve_cost: the solve mode (`solve --solver physik`: the equilibrium solve,
// physik/engine/equilibrium_solve.h) against damped least squares, side by side in one process,
// target by target, on one rig:
//   chain10, chain50, pinhead   ik_comparison's rigs and reachable targets (experiments/ik_cases.h:
//                               the effector's tail, the root's head held by a second control
//                               point, as ik_comparison's physik row; DLS anchors the root)
//   humanoid                    MuJoCo's humanoid/humanoid.xml (`rig from-mjcf`), its left hand
//   figure75                    the 75-bone figure with fingers (make_figure_rig), its left hand
// On the two figures the hand's target is its tail in a random legal pose of the hand and its
// three parents (every other bone at rest), and both feet are held where they stand (a control
// point on each foot's tail; DLS: the same three goals). Targets are drawn from --seed: the default
// is ik_comparison's; the solve's settings were chosen on seed 1 (docs/ik.md "The equilibrium
// solve"), so the default measures them on held-out targets.
//
// Per target, each solve runs --repeat times from the rest pose and the fastest thread CPU time
// counts (other processes on a shared machine only slow a run down): solve_cost_equilibrium (a
// PosingSession, built before the clock, as a tool holds it; solve_mode_rule with the tolerance
// 1e-4 of the reach), solve_cost_dls (solve_ik from the rest pose, its tolerance the same), and
// with --steps the time-stepping solve mode (steps_mode_rule, at most 2000 steps). Then, from the
// pose the equilibrium solve ended at, solve_cost_bare_trials takes as many bare trials as it
// took iterations (solve_implicit and integrate_joint_space at rest: the one O(n) recursion and
// the joint-space update, nothing else): what the iterations cost whatever the trust region's
// bookkeeping, a lower bound on the solve's time at its iteration count.
// Counted with callgrind, a ratio no busy machine moves:
//   valgrind --tool=callgrind --toggle-collect='solve_cost_equilibrium*' physik_solve_cost ...
// (and 'solve_cost_dls*', 'solve_cost_bare_trials*'); each count over the --repeat x targets
// calls is a solve's instructions.
// Prints one JSON object: rig, targets, iterations (median, per target), converged counts, the
// largest final goal residual over the reach, a hash of the final poses (so two builds can be
// seen to solve alike), the median time of each solver, the median over targets of the ratio
// equilibrium / DLS, the ratio of the medians, and the bare trials' median over DLS.
// Exit status: 0 success, 2 bad input (the option and the reason on stderr).
#include <time.h>

#include <algorithm>
#include <cinttypes>
#include <cstdio>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "bench/tool_main.h"
#include "experiments/common.h"
#include "experiments/ik_cases.h"
#include "experiments/outside_rigs.h"
#include "physik/engine/engine.h"
#include "physik/engine/equilibrium_solve.h"
#include "physik/engine/forces.h"
#include "physik/engine/implicit_step.h"
#include "physik/engine/integrate_joint_space.h"
#include "physik/engine/measures.h"
#include "physik/ik/ik_solver.h"
#include "physik/model/errors.h"
#include "physik/posing/posing_session.h"
#include "reference/mjcf_import.h"

namespace {

using physik::Vec3;

double thread_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// One rig with its goals: the effector's control point (index 0) moved to each target, the others
// held where they are at rest. DLS gets the same goals, the root anchored.
struct Case {
  std::string name;
  physik::Scene scene;  // the solve mode's settings, the control points at rest
  int effector = -1;    // bone, its tail the effector
  double reach = 0.0;   // rig units, of the effector's chain
  std::vector<Vec3> targets;
  bool root_pin = false;  // control point 1 holds the root's head (the chains and pinhead)
};

// the figures' targets: the hand's tail in a random legal pose of the hand and its three parents
std::vector<Vec3> hand_targets(const physik::Rig& rig, int hand, int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::vector<Vec3> out;
  for (int t = 0; t < n; ++t) {
    const physik::Pose random = physik::experiments::random_legal_pose(rig, rng);
    physik::Pose p = physik::rest_pose(rig);
    int b = hand;
    for (int k = 0; k < 4 && b > 0; ++k, b = rig.bone_parent[b]) {
      p.bone_local_rotation[b] = random.bone_local_rotation[b];
    }
    out.push_back(physik::forward_kinematics(rig, p).tail_world[hand]);
  }
  return out;
}

int find_bone_containing(const physik::Rig& rig, const std::vector<std::string>& parts) {
  for (int i = 0; i < rig.nbone; ++i) {
    bool all = true;
    for (const std::string& p : parts) all = all && rig.bone_name[i].find(p) != std::string::npos;
    if (all) return i;
  }
  throw physik::InputError("--rig: no bone named with " + parts[0]);
}

Case figure_case(const std::string& name, const physik::Rig& rig, const std::string& hand,
                 const std::vector<std::string>& feet, int n, unsigned seed) {
  Case c;
  c.name = name;
  c.effector = find_bone_containing(rig, {hand});
  c.scene = physik::experiments::effector_scene("solve_cost", rig, c.effector, true);
  c.scene.control_points.pop_back();  // no root pin: the feet hold the figure
  const physik::BoneFrames rest = physik::forward_kinematics(rig, physik::rest_pose(rig));
  for (const std::string& f : feet) {
    physik::ControlPoint cp;
    cp.bone = find_bone_containing(rig, {f});
    cp.alpha = 1.0;
    cp.target_world = rest.tail_world[cp.bone];
    c.scene.control_points.push_back(cp);
  }
  c.reach = rig.chain_length(c.effector, 1.0);
  c.targets = hand_targets(rig, c.effector, n, seed);
  return c;
}

Case make_case(const std::string& models, const std::string& rig, int n, unsigned seed) {
  if (rig == "humanoid") {
    const std::string xml =
        std::string(physik::experiments::outside_rigs::kSamplesDir) + "/humanoid/humanoid.xml";
    if (!std::filesystem::exists(xml)) {
      throw physik::InputError("--rig humanoid: " + xml + " is missing (libmujoco-samples)");
    }
    return figure_case(rig, physik::load_mjcf(xml).rig(), "left_hand", {"left_foot", "right_foot"},
                       n, seed);
  }
  if (rig == "figure75") {
    return figure_case(rig, physik::experiments::make_figure_rig(), "hand.L", {"foot.L", "foot.R"},
                       n, seed);
  }
  for (const physik::experiments::RigCase& rc : physik::experiments::make_ik_rigs(models, false)) {
    if (rc.name != rig) continue;
    Case c;
    c.name = rig;
    c.effector = rc.bone;
    c.scene = physik::experiments::effector_scene("solve_cost", rc.rig, rc.bone, true);
    c.reach = rc.reach;
    c.targets = physik::experiments::make_ik_targets(rc, n, 0, 0).reach;
    if (seed != 20240607u) {  // another draw of the same kind: the rig case's rule, another seed
      std::mt19937 rng(seed);
      c.targets.clear();
      for (int k = 0; k < n; ++k) {
        if (rc.chain) {
          const double r =
              0.95 * rc.reach * std::cbrt(std::uniform_real_distribution<double>(0, 1)(rng));
          c.targets.push_back(rc.rig.bone_rest_head_world[0] +
                              r * physik::experiments::random_direction(rng));
        } else {
          c.targets.push_back(physik::forward_kinematics(
                                  rc.rig, physik::experiments::random_legal_pose(rc.rig, rng))
                                  .tail_world[rc.bone]);
        }
      }
    }
    c.root_pin = true;
    return c;
  }
  throw physik::InputError("--rig: unknown rig '" + rig + "'");
}

void start(const Case& c, physik::PosingSession& s, const Vec3& target) {
  s.set_pose(physik::rest_pose(c.scene.rig));
  s.set_target(0, target, false);
  for (int k = 1; k < s.num_control_points(); ++k) {
    s.set_target(k, c.scene.control_points[k].target_world, false);
  }
}

std::vector<physik::IkGoal> dls_goals(const Case& c, const Vec3& target) {
  std::vector<physik::IkGoal> goals{{c.effector, 1.0, target}};
  const auto& cps = c.scene.control_points;
  for (std::size_t k = 1; k < cps.size() && !c.root_pin; ++k) {
    goals.push_back({cps[k].bone, cps[k].alpha, cps[k].target_world});
  }
  return goals;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

}  // namespace

// The counted functions: kept out of line and out of any namespace, so that their names are the
// patterns callgrind's --toggle-collect matches; nothing but a solve or the bare trials in them
__attribute__((noinline)) physik::SolveResult solve_cost_equilibrium(
    const Case& c, physik::PosingSession& session, const Vec3& target,
    const physik::SolveRule& rule) {
  start(c, session, target);
  return session.solve(rule);
}

__attribute__((noinline)) physik::IkReport solve_cost_dls(const Case& c, const Vec3& target) {
  physik::Pose pose = physik::rest_pose(c.scene.rig);
  physik::IkOptions o;
  o.tolerance = 1e-4 * c.reach;
  return physik::solve_ik(physik::IkMethod::kDampedLeastSquares, c.scene.rig, dls_goals(c, target),
                          pose, o);
}

__attribute__((noinline)) void solve_cost_bare_trials(const physik::Scene& scene,
                                                      physik::SimState& state, int trials) {
  for (int k = 0; k < trials; ++k) {
    physik::apply_forces(scene, state);
    physik::solve_implicit(scene, state, 1.0);
    physik::integrate_joint_space(scene.rig, 1.0, state);
  }
}

namespace {

struct Options {
  std::string models = "models", rig = "chain50";
  int targets = 20, repeat = 5;
  unsigned seed = 20240607u;
  bool steps = false;
};

// the fastest of `repeat` runs of f, thread CPU seconds
template <typename F>
double fastest(int repeat, F&& f) {
  double best = 1e300;
  for (int r = 0; r < repeat; ++r) {
    const double t0 = thread_seconds();
    f();
    best = std::min(best, thread_seconds() - t0);
  }
  return best;
}

int run(const Options& o) {
  const Case c = make_case(o.models, o.rig, o.targets, o.seed);
  physik::PosingSession session(c.scene), steps(c.scene);
  physik::SolveRule rule = physik::solve_mode_rule();
  rule.tolerance = 1e-4 * c.reach;
  physik::SolveRule steps_rule = physik::steps_mode_rule();
  steps_rule.tolerance = rule.tolerance;
  std::vector<double> iters, t_eq, t_dls, t_steps, t_bare, ratio, step_counts;
  int converged = 0, dls_converged = 0, steps_converged = 0;
  double worst = 0.0;
  std::uint64_t hash = 0;
  std::string per;
  physik::SimState bare;
  for (const Vec3& t : c.targets) {
    physik::SolveResult r;
    t_eq.push_back(fastest(o.repeat, [&] { r = solve_cost_equilibrium(c, session, t, rule); }));
    iters.push_back(r.steps);
    per += (per.empty() ? "" : ", ") + std::to_string(r.steps);
    converged += r.converged;
    worst = std::max(worst, r.residual / c.reach);
    hash = hash * 1000003u ^ physik::state_hash(session.frames());
    physik::IkReport d;
    t_dls.push_back(fastest(o.repeat, [&] { d = solve_cost_dls(c, t); }));
    dls_converged += d.converged;
    ratio.push_back(t_eq.back() / t_dls.back());
    bare = session.state();
    physik::Scene scene = session.scene();
    scene.params.scheme = physik::Scheme::kImplicit;
    scene.params.torsion_torque = physik::TorsionTorque::kGradient;
    t_bare.push_back(fastest(1, [&] { solve_cost_bare_trials(scene, bare, r.steps); }));
    if (o.steps) {
      physik::SolveResult s;
      t_steps.push_back(fastest(1, [&] {
        start(c, steps, t);
        s = steps.solve(steps_rule);
      }));
      step_counts.push_back(s.steps);
      steps_converged += s.converged;
    }
  }
  std::printf(
      "{\"rig\": \"%s\", \"bones\": %d, \"targets\": %d, \"seed\": %u, \"repeat\": %d, "
      "\"iterations_median\": %g, \"iterations\": [%s], \"converged\": %d, "
      "\"dls_converged\": %d, \"worst_residual_over_reach\": %.3g, \"pose_hash\": \"%016" PRIx64
      "\", \"equilibrium_ms_median\": %.4g, \"dls_ms_median\": %.4g, "
      "\"equilibrium_over_dls_median\": %.3g, \"ratio_of_medians\": %.3g, "
      "\"bare_trials_ms_median\": %.4g, \"bare_over_dls\": %.3g",
      c.name.c_str(), c.scene.rig.nbone, o.targets, o.seed, o.repeat, median(iters), per.c_str(),
      converged, dls_converged, worst, hash, 1e3 * median(t_eq), 1e3 * median(t_dls), median(ratio),
      median(t_eq) / median(t_dls), 1e3 * median(t_bare), median(t_bare) / median(t_dls));
  if (o.steps) {
    std::printf(", \"steps_median\": %g, \"steps_converged\": %d, \"steps_ms_median\": %.4g",
                median(step_counts), steps_converged, 1e3 * median(t_steps));
  }
  std::printf("}\n");
  return physik::kExitOk;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "physik_solve_cost: the solve mode (the equilibrium solve) against DLS on one rig's "
      "targets, side by side, the fastest of --repeat runs per target (bench/solve_cost.cpp; count "
      "them with callgrind's --toggle-collect='solve_cost_equilibrium*' or 'solve_cost_dls*')."};
  Options o;
  app.add_option("--models", o.models, "the models folder (pinhead's rig)");
  app.add_option("--rig", o.rig, "chain10, chain50, pinhead, humanoid or figure75")
      ->check(CLI::IsMember({"chain3", "chain10", "chain50", "pinhead", "humanoid", "figure75"}));
  app.add_option("--targets", o.targets, "the first N reachable targets")
      ->check(CLI::Range(1, 1000));
  app.add_option("--repeat", o.repeat, "runs per target and solver; the fastest counts")
      ->check(CLI::Range(1, 100));
  app.add_option("--seed", o.seed,
                 "the targets' seed (default ik_comparison's: held out from the settings' choice)");
  app.add_flag("--steps", o.steps, "also the time-stepping solve mode (physik-steps), once each");
  app.footer("Exit status: 0 success, 1 an unexpected failure, 2 bad input.");
  return physik::bench::tool_main("physik_solve_cost", app, argc, argv, [&] { return run(o); });
}
