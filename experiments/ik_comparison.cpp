// Study: the classic IK solvers of the guide (seed 001), the rotation method (seed 002),
// Orocos KDL (its LMA and its joint-limited Newton-Raphson, kdl/kdl_solve.h) as an outside
// reference, and the PhysIK engine, on chains of 3, 10 and 50 bones and on pinhead's left hand.
//
// Targets (fixed seed): reachable ones, uniform in the ball of 0.95 of the reach around the root
// for the free chains, and pinhead's hand tip in random legal poses; unreachable ones at 1.1..2
// times the reach in a uniform direction. Every solve starts from the rest pose with the root's
// head anchored. Per solve: residual (rig units), success (residual < 1e-3 of the reach),
// iterations (PhysIK: the equilibrium solve's recursions, or the time-stepping modes' steps; the
// hybrids: steps + DLS iterations), wall time, the largest joint-limit violation (ik_cases.h
// kMeasuredJoints), secondary motion (sum over bones of the rotation angle relative to the start;
// on pinhead also the mean displacement of bones off the root-to-hand path), and continuity: the
// same start solved for the target and for the target moved by 1% of the reach; jump = largest
// bone-tail displacement between the two solutions over the target move (1 = the pose follows the
// target rigidly). PhysIK: the default preset with its default control spring on the effector and a
// second control point pinning the root's head (PhysIK's root is free), in a PosingSession per rig
// (physik/posing; the time is the solve alone), stopped like the classic solvers: at the residual
// tolerance (1e-4 of the reach), or when no goal improves short of it (not converged), at most
// 2000 steps or iterations; the explicit rows and KDL's NR_JL on fewer targets. Rows: physik, the
// solve mode (the equilibrium solve: physik solve --solver physik); physik-full, the same with
// implicit_linearisation full; physik-steps, the time-stepping solve mode (scheme implicit, the
// potential's torsion torque, the step from the physical dt lengthening as the motion settles:
// --solver physik-steps), and physik-steps+dls with a DLS finish once the residual stops
// improving for 10 steps (the paper's suggested hybrid); physik-explicit, the paper's engine at
// its dt (no 50-chain: the 5 n^2 joint-pass cap makes a 50-bone step ~3 ms), and with a DLS
// finish. Secondary motion on pinhead also as the rotation of the bones off the root-to-hand path.
// Against the time-stepping solve's rest pose, target by target: how far the equilibrium solve's
// pose and DLS's lie from it (rest_poses.csv).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <sstream>

#include "experiments/common.h"
#include "experiments/ik_cases.h"
#include "experiments/table.h"
#include "kdl/kdl_solve.h"
#include "physik/engine/engine.h"
#include "physik/ik/ik_solver.h"
#include "physik/model/joint_angles.h"
#include "physik/posing/posing_session.h"

