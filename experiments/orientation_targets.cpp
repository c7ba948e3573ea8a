// Study: a hand with a position target and an orientation target, on pinhead and on MuJoCo's
// humanoid (humanoid/humanoid.xml converted as `physik rig from-mjcf`, reference/mjcf_import.h,
// the outside_rigs path): PhysIK's solve modes and its explicit engine against damped least
// squares with orientation rows (physik/ik/jacobian.cpp) and Orocos KDL's LMA and NR_JL with
// orientation rows, on the same targets.
//
// Targets (seed 49, reachable by construction): the hand's tail and frame (world<-bone) in a
// random legal pose (common.h random_legal_pose) of the hand and its three parents, every other
// bone at rest. Every solve starts from the rest pose.
// Solvers:
//   physik           solve_scene with --solver physik (scene_solve.h), the equilibrium solve:
//                    effector_scene's control point on the hand's tail and one holding the root's
//                    head (PhysIK's root is free), and an orientation target on the hand (its
//                    default k = control_k L^2, L the hand's length, scene.h TurnSpring)
//   physik-steps     the same scene, --solver physik-steps (the time-stepping solve mode), at
//                    most kSteps steps
//   physik-explicit  the same scene in the paper's scheme (preset original, Gauss-Seidel) as a
//                    plain run at its dt (--solver physik-explicit)
//   dls              solve_ik with one goal: position and orientation (orientation rows weighted
//                    by the chain's reach, ik_solver.h), the rig's limits respected
//   kdl, kdl-nr      Orocos KDL through --solver kdl|kdl-nr (kdl/kdl_solve.h) on the root-to-hand
//                    chain: per bone a fixed segment (its head in its parent, its rest
//                    orientation), then revolute joints about x, y, z, and the hand's tail; LMA
//                    with weights [1, 1, 1, w, w, w], w = tol / tol_angle (the reach), no joint
//                    limits; NR_JL with the rig's limits on its joints
// The engine's and KDL's tolerances are the success rule's over ten: 1e-4 of the reach, 1e-4 rad.
// Measured per solve: the position error of the hand's tail (rig units), the orientation error
// |log(q_target q^-1)| of its frame (rad), wall time, the largest joint-limit violation (every
// solver's pose in the rig's joints as the exact and implicit schemes have them,
// physik/model/joint_angles.h), and the secondary motion: the mean displacement (rig units) of the
// tails of the bones off the root-to-hand chain from the start. Success: position error <= kPosTol
// of the reach and orientation error <= kOriTol rad.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <random>

#include "experiments/common.h"
#include "experiments/outside_rigs.h"
#include "experiments/table.h"
#include "kdl/kdl_solve.h"
#include "physik/ik/ik_solver.h"
#include "physik/io/rig_io.h"
#include "physik/model/joint_angles.h"
#include "physik/posing/scene_solve.h"
#include "reference/mjcf_import.h"

