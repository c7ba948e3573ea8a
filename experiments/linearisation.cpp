// Linearisation study (chain50's step count; docs/engine.md "The implicit scheme"): the solve
// mode's rule on the ik_comparison scenes (the effector's target jumped to a random reachable
// point, the root's head pinned), with the shipped O(n) implicit step, a dense Newton step of
// backward Euler (linearisation.h, which gives the equations and the variants), and the O(n)
// step with the pose terms (implicit_linearisation full) and its term selections.
//   runs.csv   rig, target, variant: converged, steps, bare steps taken, final residual
// Rigs: the 10- and 50-bone chains and pinhead's left hand; targets from one fixed seed, as
// ik_comparison draws them (uniform in the ball of 0.95 of the reach; pinhead's hand tip in
// random legal poses). Tolerance 1e-4 of the reach, 2000 steps at most. The dense step is O(n^3)
// per step and is not timed: the table counts steps.
#include <algorithm>
#include <cmath>
#include <map>

#include "experiments/common.h"
#include "experiments/linearisation.h"
#include "experiments/table.h"
#include "physik/engine/interpolation.h"
#include "physik/ik/ik_solver.h"
#include "physik/io/rig_io.h"
#include "physik/model/params.h"
#include "physik/model/rig_generators.h"
#include "physik/posing/posing_session.h"