namespace physik::experiments {

namespace {

struct Outcome {
  std::vector<Vec3> tails_world;        // (nbone) final tails
  Vec3 root_head_world = Vec3::Zero();  // the root's final head
  std::vector<Quat> local;              // (nbone) final local rotations (rest-relative)
  double residual = 0.0;                // rig units
  int iterations = 0;
  double time_s = 0.0;
  bool converged = false;
  double limit_violation_deg = 0.0;
};

using Solver = std::function<Outcome(const RigCase&, const Vec3& target)>;

Outcome classic(IkMethod m, const RigCase& rc, const Vec3& target) {
  Pose pose = rest_pose(rc.rig);
  const IkReport rep = solve_ik(m, rc.rig, {{rc.bone, 1.0, target}}, pose);
  const BoneFrames f = forward_kinematics(rc.rig, pose);
  return {f.tail_world,
          f.head_world[0],
          pose.bone_local_rotation,
          rep.residual,
          rep.iterations,
          rep.time_s,
          rep.converged,
          rad2deg(max_limit_violation(rc.rig, kMeasuredJoints, pose))};
}

// The engine as an IK solver (physik/posing/posing_session.h), as a tool embeds it: one session
// per rig, built once; each target is solved from the rest pose at rest (the effector's target
// moved as engine_solver says), the root's head pinned by a second control point (PhysIK's root
// is free). The time is the solve alone.
struct EngineRow {
  bool solve_mode = false;  // the solve mode's engine settings (physik, physik-steps), else the
                            // scene's engine at its dt (physik-explicit)
  SolveMethod method = SolveMethod::kSteps;  // physik: the equilibrium solve
  SolveFinish finish = SolveFinish::kNone;   // the paper's hybrid: a classic finish after a stall
  std::optional<ImplicitLinearisation> linearisation;  // the solve mode's, unless given here
};

Solver engine_solver(EngineRow row) {
  auto sessions = std::make_shared<std::map<std::string, std::unique_ptr<PosingSession>>>();
  return [row, sessions](const RigCase& rc, const Vec3& target) {
    std::unique_ptr<PosingSession>& session = (*sessions)[rc.name];
    if (!session) {
      Scene scene = effector_scene("ik_comparison", rc.rig, rc.bone, row.solve_mode);
      if (row.linearisation) scene.params.implicit_linearisation = *row.linearisation;
      session = std::make_unique<PosingSession>(scene);
    }
    SolveRule rule = row.method == SolveMethod::kEquilibrium ? solve_mode_rule()
                     : row.solve_mode                        ? steps_mode_rule()
                                                             : SolveRule{};
    rule.method = row.method;
    rule.tolerance = 1e-4 * rc.reach;
    rule.max_steps = 2000;
    if (row.finish != SolveFinish::kNone) {
      rule.finish = row.finish;
      rule.stall_steps = 10;  // the hybrid switches once the residual stops improving
    }
    session->set_pose(rest_pose(rc.rig));
    // The explicit rows move the target along the scene's interpolation from the effector's rest
    // point (set_pose restarts the pull there), as a scene's initial jump: the paper interpolates
    // to keep the Gauss-Seidel solve from diverging (Sec. 3.4-3.5). The solve mode's implicit
    // step is stable under the jump, so its target jumps at once. Measured both ways (100
    // continuity pairs): with the interpolation the solve mode takes 23, 33, 314 and 22 median
    // steps on chain3, chain10, chain50 and pinhead (jump: 17, 27, 307, 16), p95 jump ratio
    // 1.58, 7.82, 1.45, 1.93 (jump: 1.68, 5.33, 1.39, 1.44)
    session->set_target(0, target, !row.solve_mode);
    session->set_target(1, rc.rig.bone_rest_head_world[0], false);
    const auto t0 = std::chrono::steady_clock::now();
    const SolveResult r = session->solve(rule);
    Outcome o;
    o.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    o.tails_world = session->frames().tail_world;
    o.root_head_world = session->frames().head_world[0];
    o.local = session->pose().bone_local_rotation;
    const ControlPoint& cp = session->scene().control_points[0];
    o.residual = (point_on_bone(session->frames(), cp.bone, cp.alpha) - target).norm();
    o.iterations = r.steps + r.finish_iterations;  // the hybrids: physics steps + DLS iterations
    o.converged = r.converged && !r.diverged;
    o.limit_violation_deg = rad2deg(max_limit_violation(rc.rig, kMeasuredJoints, session->pose()));
    return o;
  };
}

// Orocos KDL through `physik solve --solver kdl|kdl-nr` (kdl/kdl_solve.h): the effector's
// control point and the root's head held where it is (the chain's fixed base), as the physik rows'
// scene; its time is KDL's CartToJnt alone, from the rest pose.
Solver kdl_solver(const std::string& name) {
  return [name](const RigCase& rc, const Vec3& target) {
    Scene scene = effector_scene("ik_comparison", rc.rig, rc.bone, false);
    scene.control_points[0].target_world = target;
    SceneSolveOptions o;
    o.solver = name;
    o.tol = 1e-4 * rc.reach;
    const SceneSolveResult r = kdl::solve_scene_kdl(scene, o);
    Outcome out;
    out.time_s = r.time_s;
    out.iterations = r.classic.iterations;
    out.tails_world = r.frames.tail_world;
    out.root_head_world = r.frames.head_world[0];
    out.local = r.pose.bone_local_rotation;
    out.residual = (r.frames.tail_world[rc.bone] - target).norm();
    out.converged = r.classic.converged;
    out.limit_violation_deg = rad2deg(max_limit_violation(rc.rig, kMeasuredJoints, r.pose));
    return out;
  };
}

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(
      std::min<double>(v.size() - 1, std::floor(q * (v.size() - 1) + 0.5)))];
}
double mean(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x;
  return v.empty() ? std::nan("") : s / v.size();
}

struct Stats {
  std::vector<double> reach_success, reach_residual, reach_iters, reach_time, unreach_notconv,
      unreach_excess, violation, rotation, offpath, offpath_rotation, jump;
};

// How many targets per rig (the explicit PhysIK engine and KDL's NR_JL get fewer: they are slow
// on long chains)
struct Budget {
  int n_reach, n_unreach, n_cont, physik_reach, physik_unreach, physik_cont;
};

Budget budget(bool quick) {
  return quick ? Budget{12, 4, 4, 3, 1, 1} : Budget{1000, 200, 100, 100, 20, 20};
}

std::vector<RigCase> make_rigs(const Context& ctx) {
  return make_ik_rigs(ctx.models_dir, ctx.quick);
}

std::vector<std::pair<std::string, Solver>> make_solvers() {
  std::vector<std::pair<std::string, Solver>> solvers;
  for (IkMethod m : {IkMethod::kFabrik, IkMethod::kCcd, IkMethod::kJacobianTranspose,
                     IkMethod::kDampedLeastSquares, IkMethod::kMassSpring, IkMethod::kRotation}) {
    solvers.push_back(
        {to_string(m), [m](const RigCase& rc, const Vec3& t) { return classic(m, rc, t); }});
  }
  solvers.push_back({"kdl", kdl_solver("kdl")});
  solvers.push_back({"kdl-nr", kdl_solver("kdl-nr")});
  const SolveMethod eq = SolveMethod::kEquilibrium, steps = SolveMethod::kSteps;
  solvers.push_back({"physik", engine_solver({true, eq, SolveFinish::kNone, {}})});
  solvers.push_back(
      {"physik-full", engine_solver({true, eq, SolveFinish::kNone, ImplicitLinearisation::kFull})});
  solvers.push_back({"physik-steps", engine_solver({true, steps, SolveFinish::kNone, {}})});
  solvers.push_back({"physik-steps+dls", engine_solver({true, steps, SolveFinish::kDls, {}})});
  solvers.push_back({"physik-explicit", engine_solver({false, steps, SolveFinish::kNone, {}})});
  solvers.push_back({"physik-explicit+dls", engine_solver({false, steps, SolveFinish::kDls, {}})});
  return solvers;
}