namespace physik::experiments {

namespace {

// Success thresholds: the position tolerance is ik_comparison's success (1e-3 of the reach); the
// orientation's is the turn that moves the chain's far end by that much (1e-3 rad): the same
// length scale as DLS's orientation rows.
constexpr double kPosTol = 1e-3;           // 1, of the reach
constexpr double kOriTol = 1e-3;           // rad
constexpr double kVisible = M_PI / 180.0;  // rad, 1 deg: an orientation gap one can see
constexpr int kSteps = 2000;               // the engine's step cap per solve
constexpr unsigned kSeed = 49;
constexpr int kPerturbed = 4;  // the hand and its three parents

struct RigCase {
  std::string name;
  Rig rig;
  int hand = -1;
  std::vector<int> chain;  // root .. hand
  double reach = 0.0;      // rig units
};

struct Target {
  Vec3 position = Vec3::Zero();         // rig units
  Quat orientation = Quat::Identity();  // world<-bone
};

struct Result {
  Pose pose;
  double time_s = 0.0;
  bool solver_converged = false;
  std::string outcome;  // converged, stalled, out_of_steps (out of iterations), diverged
};

std::vector<Target> make_targets(const RigCase& rc, int count) {
  std::mt19937 rng(kSeed);
  std::vector<Target> out;
  for (int t = 0; t < count; ++t) {
    const Pose random = random_legal_pose(rc.rig, rng);
    Pose p = rest_pose(rc.rig);
    int b = rc.hand;
    for (int k = 0; k < kPerturbed && b > 0; ++k, b = rc.rig.bone_parent[b]) {
      p.bone_local_rotation[b] = random.bone_local_rotation[b];
    }
    const BoneFrames f = forward_kinematics(rc.rig, p);
    out.push_back({f.tail_world[rc.hand], f.orient_world[rc.hand]});
  }
  return out;
}

Scene target_scene(const RigCase& rc, const Target& t, bool solve_mode) {
  Scene sc = effector_scene("orientation_targets", rc.rig, rc.hand, solve_mode);
  sc.control_points[0].target_world = t.position;
  OrientationTarget o;
  o.bone = rc.hand;
  o.target_world = t.orientation;
  sc.orientation_targets = {o};
  sc.steps = kSteps;
  return sc;
}

// the engine (physik, physik-steps, physik-explicit) or KDL (kdl, kdl-nr) through solve_scene,
// the position and angle tolerances the success rule's over ten (1e-4 of the reach, 1e-4 rad)
Result by_scene_solve(const RigCase& rc, const Target& t, const std::string& solver) {
  SceneSolveOptions o;
  o.solver = solver;
  o.tol = 0.1 * kPosTol * rc.reach;
  o.tol_angle = 0.1 * kOriTol;
  const bool kdl = solver.rfind("kdl", 0) == 0;
  const Scene scene = target_scene(rc, t, solver != "physik-explicit");
  if (kdl) {
    const SceneSolveResult r = kdl::solve_scene_kdl(scene, o);
    return {r.pose, r.time_s, r.classic.converged,
            r.classic.converged ? "converged"
            : r.classic.stalled ? "stalled"
                                : "out_of_steps"};
  }
  const SceneSolveResult r = solve_scene(scene, o);
  const std::string outcome = r.diverged          ? "diverged"
                              : r.solve.converged ? "converged"
                              : r.solve.stalled   ? "stalled"
                                                  : "out_of_steps";
  return {r.pose, r.time_s, r.solve.converged && !r.diverged, outcome};
}

Result dls(const RigCase& rc, const Target& t) {
  IkGoal g{rc.hand, 1.0, t.position};
  g.has_orientation = true;
  g.orientation_world = t.orientation;
  Pose pose = rest_pose(rc.rig);
  const IkReport rep = solve_ik(IkMethod::kDampedLeastSquares, rc.rig, {g}, pose);
  return {pose, rep.time_s, rep.converged,
          rep.converged ? "converged"
          : rep.stalled ? "stalled"
                        : "out_of_steps"};
}

// The hand: the first bone whose name holds "hand" and "left" (pinhead's hand.L has "hand" and
// ".L"), else the first with "hand"; -1 when none.
int find_hand(const Rig& rig) {
  int any = -1;
  for (int i = 0; i < rig.nbone; ++i) {
    const std::string& n = rig.bone_name[i];
    if (n.find("hand") == std::string::npos) continue;
    if (n.find("left") != std::string::npos || n.find(".L") != std::string::npos) return i;
    if (any < 0) any = i;
  }
  return any;
}

RigCase rig_case(const std::string& name, Rig rig) {
  RigCase rc;
  rc.name = name;
  rc.rig = std::move(rig);
  rc.hand = find_hand(rc.rig);
  if (rc.hand < 0) throw std::runtime_error(name + ": no bone named hand");
  for (int b = rc.hand; b >= 0; b = rc.rig.bone_parent[b]) {
    if (rc.rig.bone_weld[b] >= 0 && rc.rig.bone_weld[b] != rc.rig.bone_parent[b]) {
      throw std::runtime_error(
          name + ": bone '" + rc.rig.bone_name[b] +
          "' on the hand's chain is welded to a sibling (KDL's chain has none)");
    }
    rc.chain.push_back(b);
  }
  std::reverse(rc.chain.begin(), rc.chain.end());
  rc.reach = chain_reach(rc.rig, {{rc.hand, 1.0, Vec3::Zero()}});
  return rc;
}

Table solves_table() {
  return Table(
      "solves", "solves.csv",
      {text("rig", "pinhead or humanoid (MuJoCo's humanoid/humanoid.xml)"),
       text("hand", "the hand bone"),
       text("solver", "physik, physik-steps, physik-explicit, dls, kdl, kdl-nr"),
       integer("target", "", "the target's index (seed 49)"),
       flag("success", "position error <= 1e-3 of the reach and orientation error <= 1e-3 rad"),
       flag("solver_converged", "the solver's own verdict"),
       text("outcome",
            "converged, stalled, out_of_steps (or iterations), diverged; KDL: its "
            "CartToJnt status"),
       real("position_error", "rig units", "the hand's tail from its target"),
       real("position_error_reach", "1", "position_error / reach"),
       real("orientation_error", "rad", "|log(q_target q^-1)| of the hand's frame"),
       real("secondary_motion", "rig units",
            "mean displacement of the tails of the bones off the root-to-hand chain"),
       real("limit_violation_deg", "deg", "the largest joint-limit violation"),
       real("time_ms", "ms", "wall time of the solve"), real("reach", "rig units", "the chain's")});
}

struct Tally {
  int n = 0, success = 0;
  std::vector<double> ori, pos, second;
};

double median(std::vector<double> v) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

std::string verdict_every(const Tally& t) {
  if (t.n == 0) return "n/a (no solves)";
  if (t.success == t.n) return "yes";
  return 2 * t.success >= t.n ? "partly" : "no";
}

std::string count(const Tally& t) {
  return std::to_string(t.success) + " of " + std::to_string(t.n);
}

// Every target of every rig by every solver: a row of `solves` each, and the tallies per solver
// (key: the solver, and solver@rig).
void measure(const std::vector<RigCase>& rigs, int ntarget, Table& solves,
             std::map<std::string, Tally>& tally) {
  const std::vector<std::string> solvers = {"physik", "physik-steps", "physik-explicit",
                                            "dls",    "kdl",          "kdl-nr"};
  for (const RigCase& rc : rigs) {
    const BoneFrames start = forward_kinematics(rc.rig, rest_pose(rc.rig));
    std::vector<char> on_chain(rc.rig.nbone, 0);
    for (int b : rc.chain) on_chain[b] = 1;
    const std::vector<Target> targets = make_targets(rc, ntarget);
    for (std::size_t t = 0; t < targets.size(); ++t) {
      for (const std::string& s : solvers) {
        const Result r = s == "dls" ? dls(rc, targets[t]) : by_scene_solve(rc, targets[t], s);
        const BoneFrames f = forward_kinematics(rc.rig, r.pose);
        const double pos = (f.tail_world[rc.hand] - targets[t].position).norm();
        const double ori =
            rotation_vector(targets[t].orientation * f.orient_world[rc.hand].conjugate()).norm();
        double second = 0.0;
        int off = 0;
        for (int b = 0; b < rc.rig.nbone; ++b) {
          if (on_chain[b]) continue;
          second += (f.tail_world[b] - start.tail_world[b]).norm();
          ++off;
        }
        second = off > 0 ? second / off : 0.0;
        const bool ok =
            std::isfinite(pos) && std::isfinite(ori) && pos <= kPosTol * rc.reach && ori <= kOriTol;
        solves.add({rc.name, rc.rig.bone_name[rc.hand], s, static_cast<int>(t), ok,
                    r.solver_converged, r.outcome, pos, pos / rc.reach, ori, second,
                    rad2deg(max_limit_violation(rc.rig, LockedAxes::kRemoved, r.pose)),
                    1000.0 * r.time_s, rc.reach});
        for (const std::string& key : {s, s + "@" + rc.name}) {
          Tally& ty = tally[key];
          ++ty.n;
          ty.success += ok ? 1 : 0;
          ty.ori.push_back(ori);
          ty.pos.push_back(pos / rc.reach);
          ty.second.push_back(second / rc.reach);
        }
      }
    }
  }
}

// whether each solver reaches both the position and the orientation on every target
void add_reach_claims(Report& report, const std::vector<RigCase>& rigs,
                      std::map<std::string, Tally>& tally) {
  auto per_rig = [&](const std::string& s) {
    std::string m;
    for (const RigCase& rc : rigs) {
      const Tally& ty = tally[s + "@" + rc.name];
      m += (m.empty() ? "" : "; ") + rc.name + " " + count(ty) + ", median orientation error " +
           num(median(ty.ori)) + " rad, position " + num(median(ty.pos)) + " of the reach";
    }
    return m;
  };
  report
      .claim(
          "DLS with orientation rows reaches the hand's position (1e-3 of the reach) and "
          "orientation (1e-3 rad) on every target",
          per_rig("dls"), verdict_every(tally["dls"]))
      .named("dls-reaches");
  report
      .claim("KDL's LMA with orientation weights reaches both on every target", per_rig("kdl"),
             verdict_every(tally["kdl"]))
      .named("kdl-reaches");
  report
      .claim(
          "KDL's joint-limited Newton-Raphson with orientation rows reaches both on every "
          "target (partly: on at least half)",
          per_rig("kdl-nr"), verdict_every(tally["kdl-nr"]))
      .named("kdl-nr-reaches");
  report
      .claim("PhysIK's solve mode (the equilibrium solve) reaches both on every target",
             per_rig("physik"), verdict_every(tally["physik"]))
      .named("physik-solve-reaches");
  report
      .claim(
          "PhysIK's time-stepping solve mode reaches both on every target (partly: on at "
          "least half)",
          per_rig("physik-steps"), verdict_every(tally["physik-steps"]))
      .named("physik-steps-reaches");
  report
      .claim("PhysIK's explicit engine reaches both on every target (partly: on at least half)",
             per_rig("physik-explicit"), verdict_every(tally["physik-explicit"]))
      .named("physik-explicit-reaches");
}

void add_claims(Report& report, const std::vector<RigCase>& rigs,
                std::map<std::string, Tally>& tally) {
  add_reach_claims(report, rigs, tally);
  {
    const double gap = median(tally["physik"].ori) - median(tally["dls"].ori);
    report
        .claim("PhysIK's solve mode's median orientation error is within 1 deg of DLS's",
               "physik " + num(median(tally["physik"].ori)) + " rad, dls " +
                   num(median(tally["dls"].ori)) + " rad (difference " + num(gap) + " rad)",
               !std::isfinite(gap)         ? "no (not finite)"
               : std::abs(gap) <= kVisible ? "yes"
                                           : "no")
        .named("orientation-gap");
  }
  {
    // DLS and KDL turn the root (it is on their chain), so the whole body turns with it: their
    // off-chain motion is that turn; PhysIK's is the body following the pull
    const double ph = median(tally["physik"].second);
    const double dl = median(tally["dls"].second);
    const double kd = median(tally["kdl"].second);
    report
        .claim(
            "PhysIK's solve mode moves the bones off the hand's chain (secondary motion, "
            "median above 1e-3 of the reach)",
            "mean off-chain tail displacement / reach, median: physik " + num(ph) +
                ", physik-steps " + num(median(tally["physik-steps"].second)) +
                ", physik-explicit " + num(median(tally["physik-explicit"].second)) + "; dls " +
                num(dl) + " and kdl " + num(kd) +
                " (they turn the root, on their chain, and the body with it)",
            ph > kPosTol ? "yes" : "no")
        .named("secondary-motion");
  }
}

void run(const Context& ctx) {
  const int ntarget = ctx.quick ? 3 : 12;
  std::vector<RigCase> rigs;
  rigs.push_back(rig_case("pinhead", load_rig(ctx.models_dir + "/rigs/pinhead.json")));
  const std::string humanoid = std::string(outside_rigs::kSamplesDir) + "/humanoid/humanoid.xml";
  std::string skipped;
  if (std::filesystem::exists(humanoid)) {
    rigs.push_back(rig_case("humanoid", load_mjcf(humanoid).rig()));
  } else {
    skipped = humanoid + " is missing (Debian's libmujoco-samples): the humanoid is left out";
  }
  Table solves = solves_table();
  std::map<std::string, Tally> tally;
  measure(rigs, ntarget, solves, tally);
  solves.write_csv(ctx.out_dir);

  Report report(
      "Orientation targets: a hand's position and orientation, PhysIK against DLS "
      "and KDL");
  add_claims(report, rigs, tally);
  solves.add_to_report(report, "Every solve (errors: rig units and rad)",
                       {{"rig", "rig"},
                        {"solver", "solver"},
                        {"target", "target"},
                        {"success", "success"},
                        {"position error / reach", "position_error_reach"},
                        {"orientation error (rad)", "orientation_error"},
                        {"secondary motion", "secondary_motion"},
                        {"limit violation (deg)", "limit_violation_deg"},
                        {"time (ms)", "time_ms"}});
  report.note(
      "Targets: the hand's tail and frame in a random legal pose of the hand and its three "
      "parents (seed 49), reachable by construction; every solve from the rest pose. PhysIK: "
      "effector_scene (the hand's tail, the root's head held) with an orientation target on the "
      "hand at its default k (control_k L^2), through solve_scene: physik (the equilibrium "
      "solve), physik-steps (the time-stepping solve mode), physik-explicit the paper's scheme "
      "(preset original) at its dt, at most 2000 steps; tolerances 1e-4 of the reach and 1e-4 "
      "rad. DLS: one goal with position and orientation rows weighted by the reach. KDL "
      "(kdl/kdl_solve.h, `--solver kdl|kdl-nr`): on the root-to-hand chain, LMA (weights [1, 1, "
      "1, w, w, w], w = tol / tol_angle = the reach; no joint limits) and NR_JL (joint-limited "
      "Newton-Raphson). Success: position error <= 1e-3 of the reach and orientation error <= "
      "1e-3 rad.");
  if (!skipped.empty()) report.note(skipped);
  report.figures({"orientation_targets.png"});
  nlohmann::json rig_rows = nlohmann::json::array();
  for (const RigCase& rc : rigs) {
    rig_rows.push_back({{"rig", rc.name},
                        {"hand", rc.rig.bone_name[rc.hand]},
                        {"bones", rc.rig.nbone},
                        {"chain_bones", rc.chain.size()},
                        {"reach", rc.reach}});
  }
  write_summary(ctx,
                {{"experiment", "orientation_targets"},
                 {"rigs", rig_rows},
                 {"targets_per_rig", ntarget},
                 {"seed", kSeed}},
                report, {&solves});
}

const Registration registered{
    242,
    {"orientation_targets", "study: orientation targets",
     "a hand's position and orientation target: PhysIK against DLS with orientation rows and KDL",
     run}};

}  // namespace

}  // namespace physik::experiments