namespace physik::experiments {

namespace {

using linearisation::Variant;

struct StudyRig {
  std::string name;
  Rig rig;
  int bone = 0;  // the effector's bone (its tail is the effector)
  bool chain = true;
};

// ik_comparison's scene, its target jumping (no interpolation)
Scene study_scene(const StudyRig& r) {
  Scene sc = effector_scene("linearisation", r.rig, r.bone, true);
  sc.params.interpolation = Interpolation::kNone;
  return sc;
}

std::vector<Vec3> study_targets(const StudyRig& r, double reach, int n) {
  std::mt19937 rng(20240607);
  std::vector<Vec3> out;
  for (int k = 0; k < n; ++k) {
    if (r.chain) {
      const double d = 0.95 * reach * std::cbrt(std::uniform_real_distribution<double>(0, 1)(rng));
      out.push_back(r.rig.bone_rest_head_world[0] + d * random_direction(rng));
    } else {
      out.push_back(forward_kinematics(r.rig, random_legal_pose(r.rig, rng)).tail_world[r.bone]);
    }
  }
  return out;
}

double median(std::vector<double> v) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  const std::size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

struct VariantCount {
  std::vector<double> steps, substeps;
  int converged = 0, diverged = 0, runs = 0;
};

std::vector<StudyRig> study_rigs(const Context& ctx) {
  std::vector<StudyRig> rigs;
  rigs.push_back({"chain10", make_chain_rig(10), 9, true});
  if (!ctx.quick) {
    rigs.push_back({"chain50", make_chain_rig(50), 49, true});
    StudyRig pinhead{"pinhead", load_rig(ctx.models_dir + "/rigs/pinhead.json"), 0, false};
    pinhead.bone = pinhead.rig.find_bone("hand.L");
    rigs.push_back(pinhead);
  }
  return rigs;
}

// the pose split's dense variants on the rigs up to 20 bones: on chain50 pose_forces takes
// thousands of bare steps of O(n^3) each
std::vector<Variant> variants_of(const Context& ctx, const StudyRig& r) {
  if (ctx.quick) return std::vector<Variant>{Variant::kShipped, Variant::kNewton, Variant::kFull};
  std::vector<Variant> v = {Variant::kShipped, Variant::kShippedDcdv, Variant::kNewton,
                            Variant::kNewtonAtRest, Variant::kNewtonNoGyro};
  if (r.rig.nbone <= 20) {
    for (Variant x : {Variant::kPoseForces, Variant::kPoseInertia, Variant::kShippedDense})
      v.push_back(x);
  }
  // the O(n) steps with the pose terms (implicit_linearisation full), on every rig
  for (Variant x : {Variant::kFull, Variant::kFullForces, Variant::kFullInertia, Variant::kFullNoZ,
                    Variant::kFullSketch}) {
    v.push_back(x);
  }
  return v;
}

constexpr int kMaxSteps = 2000;

using Cells = std::map<std::string, std::map<std::string, VariantCount>>;  // rig -> variant

// runs.csv: every rig's every target with every variant; the cells gather its counts
Table measure(const Context& ctx, const std::vector<StudyRig>& rigs, int n_targets, Cells& cells) {
  const auto r9 = [](std::string name, std::string unit, std::string doc) {
    return real(std::move(name), std::move(unit), std::move(doc), 9);
  };
  Table csv(
      "runs", "runs.csv",
      {text("rig", "chain10, chain50 or pinhead"), integer("target", "", "the target's index"),
       text("variant", "the step (linearisation.h)"),
       flag("converged", "every control point within the tolerance"),
       flag("diverged", "the state went non-finite"),
       integer("steps", "steps", "steps of the rule"),
       integer("substeps", "steps", "bare steps, the guard's rejected ones included"),
       r9("residual", "rig units", "the largest residual at the end")});
  for (const StudyRig& r : rigs) {
    const Scene scene = study_scene(r);
    const double reach = chain_reach(r.rig, {{r.bone, 1.0, Vec3::Zero()}});
    const std::vector<Vec3> targets = study_targets(r, reach, n_targets);
    for (Variant v : variants_of(ctx, r)) {
      VariantCount& cell = cells[r.name][linearisation::variant_name(v)];
      for (std::size_t t = 0; t < targets.size(); ++t) {
        SimState s;
        init_state(scene, s);
        start_target_jump(scene, s, 0, targets[t]);
        const linearisation::SolveCount c =
            linearisation::solve(scene, s, 1e-4 * reach, kMaxSteps, v);
        csv.add({r.name, t, linearisation::variant_name(v), c.converged, c.diverged, c.steps,
                 c.substeps, c.residual});
        cell.steps.push_back(c.steps);
        cell.substeps.push_back(c.substeps);
        cell.converged += c.converged;
        cell.diverged += c.diverged;
        cell.runs += 1;
      }
      if (ctx.log) {
        *ctx.log << "  " << r.name << " " << linearisation::variant_name(v) << ": median "
                 << num(median(cell.steps)) << " steps, " << num(median(cell.substeps))
                 << " bare steps, " << cell.converged << "/" << cell.runs << " converged\n"
                 << std::flush;
      }
    }
  }
  return csv;
}

// the summary's rows and the report's table: per rig and variant, medians and counts
void tabulate(const Context& ctx, const std::vector<StudyRig>& rigs, Cells& cells,
              nlohmann::json& rows, nlohmann::json& table) {
  for (const StudyRig& r : rigs) {
    for (Variant v : variants_of(ctx, r)) {
      const VariantCount& c = cells[r.name][linearisation::variant_name(v)];
      rows.push_back({{"rig", r.name},
                      {"variant", linearisation::variant_name(v)},
                      {"median_steps", median(c.steps)},
                      {"median_substeps", median(c.substeps)},
                      {"converged", c.converged},
                      {"diverged", c.diverged},
                      {"runs", c.runs}});
      table.push_back({r.name, linearisation::variant_name(v), num(median(c.steps)),
                       num(median(c.substeps)),
                       std::to_string(c.converged) + "/" + std::to_string(c.runs)});
    }
  }
}

void add_notes(Report& report) {
  report
      .note(
          "shipped = the O(n) implicit step (Gauss-Newton springs, the velocity products "
          "explicit); "
          "shipped_dcdv = the same with the velocity products' derivative dC/dv added; newton = a "
          "dense step of backward Euler linearising every term, from central differences of "
          "the exact accelerations; newton_at_rest = the same linearised at the pose with v = 0 "
          "(the "
          "velocity products' derivatives dropped); newton_no_gyro = newton without the derivative "
          "of "
          "w x I w; pose_forces, pose_inertia = newton_at_rest's two pose terms apart (the forces' "
          "and the "
          "inertia's; chain10 and pinhead only); shipped_dense = the shipped step rebuilt densely, "
          "a check. "
          "full = the O(n) implicit step with implicit_linearisation full, newton_at_rest's system "
          "in the "
          "articulated-body recursion (physik/engine/implicit_pose_terms.h); full_forces, "
          "full_inertia = "
          "its forces' and its inertia's terms alone (pose_forces' and pose_inertia's systems); "
          "full_no_z = "
          "full without the turn of the joint accelerations below a moving joint; full_sketch = "
          "the "
          "design sketch (the transmitted wrench, torsion torques in it, turning the joint axes; "
          "no other "
          "term). Same rule and guard for all (experiments/linearisation.h).")
      .note(
          "The dense step costs O(n^3) per step and is a measuring instrument, not a solver: the "
          "table counts steps, not time. A run that does not converge counts its 2000 steps.");
}

// the claims on the O(n) step with the pose terms (implicit_linearisation full)
template <class Steps, class Pair>
void add_full_step_claims(Report& report, const std::vector<StudyRig>& rigs, const Steps& steps,
                          const Pair& pair) {
  bool same = true, fewer = true;
  std::string same_text, fewer_text;
  for (const StudyRig& r : rigs) {
    const double a = steps(r.name, Variant::kFull), b = steps(r.name, Variant::kNewtonAtRest);
    same = same && std::abs(a - b) <= 0.1 * b;
    fewer = fewer && a < steps(r.name, Variant::kShipped);
    same_text +=
        (same_text.empty() ? "" : "; ") + pair(r.name, Variant::kFull, Variant::kNewtonAtRest);
    fewer_text +=
        (fewer_text.empty() ? "" : "; ") + pair(r.name, Variant::kFull, Variant::kShipped);
  }
  report
      .claim(
          "The O(n) step with the pose terms is the dense newton_at_rest step (the same system to "
          "round-off, checked by a test): full within 10% of newton_at_rest's median steps on "
          "every "
          "rig",
          same_text, same ? "yes" : "no")
      .named("full-equals-dense");
  report
      .claim(
          "The pose terms in O(n) cut the solve's steps: full needs fewer median steps than the "
          "shipped (Gauss-Newton) step on every rig",
          fewer_text, fewer ? "yes" : "no")
      .named("full-fewer-steps");
  bool each = true;
  std::string each_text;
  for (Variant v :
       {Variant::kFullForces, Variant::kFullInertia, Variant::kFullNoZ, Variant::kFullSketch}) {
    each = each && steps("chain50", v) > steps("chain50", Variant::kFull);
    each_text += (each_text.empty() ? "" : "; ") + pair("chain50", v, Variant::kFull);
  }
  report
      .claim(
          "Every term counts on chain50: the forces' terms alone, the inertia's alone, full "
          "without "
          "the joint accelerations' turn, and the design sketch each need more median steps than "
          "full",
          each_text, each ? "yes" : "no")
      .named("every-term-counts");
}

// the gyroscopic and the pinhead claims, then the full step's
template <class Steps, class Pair>
void add_more_claims(Report& report, const std::vector<StudyRig>& rigs, const Steps& steps,
                     const Pair& pair) {
  bool gyro_flat = true;
  std::string gyro_text;
  for (const StudyRig& r : rigs) {
    const double a = steps(r.name, Variant::kNewtonNoGyro), b = steps(r.name, Variant::kNewton);
    gyro_flat = gyro_flat && std::abs(a - b) <= 0.1 * b;
    gyro_text += std::string(gyro_text.empty() ? "" : "; ") +
                 pair(r.name, Variant::kNewtonNoGyro, Variant::kNewton);
  }
  // how far from a sphere the bones are: w x I w vanishes for equal principal moments
  std::string moments;
  for (const StudyRig& r : rigs) {
    double ratio = 1.0;
    for (const Vec3& I : r.rig.bone_inertia_local)
      ratio = std::min(ratio, I.minCoeff() / I.maxCoeff());
    moments += std::string(moments.empty() ? "" : ", ") + r.name + " " + num(ratio);
  }
  report.claim(
      "The gyroscopic torque's derivative does not matter on these rigs: newton_no_gyro within 10% "
      "of newton's median steps on every rig",
      gyro_text + "; smallest principal moment over the largest, worst bone: " + moments,
      gyro_flat ? "yes" : "no");
  // the rule's ramp: doubling from dt, the step reaches 100 s at this step
  const int ramp =
      1 + static_cast<int>(std::ceil(std::log2(100.0 / study_scene(rigs.front()).params.dt)));
  report.claim(
      "On pinhead the linearisation does not set the step count (newton at least 0.8x the shipped "
      "step's median steps): the rule's ramp from dt does",
      pair("pinhead", Variant::kNewton, Variant::kShipped) +
          "; doubling from dt, the step reaches "
          "100 s at step " +
          std::to_string(ramp),
      steps("pinhead", Variant::kNewton) >= 0.8 * steps("pinhead", Variant::kShipped) ? "yes"
                                                                                      : "no");
  add_full_step_claims(report, rigs, steps, pair);
}

// the claims of a full run (a quick run has neither chain50 nor pinhead)
void add_claims(Report& report, const std::vector<StudyRig>& rigs, Cells& cells) {
  const auto steps = [&](const std::string& rig, Variant v) {
    return median(cells[rig][linearisation::variant_name(v)].steps);
  };
  const auto pair = [&](const std::string& rig, Variant a, Variant b) {
    return rig + ": " + linearisation::variant_name(a) + " " + num(steps(rig, a)) + " vs " +
           linearisation::variant_name(b) + " " + num(steps(rig, b)) + " median steps";
  };
  report.claim(
      "Hypothesis: linearising the velocity products (dC/dv, as MuJoCo's implicit "
      "integrator does) cures chain50's whip: the shipped step with dC/dv added needs at most half "
      "the shipped step's steps",
      pair("chain50", Variant::kShippedDcdv, Variant::kShipped),
      steps("chain50", Variant::kShippedDcdv) <= 0.5 * steps("chain50", Variant::kShipped) ? "yes"
                                                                                           : "no");
  report.claim(
      "A full linearisation does: a dense Newton step of backward Euler needs at most half the "
      "shipped step's steps on chain50",
      pair("chain50", Variant::kNewton, Variant::kShipped),
      steps("chain50", Variant::kNewton) <= 0.5 * steps("chain50", Variant::kShipped) ? "yes"
                                                                                      : "no");
  report.claim(
      "The pose terms (the forces' full dependence on the pose, and M(q)) carry most of it: "
      "newton_at_rest, without dC/dv, needs under 0.8x the shipped step's steps on chain50",
      pair("chain50", Variant::kNewtonAtRest, Variant::kShipped),
      steps("chain50", Variant::kNewtonAtRest) < 0.8 * steps("chain50", Variant::kShipped) ? "yes"
                                                                                           : "no");
  report.claim(
      "With the pose terms in, dC/dv matters too: newton_at_rest needs over 1.25x newton's steps "
      "on chain50",
      pair("chain50", Variant::kNewtonAtRest, Variant::kNewton),
      steps("chain50", Variant::kNewtonAtRest) > 1.25 * steps("chain50", Variant::kNewton) ? "yes"
                                                                                           : "no");
  const auto no_better = [&](const std::string& rig, Variant v) {
    return steps(rig, v) >= steps(rig, Variant::kShipped);
  };
  report.claim(
      "On chain10 neither pose term helps alone: pose_forces (the forces' full tangent, M held) "
      "and "
      "pose_inertia (the inertia's term on the shipped K) each need at least the shipped step's "
      "median steps, where both together (newton_at_rest) need fewer (not run on chain50)",
      pair("chain10", Variant::kPoseForces, Variant::kShipped) + "; " +
          pair("chain10", Variant::kPoseInertia, Variant::kShipped) + "; " +
          pair("chain10", Variant::kNewtonAtRest, Variant::kShipped),
      no_better("chain10", Variant::kPoseForces) && no_better("chain10", Variant::kPoseInertia) &&
              steps("chain10", Variant::kNewtonAtRest) < steps("chain10", Variant::kShipped)
          ? "yes"
          : "no");
  report.claim(
      "The pieces hold together: the shipped step rebuilt densely (shipped_dense, from the "
      "unit-force "
      "responses) takes the shipped step's median steps on chain10 and pinhead",
      pair("chain10", Variant::kShippedDense, Variant::kShipped) + "; " +
          pair("pinhead", Variant::kShippedDense, Variant::kShipped),
      steps("chain10", Variant::kShippedDense) == steps("chain10", Variant::kShipped) &&
              steps("pinhead", Variant::kShippedDense) == steps("pinhead", Variant::kShipped)
          ? "yes"
          : "no");
  add_more_claims(report, rigs, steps, pair);
}

void run(const Context& ctx) {
  const std::vector<StudyRig> rigs = study_rigs(ctx);
  const int n_targets = ctx.quick ? 1 : 6;
  Cells cells;
  const Table runs = measure(ctx, rigs, n_targets, cells);
  runs.write_csv(ctx.out_dir);
  nlohmann::json rows = nlohmann::json::array(), table = nlohmann::json::array();
  tabulate(ctx, rigs, cells, rows, table);
  Report report("Linearisation: what the implicit step leaves out, against a dense Newton step");
  report
      .settings(settings_json(study_scene(rigs.front()), {{"targets_per_rig", n_targets},
                                                          {"tolerance", "1e-4 of the reach"},
                                                          {"max_steps", kMaxSteps}}))
      .table("Median steps and bare steps (the guard's rejected ones included) per solve",
             {"rig", "variant", "steps", "bare steps", "converged"}, table)
      .figures({"linearisation.png"});
  add_notes(report);
  if (!ctx.quick) add_claims(report, rigs, cells);
  write_summary(ctx, {{"experiment", "linearisation"}, {"rows", rows}}, report, {&runs});
}

}  // namespace

const Registration linearisation_registered{
    247,
    {"linearisation", "Sec. 5 future work",
     "the solve mode with the shipped implicit step against dense steps of backward Euler that "
     "linearise more terms (chain10, chain50, pinhead): which terms set the step count",
     run}};

}  // namespace physik::experiments