Targets make_targets(const RigCase& rc, const Budget& b) {
  return make_ik_targets(rc, b.n_reach, b.n_unreach, b.n_cont);
}

// The three per-solve tables, 9 significant digits.
struct Tables {
  Table solves = solves_table(), cont = continuity_table(), rest = rest_table();

  static Table solves_table() {
    const auto r9 = [](std::string name, std::string unit, std::string doc) {
      return real(std::move(name), std::move(unit), std::move(doc), 9);
    };
    return Table(
        "solves", "solves.csv",
        {text("rig", "chain3, chain10, chain50 or pinhead"), text("solver", "the solver"),
         text("kind", "the target: reachable or unreachable"),
         integer("index", "", "the target's index within its kind"),
         r9("target_x", "rig units", "the target"), r9("target_y", "rig units", "the target"),
         r9("target_z", "rig units", "the target"),
         r9("residual", "rig units", "the effector's distance to the target"),
         r9("residual_over_reach", "", "residual / the chain's reach"),
         flag("success", "residual below 1e-3 of the reach"),
         flag("converged", "the solver's own convergence test"),
         integer("iterations", "", "the solver's iterations (PhysIK: steps)"),
         r9("time_s", "s", "wall time of the solve"),
         r9("limit_violation_deg", "deg", "the largest joint-limit excess"),
         r9("total_rotation_rad", "rad", "the sum of every bone's rotation from rest"),
         r9("offpath_motion", "rig units", "mean tail motion of the bones off the path"),
         r9("offpath_rotation_rad", "rad", "the rotation of the bones off the path")});
  }
  static Table continuity_table() {
    return Table(
        "continuity", "continuity.csv",
        {text("rig", "chain3, chain10, chain50 or pinhead"), text("solver", "the solver"),
         integer("index", "", "the reachable target moved"),
         real("target_move", "rig units", "how far the target moved (1% of the reach)", 9),
         real("max_tail_jump", "rig units", "the largest bone-tail motion between the solves", 9),
         real("jump_ratio", "", "max_tail_jump / target_move", 9)});
  }
  static Table rest_table() {
    return Table(
        "rest_poses", "rest_poses.csv",
        {text("rig", "chain3, chain10, chain50 or pinhead"),
         integer("index", "", "the reachable target"),
         real("physik_distance", "1",
              "the equilibrium solve's pose from the time-stepping solve's rest pose: the largest "
              "bone-end distance over the rig's height",
              9),
         real("dls_distance", "1", "the same for DLS's pose", 9),
         flag("closer", "physik_distance < dls_distance")});
  }
};

// One rig with one solver: what a solve is measured against.
struct SolveCase {
  const RigCase& rc;
  const std::string& solver;
  const std::vector<char>& on_path;  // (nbone) bone on the root-to-effector path
  const BoneFrames& rest;
};

// One solve into solves.csv and the stats: success, total rotation, off-path motion.
void record_solve(const SolveCase& sc, const char* kind, int idx, const Vec3& t, const Outcome& o,
                  Table& solves, Stats& st) {
  const RigCase& rc = sc.rc;
  const bool success = o.residual < 1e-3 * rc.reach;
  double rot = 0.0, off = 0.0, off_rot = 0.0;
  int noff = 0;
  for (int i = 0; i < rc.rig.nbone; ++i) {
    const double angle = o.local[i].angularDistance(Quat::Identity());
    rot += angle;
    if (!sc.on_path[i]) {
      off += (o.tails_world[i] - sc.rest.tail_world[i]).norm();
      off_rot += angle;
      ++noff;
    }
  }
  off = noff ? off / noff : 0.0;
  solves.add({rc.name, sc.solver, kind, idx, t.x(), t.y(), t.z(), o.residual, o.residual / rc.reach,
              success, o.converged, o.iterations, o.time_s, o.limit_violation_deg, rot, off,
              off_rot});
  st.violation.push_back(o.limit_violation_deg);
  if (std::string(kind) == "reachable") {
    st.reach_success.push_back(success);
    st.reach_residual.push_back(o.residual / rc.reach);
    st.reach_iters.push_back(o.iterations);
    st.reach_time.push_back(o.time_s);
    st.rotation.push_back(rot);
    st.offpath.push_back(off);
    st.offpath_rotation.push_back(off_rot);
  } else {
    const Vec3 root = rc.rig.bone_rest_head_world[0];
    st.unreach_notconv.push_back(!o.converged);
    st.unreach_excess.push_back((o.residual - ((t - root).norm() - rc.reach)) / rc.reach);
  }
}

// One table row of the summary: a rig, a solver, its statistics.
nlohmann::json stats_row(const RigCase& rc, const std::string& solver, int nr, int nu,
                         const Stats& st) {
  int jumps_over_10 = 0;
  for (double j : st.jump) jumps_over_10 += j > 10.0;
  return {{"rig", rc.name},
          {"solver", solver},
          {"reachable", nr},
          {"unreachable", nu},
          {"success_rate", mean(st.reach_success)},
          {"median_residual_over_reach", percentile(st.reach_residual, 0.5)},
          {"median_iterations", percentile(st.reach_iters, 0.5)},
          {"p95_iterations", percentile(st.reach_iters, 0.95)},
          {"mean_time_ms", 1e3 * mean(st.reach_time)},
          {"median_time_ms", 1e3 * percentile(st.reach_time, 0.5)},
          {"max_limit_violation_deg", *std::max_element(st.violation.begin(), st.violation.end())},
          {"mean_total_rotation_rad", mean(st.rotation)},
          {"mean_offpath_motion", mean(st.offpath)},
          {"mean_offpath_rotation_rad", mean(st.offpath_rotation)},
          {"unreachable_not_converged", mean(st.unreach_notconv)},
          {"unreachable_excess_over_reach", mean(st.unreach_excess)},
          {"continuity_median_ratio", percentile(st.jump, 0.5)},
          {"continuity_p95_ratio", percentile(st.jump, 0.95)},
          {"continuity_jumps_over_10",
           st.jump.empty() ? 0.0 : static_cast<double>(jumps_over_10) / st.jump.size()}};
}

// Every target of one rig with one solver: reachable, unreachable, then the continuity pairs
// (the same start solved for a reachable target and for it moved by 1% of the reach).
nlohmann::json run_solver(const Context& ctx, const SolveCase& sc, const Solver& solve,
                          const Targets& targets, const Budget& b, Tables& tables,
                          std::vector<Outcome>& reach_out) {
  // the explicit engine is slow (hundreds of steps a solve), and so is KDL's NR_JL on long chains
  // (an SVD of the 6 x 3n Jacobian per iteration, to its 2000 iterations on every unreachable
  // target: 10 minutes on the 50-bone chain): they get fewer targets; the solve mode gets the
  // classic solvers' counts, so its p95 jump ratio stands on as many pairs as DLS's
  const bool few = sc.solver.rfind("physik-explicit", 0) == 0 || sc.solver == "kdl-nr";
  const int nr = few ? std::min(b.physik_reach, b.n_reach) : b.n_reach;
  const int nu = few ? std::min(b.physik_unreach, b.n_unreach) : b.n_unreach;
  const int nc = few ? std::min(b.physik_cont, b.n_cont) : b.n_cont;
  if (ctx.log)
    *ctx.log << "  " << sc.rc.name << " / " << sc.solver << ": " << nr << " + " << nu
             << " targets\n";
  Stats st;
  reach_out.clear();
  for (int t = 0; t < nr; ++t) {
    reach_out.push_back(solve(sc.rc, targets.reach[t]));
    record_solve(sc, "reachable", t, targets.reach[t], reach_out.back(), tables.solves, st);
  }
  for (int t = 0; t < nu; ++t) {
    record_solve(sc, "unreachable", t, targets.unreach[t], solve(sc.rc, targets.unreach[t]),
                 tables.solves, st);
  }
  for (int t = 0; t < nc; ++t) {
    const Vec3& move = targets.moves[t];
    const Outcome moved = solve(sc.rc, targets.reach[t] + move);
    double jump = 0.0;
    for (int i = 0; i < sc.rc.rig.nbone; ++i) {
      jump = std::max(jump, (moved.tails_world[i] - reach_out[t].tails_world[i]).norm());
    }
    st.jump.push_back(jump / move.norm());
    tables.cont.add({sc.rc.name, sc.solver, t, move.norm(), jump, jump / move.norm()});
  }
  return stats_row(sc.rc, sc.solver, nr, nu, st);
}

// the largest distance between the bone ends (the root's head, every tail) of two outcomes, over
// the rig's height
double pose_distance(const Rig& rig, const Outcome& a, const Outcome& b) {
  double d = (a.root_head_world - b.root_head_world).norm();
  for (int i = 0; i < rig.nbone; ++i) d = std::max(d, (a.tails_world[i] - b.tails_world[i]).norm());
  return d / rig.height();
}

// The equilibrium solve's and DLS's poses against the time-stepping solve's rest pose, target by
// target (the rest_poses table), and the rig's row of the summary's "rest_distance"
nlohmann::json rest_distances(const RigCase& rc,
                              const std::map<std::string, std::vector<Outcome>>& out, Table& rest) {
  const std::vector<Outcome>&eq = out.at("physik"), &steps = out.at("physik-steps"),
        &dls = out.at("dls");
  std::vector<double> de, dd;
  double closer = 0.0;
  for (std::size_t t = 0; t < steps.size() && t < eq.size() && t < dls.size(); ++t) {
    de.push_back(pose_distance(rc.rig, eq[t], steps[t]));
    dd.push_back(pose_distance(rc.rig, dls[t], steps[t]));
    closer += de.back() < dd.back();
    rest.add({rc.name, static_cast<int>(t), de.back(), dd.back(), de.back() < dd.back()});
  }
  return {{"rig", rc.name},
          {"targets", de.size()},
          {"closer_fraction", de.empty() ? 0.0 : closer / de.size()},
          {"physik_median", percentile(de, 0.5)},
          {"physik_p90", percentile(de, 0.9)},
          {"physik_max", percentile(de, 1.0)},
          {"dls_median", percentile(dd, 0.5)},
          {"dls_p90", percentile(dd, 0.9)},
          {"dls_max", percentile(dd, 1.0)}};
}

// The rows of the summary table, one per rig and solver (PhysIK's explicit engine: up to 20
// bones); the per-solve tables filled; `rest` the rest_distances rows.
nlohmann::json run_all(const Context& ctx, const Budget& b, Tables& tables, nlohmann::json& rest) {
  const std::vector<std::pair<std::string, Solver>> solvers = make_solvers();
  nlohmann::json table = nlohmann::json::array();
  rest = nlohmann::json::array();
  for (const RigCase& rc : make_rigs(ctx)) {
    std::map<std::string, std::vector<Outcome>> kept;
    const Targets targets = make_targets(rc, b);
    // path of the effector: bones off it measure secondary motion on trees
    std::vector<char> on_path(rc.rig.nbone, 0);
    for (int bone = rc.bone; bone >= 0; bone = rc.rig.bone_parent[bone]) on_path[bone] = 1;
    const BoneFrames rest_frames = forward_kinematics(rc.rig, rest_pose(rc.rig));
    for (const auto& [sname, solve] : solvers) {
      // the explicit engine's 5 n^2 joint-pass cap makes a 50-bone step ~3 ms
      if (sname.rfind("physik-explicit", 0) == 0 && rc.rig.nbone > 20) continue;
      std::vector<Outcome> outcomes;
      table.push_back(
          run_solver(ctx, {rc, sname, on_path, rest_frames}, solve, targets, b, tables, outcomes));
      if (sname == "physik" || sname == "physik-steps" || sname == "dls") {
        kept[sname] = std::move(outcomes);
      }
    }
    rest.push_back(rest_distances(rc, kept, tables.rest));
  }
  return table;
}

// A value of the table (NaN when the rig/solver pair was not run).
struct TableView {
  const nlohmann::json& table;
  double operator()(const std::string& rig, const std::string& solver, const char* key) const {
    for (const auto& r : table) {
      if (r["rig"] == rig && r["solver"] == solver) return r[key].get<double>();
    }
    return std::nan("");
  }
};

std::string pct(double x) {
  return num(100.0 * x, 4) + "%";
}
// a rate or a time of a row that may not have run (the explicit engine skips the 50-bone chain)
std::string pct_or_not_run(double x) {
  return std::isnan(x) ? "not run" : pct(x);
}
std::string ms_or_not_run(double x) {
  return std::isnan(x) ? "not run" : num(x) + " ms";
}

// claims from the guide (seed 001) about the classic solvers
void add_classic_claims(Report& report, const TableView& val, const std::string& big) {
  std::ostringstream m;
  bool holds = true;
  for (const auto& r : val.table) {
    if (r["solver"].get<std::string>().rfind("physik", 0) == 0) continue;
    m << r["rig"].get<std::string>() << " " << r["solver"].get<std::string>() << " "
      << pct(r["success_rate"].get<double>()) << "; ";
    holds &= r["success_rate"].get<double>() >= 0.99;
  }
  report.claim(
      "Every classic solver reaches reachable targets (residual < 1e-3 of the reach, rest-pose "
      "start, 1000 iterations)",
      m.str(), holds ? "yes" : "no");
  const double jt = val(big, "jt", "median_iterations"), dls = val(big, "dls", "median_iterations");
  const double tj = val(big, "jt", "mean_time_ms"), td = val(big, "dls", "mean_time_ms");
  report.claim("Guide: the Jacobian transpose is a slow 'C tier' solver; DLS regularises it",
               big + ": median iterations JT " + num(jt) + " vs DLS " + num(dls) + ", time " +
                   num(tj) + " vs " + num(td) + " ms, success JT " +
                   pct(val(big, "jt", "success_rate")) + " vs DLS " +
                   pct(val(big, "dls", "success_rate")),
               jt > 3 * dls ? "yes" : "no");
  const double ccd = val(big, "ccd", "mean_total_rotation_rad"),
               dls_rot = val(big, "dls", "mean_total_rotation_rad");
  report.claim(
      "Guide: CCD rolls the chain up (more joint rotation than the Jacobian methods for the same "
      "goals)",
      big + ": mean total rotation CCD " + num(ccd) + " rad vs DLS " + num(dls_rot) + " rad",
      ccd > dls_rot ? "yes" : "no");
  const double chain = val("chain10", "fabrik", "success_rate"),
               pin = val("pinhead", "fabrik", "success_rate");
  report.claim(
      "Guide: FABRIK has issues with rotation constraints (pinhead's locked collar, hinge elbow) "
      "but not on free chains",
      "success chain10 " + pct(chain) + ", pinhead " + pct(pin) + "; median iterations " +
          num(val("chain10", "fabrik", "median_iterations")) + " vs " +
          num(val("pinhead", "fabrik", "median_iterations")),
      pin < chain ? "yes" : (pin == chain ? "no" : "no"));
}

// claims from seed 002 (rotation method), the paper (secondary motion), KDL and PhysIK itself
void add_other_claims(Report& report, const TableView& val, const std::string& big) {
  const double rot = val("pinhead", "rotation", "continuity_p95_ratio"),
               dls = val("pinhead", "dls", "continuity_p95_ratio"),
               jt = val("pinhead", "jt", "continuity_p95_ratio");
  report.claim(
      "Seed 002: the rotation method is immune to the Jacobian methods' instability near singular "
      "configurations (smoother under small target moves)",
      "pinhead p95 jump ratio (tail motion / target motion): rotation " + num(rot) + ", DLS " +
          num(dls) + ", JT " + num(jt) + "; " + big + ": rotation " +
          num(val(big, "rotation", "continuity_p95_ratio")) + ", DLS " +
          num(val(big, "dls", "continuity_p95_ratio")) + " (but the rotation method reaches only " +
          pct(val(big, "rotation", "success_rate")) +
          " there, so it barely moves); "
          "both reach ~100% on pinhead, where the comparison is fair",
      rot < std::min(dls, jt) ? "partly" : "no");
  const double ph = val("pinhead", "physik-explicit", "mean_offpath_motion");
  double best = 0.0;
  for (const char* s : {"fabrik", "ccd", "jt", "dls", "mass-spring", "rotation"}) {
    best = std::max(best, val("pinhead", s, "mean_offpath_motion"));
  }
  report.claim(
      "Paper Fig 9: PhysIK moves the rest of the body (secondary motion) where classic IK moves "
      "only the arm chain",
      "pinhead mean displacement of bones off the head-to-hand path: PhysIK (explicit) " + num(ph) +
          " rig units, largest classic solver " + num(best) +
          " (classic solvers turn the root head bone, which carries the body)",
      ph > best ? "yes" : "no");
  std::ostringstream m;
  for (const std::string& r : {std::string("chain3"), std::string("chain10"), big}) {
    m << r << ": KDL " << pct(val(r, "kdl", "success_rate")) << " in "
      << num(val(r, "kdl", "mean_time_ms")) << " ms, KDL NR_JL "
      << pct(val(r, "kdl-nr", "success_rate")) << " in " << num(val(r, "kdl-nr", "mean_time_ms"))
      << " ms, DLS " << pct(val(r, "dls", "success_rate")) << " in "
      << num(val(r, "dls", "mean_time_ms")) << " ms; ";
  }
  report.claim(
      "Outside reference: our DLS matches Orocos KDL's LMA in success on free chains", m.str(),
      val(big, "dls", "success_rate") >= val(big, "kdl", "success_rate") - 0.01 ? "yes" : "no");
  const double ps = val("pinhead", "physik-explicit", "success_rate");
  report.claim(
      "PhysIK (the paper's explicit engine) meets a reachable target to 1e-3 of the reach (stops "
      "at 1e-4 of the reach or when stalled, 2000-step cap)",
      "success chain3 " + pct(val("chain3", "physik-explicit", "success_rate")) + ", chain10 " +
          pct(val("chain10", "physik-explicit", "success_rate")) + ", pinhead " + pct(ps) +
          "; median steps on pinhead " +
          num(val("pinhead", "physik-explicit", "median_iterations")) + ", " +
          num(val("pinhead", "physik-explicit", "mean_time_ms")) + " ms per solve",
      ps >= 0.99  ? "yes"
      : ps >= 0.5 ? "partly"
                  : "no");
}

// the equilibrium solve with the pose terms in its step (physik-full) against the Gauss-Newton
// step (physik): every reachable target met, and which is faster
void add_full_step_claim(Report& report, const TableView& val,
                         const std::vector<std::string>& rigs) {
  std::ostringstream full;
  bool full_all = true;
  int gauss_newton_faster = 0;
  for (const std::string& r : rigs) {
    const double s = val(r, "physik-full", "success_rate");
    gauss_newton_faster +=
        val(r, "physik", "median_time_ms") < val(r, "physik-full", "median_time_ms");
    full << r << " " << pct(s) << " in " << num(val(r, "physik-full", "median_iterations"))
         << " iterations, " << num(val(r, "physik-full", "median_time_ms")) << " ms (physik "
         << num(val(r, "physik", "median_iterations")) << " iterations, "
         << num(val(r, "physik", "median_time_ms")) << " ms); ";
    full_all &= s >= 1.0;
  }
  report
      .claim(
          "The equilibrium solve with implicit_linearisation full (physik-full: the pose terms "
          "in the step) meets every reachable target",
          full.str(), full_all ? "yes" : "no")
      .named("full-step-meets-reachable");
  report
      .claim(
          "The equilibrium solve keeps implicit_linearisation gauss-newton: it solves faster "
          "than full (median ms per solve, same targets) on most rigs",
          std::to_string(gauss_newton_faster) + " of " + std::to_string(rigs.size()) +
              " rigs (the figures above)",
          2 * gauss_newton_faster > static_cast<int>(rigs.size()) ? "yes" : "no")
      .named("solve-mode-keeps-gauss-newton");
}

// the equilibrium solve's secondary motion on pinhead against the time-stepping solve mode's
void add_secondary_motion_claim(Report& report, const TableView& val) {
  const double rot = val("pinhead", "physik", "mean_offpath_rotation_rad"),
               rot_s = val("pinhead", "physik-steps", "mean_offpath_rotation_rad"),
               off = val("pinhead", "physik", "mean_offpath_motion"),
               off_s = val("pinhead", "physik-steps", "mean_offpath_motion");
  report
      .claim(
          "Solve mode: secondary motion (rotation of the bones off the controlled chain) at least "
          "95% of the time-stepping solve mode's",
          "pinhead: rotation off the head-to-hand path " + num(rot) + " rad vs physik-steps " +
              num(rot_s) + " (" + pct(rot / rot_s) + "); their displacement " + num(off) + " vs " +
              num(off_s) + " rig units (" + pct(off / off_s) + "); the paper's explicit " +
              "engine " + num(val("pinhead", "physik-explicit", "mean_offpath_rotation_rad")) +
              " rad",
          rot >= 0.95 * rot_s ? "yes" : "no")
      .named("equilibrium-secondary-motion");
}

// the solve mode (physik: the equilibrium solve) against DLS and the time-stepping solve mode
void add_solve_mode_claims(Report& report, const TableView& val,
                           const std::vector<std::string>& rigs) {
  std::ostringstream succ, speed, iters, jump;
  bool all_succ = true, all_fast = true, all_few = true, all_smooth = true;
  for (const std::string& r : rigs) {
    const double s = val(r, "physik", "success_rate"), t = val(r, "physik", "median_time_ms"),
                 td = val(r, "dls", "median_time_ms"), it = val(r, "physik", "median_iterations"),
                 j = val(r, "physik", "continuity_p95_ratio"),
                 jd = val(r, "dls", "continuity_p95_ratio");
    succ << r << " " << pct(s) << " (physik-steps " << pct(val(r, "physik-steps", "success_rate"))
         << ", explicit " << pct_or_not_run(val(r, "physik-explicit", "success_rate")) << "); ";
    speed << r << " " << num(t) << " ms vs DLS " << num(td) << " ms (" << num(t / td)
          << "x; physik-steps " << num(val(r, "physik-steps", "median_time_ms")) << " ms); ";
    iters << r << " " << num(it) << " (physik-steps "
          << num(val(r, "physik-steps", "median_iterations")) << " steps, DLS "
          << num(val(r, "dls", "median_iterations")) << "); ";
    jump << r << " " << num(j) << " vs DLS " << num(jd) << "; ";
    all_succ &= s >= 1.0;
    all_fast &= t <= td;
    all_few &= it <= 12.0;
    all_smooth &= j <= jd;
  }
  report
      .claim(
          "Solve mode (physik: the equilibrium solve, a trust region of implicit steps at rest): "
          "every reachable target met",
          succ.str(), all_succ ? "yes" : "no")
      .named("equilibrium-meets-reachable");
  report
      .claim(
          "Solve mode: median ms per solve at most DLS's, in the same run (this table's "
          "wall times; bench/solve_cost.cpp compares them target by target in CPU time)",
          speed.str(), all_fast ? "yes" : "no")
      .named("equilibrium-time");
  report
      .claim("Solve mode: median iterations per solve (one O(n) recursion each) at most 12",
             iters.str(), all_few ? "yes" : "no")
      .named("equilibrium-iterations");
  report.claim("Solve mode: p95 jump ratio (tail motion / target motion) at most DLS's", jump.str(),
               all_smooth ? "yes" : "no");
  add_secondary_motion_claim(report, val);
  std::ostringstream hy;
  for (const std::string& r : rigs) {
    hy << r << ": physik-steps+dls " << pct(val(r, "physik-steps+dls", "success_rate")) << " in "
       << num(val(r, "physik-steps+dls", "median_time_ms")) << " ms, physik-explicit+dls "
       << pct_or_not_run(val(r, "physik-explicit+dls", "success_rate")) << " in "
       << ms_or_not_run(val(r, "physik-explicit+dls", "median_time_ms")) << ", physik "
       << num(val(r, "physik", "median_time_ms")) << " ms; ";
  }
  add_full_step_claim(report, val, rigs);
  report.claim(
      "The paper's hybrid (physics for the transient, DLS once the residual stops improving for 10 "
      "steps) against the solve mode",
      hy.str() + "(the explicit engine skips the 50-bone chain)", "n/a");
}

// the equilibrium solve's pose nearer the time-stepping solve's rest pose than DLS's is
void add_rest_pose_claim(Report& report, const nlohmann::json& rest) {
  std::ostringstream m;
  double closer = 0.0, n = 0.0;
  for (const auto& r : rest) {
    const double k = r["targets"].get<double>();
    closer += r["closer_fraction"].get<double>() * k;
    n += k;
    m << r["rig"].get<std::string>() << ": closer on " << pct(r["closer_fraction"].get<double>())
      << "; physik median " << num(r["physik_median"].get<double>()) << ", p90 "
      << num(r["physik_p90"].get<double>()) << ", max " << num(r["physik_max"].get<double>())
      << " of the height; DLS median " << num(r["dls_median"].get<double>()) << ", p90 "
      << num(r["dls_p90"].get<double>()) << "; ";
  }
  const double fraction = n > 0.0 ? closer / n : 0.0;
  report
      .claim(
          "The equilibrium solve's pose is closer to the time-stepping solve's rest pose than "
          "DLS's pose (bone ends, over the height) on at least 90% of the reachable targets",
          "all rigs " + pct(fraction) + "; " + m.str() + "(rest_poses.csv has every target)",
          fraction >= 0.9 ? "yes" : "no")
      .named("equilibrium-near-the-rest-pose");
}

void add_notes(Report& report, const Budget& b, const nlohmann::json& table) {
  report.note(
      "Targets: " + std::to_string(b.n_reach) + " reachable + " + std::to_string(b.n_unreach) +
      " unreachable per rig (seed 20240607), the solve modes (physik, physik-steps, their "
      "variants) as many; the "
      "explicit "
      "engine (physik-explicit rows) gets " +
      std::to_string(b.physik_reach) + " + " + std::to_string(b.physik_unreach) +
      " and no 50-bone chain (its 5 n^2 joint-pass cap "
      "makes a 50-bone step ~3 ms); continuity on the first " +
      std::to_string(b.n_cont) + " reachable targets (explicit " + std::to_string(b.physik_cont) +
      "), target moved by 1% of the reach. "
      "The explicit rows move the effector's target along the scene's interpolation from its rest "
      "point (the paper's guard against the Gauss-Seidel solve diverging); the solve mode jumps it "
      "at once.");
  report.note(
      "PhysIK's root is free, so it gets a second control point pinning the root's head; "
      "classic solvers anchor the root's head and turn the root bone (pinhead's root is the head "
      "bone). "
      "The pin is a spring too, so toward unreachable targets PhysIK's root is dragged along "
      "(negative "
      "excess: the hand gets closer than |t| - reach), and its joint limits are torsion springs "
      "(soft), hence the limit violation; classic solvers clamp their rotation vectors, which on a "
      "hinge locked away from zero or a two-axis joint is not the same as staying on the joint "
      "(every solver is measured in the exact and implicit schemes' joints, kMeasuredJoints).");
  report.note(
      "PhysIK stops like the classic solvers: when every control point is within 1e-4 of the "
      "reach (scene convergence.stop_at_residual_tol), or when its residual stalls short of it "
      "(no 1% improvement in 50 steps; then it has not converged).");
  report.note(
      "Columns: success = residual < 1e-3 reach; median res/reach = median residual on reachable "
      "targets over the reach; iters = median iterations (PhysIK: steps); "
      "ms = mean wall time per solve; viol = largest limit violation (deg); rot = mean total joint "
      "rotation (rad); off = mean displacement of off-path bones; unreach nc = fraction of "
      "unreachable "
      "targets reported not converged; excess = mean residual beyond |t| - reach (over reach); "
      "jump p95 = 95th percentile of tail motion / target motion.");
  for (const auto& r : table) {
    std::ostringstream s;
    s << r["rig"].get<std::string>() << " | " << r["solver"].get<std::string>() << " | success "
      << pct(r["success_rate"].get<double>()) << " | median res/reach "
      << num(r["median_residual_over_reach"].get<double>(), 2) << " | iters "
      << num(r["median_iterations"].get<double>()) << " | ms "
      << num(r["mean_time_ms"].get<double>()) << " | viol "
      << num(r["max_limit_violation_deg"].get<double>()) << " | rot "
      << num(r["mean_total_rotation_rad"].get<double>()) << " | off "
      << num(r["mean_offpath_motion"].get<double>()) << " | unreach nc "
      << pct(r["unreachable_not_converged"].get<double>()) << " | excess "
      << num(r["unreachable_excess_over_reach"].get<double>()) << " | jump p95 "
      << num(r["continuity_p95_ratio"].get<double>());
    report.note(s.str());
  }
}

void run(const Context& ctx) {
  const Budget b = budget(ctx.quick);
  Tables tables;
  nlohmann::json rest;
  const nlohmann::json table = run_all(ctx, b, tables, rest);
  tables.solves.write_csv(ctx.out_dir);
  tables.cont.write_csv(ctx.out_dir);
  tables.rest.write_csv(ctx.out_dir);
  const std::string big = ctx.quick ? "chain10" : "chain50";
  Report report("Classic IK solvers, the rotation method, KDL and PhysIK");
  report.section("baselines");
  add_classic_claims(report, TableView{table}, big);
  add_other_claims(report, TableView{table}, big);
  report.section("PhysIK as an IK solver");
  std::vector<std::string> rigs = {"chain3", "chain10"};
  if (!ctx.quick) rigs.push_back("chain50");
  rigs.push_back("pinhead");
  add_solve_mode_claims(report, TableView{table}, rigs);
  add_rest_pose_claim(report, rest);
  add_notes(report, b, table);
  report.figures({"ik_success.png", "ik_time.png", "ik_continuity.png"});
  write_summary(ctx,
                {{"experiment", "ik_comparison"},
                 {"quick", ctx.quick},
                 {"table", table},
                 {"rest_distance", rest}},
                report, {&tables.solves, &tables.cont, &tables.rest});
}

const Registration registered{
    240,
    {"ik_comparison", "study: IK solvers",
     "classic IK solvers, the rotation method, KDL and PhysIK on chains and pinhead", run}};

}  // namespace

}  // namespace physik::experiments
