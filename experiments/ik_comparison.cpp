// Study (issue 7): the classic IK solvers of the guide (seed 001), the rotation method (seed 002),
// Orocos KDL's ChainIkSolverPos_LMA as an outside reference, and the PhysIK engine, on chains of
// 3, 10 and 50 bones and on pinhead's left hand.
//
// Targets (fixed seed): reachable ones, uniform in the ball of 0.95 of the reach around the root
// for the free chains, and pinhead's hand tip in random legal poses; unreachable ones at 1.1..2
// times the reach in a uniform direction. Every solve starts from the rest pose with the root's
// head anchored. Per solve: residual (rig units), success (residual < 1e-3 of the reach),
// iterations (PhysIK: steps), wall time, the largest joint-limit violation, secondary motion
// (sum over bones of the rotation angle relative to the start; on pinhead also the mean
// displacement of bones off the root-to-hand path), and continuity: the same start solved for
// the target and for the target moved by 1% of the reach; jump = largest bone-tail displacement
// between the two solutions over the target move (1 = the pose follows the target rigidly).
// PhysIK: the default preset with its default control spring on the effector and a second control point pinning the root's head (PhysIK's root is free), stopped
// like the classic solvers: at the residual tolerance (1e-4 of the reach), or when the residual
// stalls short of it (not converged), at most 2000 steps; fewer targets, no 50-chain
// (the 5 n^2 joint-pass cap makes a 50-bone step ~3 ms).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <functional>
#include <iomanip>
#include <map>
#include <random>
#include <sstream>

#include <kdl/chain.hpp>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainiksolverpos_lma.hpp>

#include "experiments/experiment.h"
#include "physik/engine/engine.h"
#include "physik/ik/ik_solver.h"
#include "physik/io/json_fields.h"
#include "physik/io/rig_io.h"
#include "physik/model/rig_generators.h"

namespace physik::experiments {

namespace {

struct RigCase {
  std::string name;
  Rig rig;
  int bone = 0;          // the effector's bone (its tail is the effector)
  double reach = 0.0;    // rig units
  bool chain = false;
};

struct Outcome {
  std::vector<Vec3> tails_world;   // (nbone) final tails
  std::vector<Quat> local;         // (nbone) final local rotations (rest-relative)
  double residual = 0.0;           // rig units
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
  return {f.tail_world, pose.bone_local_rotation, rep.residual, rep.iterations, rep.time_s,
          rep.converged, rad2deg(max_limit_violation(rc.rig, pose))};
}

Outcome physik_engine(const RigCase& rc, const Vec3& target) {
  Scene sc;
  sc.file = "ik_comparison";
  sc.rig = rc.rig;
  sc.params = preset_params(kDefaultPreset);
  ControlPoint effector, pin;
  effector.bone = rc.bone;
  effector.alpha = 1.0;
  effector.target_world = target;
  effector.k = sc.params.control_k;
  effector.spring = sc.params.control_spring;
  pin.bone = 0;
  pin.alpha = 0.0;
  pin.target_world = rc.rig.bone_rest_head_world[0];
  pin.k = sc.params.control_k;
  pin.spring = sc.params.control_spring;
  sc.control_points = {effector, pin};
  sc.initial_pose = rest_pose(rc.rig);
  sc.steps = 2000;
  sc.convergence.stop_when_converged = true;
  sc.convergence.stop_at_residual_tol = true;
  sc.convergence.residual_tol = 1e-4 * rc.reach;
  const RunSummary s = run_scene(sc);
  Outcome o;
  o.tails_world = s.final_frames.tail_world;
  o.local = s.final_pose.bone_local_rotation;
  o.residual = s.final_residuals[0];
  o.iterations = s.steps_run;
  o.time_s = s.wall_time_s;
  o.converged = s.converged && !s.diverged;
  o.limit_violation_deg = rad2deg(max_limit_violation(rc.rig, s.final_pose));
  return o;
}

// KDL: each bone is three revolute joints (x, y, z) at its head and a segment of its length
// along the chain (+Z, the chains' rest direction); a position-only LMA (rotation weights 0).
Outcome kdl_lma(const RigCase& rc, const Vec3& target) {
  KDL::Chain chain;
  for (int i = 0; i < rc.rig.nbone; ++i) {
    chain.addSegment(KDL::Segment(KDL::Joint(KDL::Joint::RotX)));
    chain.addSegment(KDL::Segment(KDL::Joint(KDL::Joint::RotY)));
    chain.addSegment(KDL::Segment(KDL::Joint(KDL::Joint::RotZ),
                                  KDL::Frame(KDL::Vector(0, 0, rc.rig.bone_length[i]))));
  }
  Eigen::Matrix<double, 6, 1> weights;
  weights << 1, 1, 1, 0, 0, 0;
  KDL::ChainIkSolverPos_LMA lma(chain, weights, 1e-4 * rc.reach, 1000, 1e-15);
  KDL::JntArray q0(chain.getNrOfJoints()), q(chain.getNrOfJoints());
  const auto t0 = std::chrono::steady_clock::now();
  lma.CartToJnt(q0, KDL::Frame(KDL::Vector(target.x(), target.y(), target.z())), q);
  Outcome o;
  o.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  o.iterations = lma.lastNrOfIter;
  KDL::ChainFkSolverPos_recursive fk(chain);
  for (int i = 0; i < rc.rig.nbone; ++i) {
    KDL::Frame fr;
    fk.JntToCart(q, fr, 3 * i + 3);
    o.tails_world.push_back(Vec3(fr.p.x(), fr.p.y(), fr.p.z()));
    o.local.push_back(Quat(Eigen::AngleAxisd(q(3 * i), Vec3::UnitX()) *
                           Eigen::AngleAxisd(q(3 * i + 1), Vec3::UnitY()) *
                           Eigen::AngleAxisd(q(3 * i + 2), Vec3::UnitZ())));
  }
  o.residual = (o.tails_world.back() - target).norm();
  o.converged = o.residual <= 1e-4 * rc.reach;
  return o;
}

Vec3 random_direction(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Vec3 v(n(rng), n(rng), n(rng));
  return v.normalized();
}

Pose random_legal_pose(const Rig& rig, std::mt19937& rng) {
  Pose p = rest_pose(rig);
  for (int i = 0; i < rig.nbone; ++i) {
    Vec3 v;
    for (int k = 0; k < 3; ++k) {
      const AxisLimit& l = rig.bone_limit[i][k];
      const bool lim = l.limited && i > 0;
      v[k] = std::uniform_real_distribution<double>(lim ? l.min : -1.0, lim ? l.max : 1.0)(rng);
    }
    p.bone_local_rotation[i] = quat_from_rotation_vector(v);
  }
  return p;
}

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(std::min<double>(v.size() - 1, std::floor(q * (v.size() - 1) + 0.5)))];
}
double mean(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x;
  return v.empty() ? std::nan("") : s / v.size();
}

struct Stats {
  std::vector<double> reach_success, reach_residual, reach_iters, reach_time, unreach_notconv, unreach_excess,
      violation, rotation, offpath, jump;
};

std::string fmt(double v, int prec = 3) {
  std::ostringstream s;
  s << std::setprecision(prec) << v;
  return s.str();
}

void run(const Context& ctx) {
  const int n_reach = ctx.quick ? 12 : 1000, n_unreach = ctx.quick ? 4 : 200;
  const int n_cont = ctx.quick ? 4 : 100;
  const int physik_reach = ctx.quick ? 3 : 100, physik_unreach = ctx.quick ? 1 : 20;
  const int physik_cont = ctx.quick ? 1 : 20;

  std::vector<RigCase> rigs;
  for (int n : {3, 10, 50}) {
    if (ctx.quick && n == 50) continue;
    RigCase rc;
    rc.rig = make_chain_rig(n);
    rc.name = "chain" + std::to_string(n);
    rc.bone = n - 1;
    rc.chain = true;
    rigs.push_back(rc);
  }
  {
    RigCase rc;
    rc.rig = load_rig(ctx.models_dir + "/rigs/pinhead.json");
    rc.name = "pinhead";
    rc.bone = rc.rig.find_bone("hand.L");
    rigs.push_back(rc);
  }
  for (RigCase& rc : rigs) rc.reach = chain_reach(rc.rig, {{rc.bone, 1.0, Vec3::Zero()}});

  std::vector<std::pair<std::string, Solver>> solvers;
  for (IkMethod m : {IkMethod::kFabrik, IkMethod::kCcd, IkMethod::kJacobianTranspose,
                     IkMethod::kDampedLeastSquares, IkMethod::kMassSpring, IkMethod::kRotation}) {
    solvers.push_back({to_string(m), [m](const RigCase& rc, const Vec3& t) { return classic(m, rc, t); }});
  }
  solvers.push_back({"kdl-lma", kdl_lma});
  solvers.push_back({"physik", physik_engine});

  std::ofstream solves(ctx.out_dir + "/solves.csv");
  solves << "rig,solver,kind,index,target_x,target_y,target_z,residual,residual_over_reach,success,"
            "converged,iterations,time_s,limit_violation_deg,total_rotation_rad,offpath_motion\n";
  std::ofstream cont(ctx.out_dir + "/continuity.csv");
  cont << "rig,solver,index,target_move,max_tail_jump,jump_ratio\n";
  solves << std::setprecision(9);
  cont << std::setprecision(9);

  nlohmann::json table = nlohmann::json::array();
  std::map<std::string, std::map<std::string, Stats>> all;
  for (const RigCase& rc : rigs) {
    std::mt19937 rng(20240607);
    std::vector<Vec3> reach_targets, unreach_targets, moves;
    const Vec3 root = rc.rig.bone_rest_head_world[0];
    for (int t = 0; t < n_reach; ++t) {
      if (rc.chain) {
        const double r = 0.95 * rc.reach * std::cbrt(std::uniform_real_distribution<double>(0, 1)(rng));
        reach_targets.push_back(root + r * random_direction(rng));
      } else {
        reach_targets.push_back(
            forward_kinematics(rc.rig, random_legal_pose(rc.rig, rng)).tail_world[rc.bone]);
      }
    }
    for (int t = 0; t < n_unreach; ++t) {
      const double r = rc.reach * std::uniform_real_distribution<double>(1.1, 2.0)(rng);
      unreach_targets.push_back(root + r * random_direction(rng));
    }
    for (int t = 0; t < n_cont; ++t) moves.push_back(0.01 * rc.reach * random_direction(rng));
    // path of the effector: bones off it measure secondary motion on trees
    std::vector<char> on_path(rc.rig.nbone, 0);
    for (int b = rc.bone; b >= 0; b = rc.rig.bone_parent[b]) on_path[b] = 1;
    const BoneFrames rest = forward_kinematics(rc.rig, rest_pose(rc.rig));

    for (const auto& [sname, solve] : solvers) {
      if (sname == "kdl-lma" && !rc.chain) continue;  // KDL: chains only
      const bool is_physik = sname == "physik";
      if (is_physik && rc.rig.nbone > 20) continue;
      const int nr = is_physik ? std::min(physik_reach, n_reach) : n_reach;
      const int nu = is_physik ? std::min(physik_unreach, n_unreach) : n_unreach;
      const int nc = is_physik ? std::min(physik_cont, n_cont) : n_cont;
      if (ctx.log) *ctx.log << "  " << rc.name << " / " << sname << ": " << nr << " + " << nu << " targets\n";
      Stats& st = all[rc.name][sname];
      std::vector<Outcome> reach_out;
      auto record = [&](const char* kind, int idx, const Vec3& t, const Outcome& o) {
        const bool success = o.residual < 1e-3 * rc.reach;
        double rot = 0.0, off = 0.0;
        int noff = 0;
        for (int i = 0; i < rc.rig.nbone; ++i) {
          rot += o.local[i].angularDistance(Quat::Identity());
          if (!on_path[i]) {
            off += (o.tails_world[i] - rest.tail_world[i]).norm();
            ++noff;
          }
        }
        off = noff ? off / noff : 0.0;
        solves << rc.name << "," << sname << "," << kind << "," << idx << "," << t.x() << ","
               << t.y() << "," << t.z() << "," << o.residual << "," << o.residual / rc.reach << ","
               << success << "," << o.converged << "," << o.iterations << "," << o.time_s << ","
               << o.limit_violation_deg << "," << rot << "," << off << "\n";
        st.violation.push_back(o.limit_violation_deg);
        if (std::string(kind) == "reachable") {
          st.reach_success.push_back(success);
          st.reach_residual.push_back(o.residual / rc.reach);
          st.reach_iters.push_back(o.iterations);
          st.reach_time.push_back(o.time_s);
          st.rotation.push_back(rot);
          st.offpath.push_back(off);
        } else {
          st.unreach_notconv.push_back(!o.converged);
          st.unreach_excess.push_back((o.residual - ((t - root).norm() - rc.reach)) / rc.reach);
        }
      };
      for (int t = 0; t < nr; ++t) {
        reach_out.push_back(solve(rc, reach_targets[t]));
        record("reachable", t, reach_targets[t], reach_out.back());
      }
      for (int t = 0; t < nu; ++t) record("unreachable", t, unreach_targets[t], solve(rc, unreach_targets[t]));
      for (int t = 0; t < nc; ++t) {
        const Outcome moved = solve(rc, reach_targets[t] + moves[t]);
        double jump = 0.0;
        for (int i = 0; i < rc.rig.nbone; ++i) {
          jump = std::max(jump, (moved.tails_world[i] - reach_out[t].tails_world[i]).norm());
        }
        const double ratio = jump / moves[t].norm();
        st.jump.push_back(ratio);
        cont << rc.name << "," << sname << "," << t << "," << moves[t].norm() << "," << jump << ","
             << ratio << "\n";
      }
      nlohmann::json row = {
          {"rig", rc.name},
          {"solver", sname},
          {"reachable", nr},
          {"unreachable", nu},
          {"success_rate", mean(st.reach_success)},
          {"median_residual_over_reach", percentile(st.reach_residual, 0.5)},
          {"median_iterations", percentile(st.reach_iters, 0.5)},
          {"p95_iterations", percentile(st.reach_iters, 0.95)},
          {"mean_time_ms", 1e3 * mean(st.reach_time)},
          {"max_limit_violation_deg", *std::max_element(st.violation.begin(), st.violation.end())},
          {"mean_total_rotation_rad", mean(st.rotation)},
          {"mean_offpath_motion", mean(st.offpath)},
          {"unreachable_not_converged", mean(st.unreach_notconv)},
          {"unreachable_excess_over_reach", mean(st.unreach_excess)},
          {"continuity_median_ratio", percentile(st.jump, 0.5)},
          {"continuity_p95_ratio", percentile(st.jump, 0.95)},
          {"continuity_jumps_over_10", [&] {
             int c = 0;
             for (double j : st.jump) c += j > 10.0;
             return st.jump.empty() ? 0.0 : static_cast<double>(c) / st.jump.size();
           }()}};
      table.push_back(row);
    }
  }

  // claims from the guide, seed 002 and the paper, measured here
  auto row_of = [&](const std::string& rig, const std::string& solver) -> const nlohmann::json* {
    for (const auto& r : table) {
      if (r["rig"] == rig && r["solver"] == solver) return &r;
    }
    return nullptr;
  };
  auto val = [&](const std::string& rig, const std::string& solver, const char* key) {
    const nlohmann::json* r = row_of(rig, solver);
    return r ? (*r)[key].get<double>() : std::nan("");
  };
  const std::string big = ctx.quick ? "chain10" : "chain50";
  nlohmann::json claims = nlohmann::json::array();
  auto pct = [](double x) { return fmt(100.0 * x, 4) + "%"; };
  {
    std::ostringstream m;
    bool holds = true;
    for (const auto& r : table) {
      if (r["solver"] == "physik") continue;
      m << r["rig"].get<std::string>() << " " << r["solver"].get<std::string>() << " "
        << pct(r["success_rate"].get<double>()) << "; ";
      holds &= r["success_rate"].get<double>() >= 0.99;
    }
    claims.push_back({{"claim", "Every classic solver reaches reachable targets (residual < 1e-3 of the reach, rest-pose start, 1000 iterations)"},
                      {"measured", m.str()},
                      {"holds", holds ? "yes" : "no"}});
  }
  {
    const double jt = val(big, "jt", "median_iterations"), dls = val(big, "dls", "median_iterations");
    const double tj = val(big, "jt", "mean_time_ms"), td = val(big, "dls", "mean_time_ms");
    claims.push_back({{"claim", "Guide: the Jacobian transpose is a slow 'C tier' solver; DLS regularises it"},
                      {"measured", big + ": median iterations JT " + fmt(jt) + " vs DLS " + fmt(dls) +
                                       ", time " + fmt(tj) + " vs " + fmt(td) + " ms, success JT " +
                                       pct(val(big, "jt", "success_rate")) + " vs DLS " +
                                       pct(val(big, "dls", "success_rate"))},
                      {"holds", jt > 3 * dls ? "yes" : "no"}});
  }
  {
    const double ccd = val(big, "ccd", "mean_total_rotation_rad"),
                 dls = val(big, "dls", "mean_total_rotation_rad");
    claims.push_back({{"claim", "Guide: CCD rolls the chain up (more joint rotation than the Jacobian methods for the same goals)"},
                      {"measured", big + ": mean total rotation CCD " + fmt(ccd) + " rad vs DLS " + fmt(dls) + " rad"},
                      {"holds", ccd > dls ? "yes" : "no"}});
  }
  {
    const double chain = val("chain10", "fabrik", "success_rate"), pin = val("pinhead", "fabrik", "success_rate");
    claims.push_back({{"claim", "Guide: FABRIK has issues with rotation constraints (pinhead's locked collar, hinge elbow) but not on free chains"},
                      {"measured", "success chain10 " + pct(chain) + ", pinhead " + pct(pin) +
                                       "; median iterations " + fmt(val("chain10", "fabrik", "median_iterations")) +
                                       " vs " + fmt(val("pinhead", "fabrik", "median_iterations"))},
                      {"holds", pin < chain ? "yes" : (pin == chain ? "no" : "no")}});
  }
  {
    const double rot = val("pinhead", "rotation", "continuity_p95_ratio"),
                 dls = val("pinhead", "dls", "continuity_p95_ratio"),
                 jt = val("pinhead", "jt", "continuity_p95_ratio");
    claims.push_back({{"claim", "Seed 002: the rotation method is immune to the Jacobian methods' instability near singular configurations (smoother under small target moves)"},
                      {"measured", "pinhead p95 jump ratio (tail motion / target motion): rotation " + fmt(rot) +
                                       ", DLS " + fmt(dls) + ", JT " + fmt(jt) + "; " + big + ": rotation " +
                                       fmt(val(big, "rotation", "continuity_p95_ratio")) + ", DLS " +
                                       fmt(val(big, "dls", "continuity_p95_ratio")) +
                                       " (but the rotation method reaches only " +
                                       pct(val(big, "rotation", "success_rate")) + " there, so it barely moves); "
                                       "both reach ~100% on pinhead, where the comparison is fair"},
                      {"holds", rot < std::min(dls, jt) ? "partly" : "no"}});
  }
  {
    const double ph = val("pinhead", "physik", "mean_offpath_motion");
    double best = 0.0;
    for (const char* s : {"fabrik", "ccd", "jt", "dls", "mass-spring", "rotation"}) {
      best = std::max(best, val("pinhead", s, "mean_offpath_motion"));
    }
    claims.push_back({{"claim", "Paper Fig 9: PhysIK moves the rest of the body (secondary motion) where classic IK moves only the arm chain"},
                      {"measured", "pinhead mean displacement of bones off the head-to-hand path: PhysIK " + fmt(ph) +
                                       " rig units, largest classic solver " + fmt(best) +
                                       " (classic solvers turn the root head bone, which carries the body)"},
                      {"holds", ph > best ? "yes" : "no"}});
  }
  {
    std::ostringstream m;
    for (const std::string& r : {std::string("chain3"), std::string("chain10"), big}) {
      m << r << ": KDL " << pct(val(r, "kdl-lma", "success_rate")) << " in "
        << fmt(val(r, "kdl-lma", "mean_time_ms")) << " ms, DLS " << pct(val(r, "dls", "success_rate"))
        << " in " << fmt(val(r, "dls", "mean_time_ms")) << " ms; ";
    }
    claims.push_back({{"claim", "Outside reference: our DLS matches Orocos KDL's LMA in success on free chains"},
                      {"measured", m.str()},
                      {"holds", val(big, "dls", "success_rate") >= val(big, "kdl-lma", "success_rate") - 0.01 ? "yes" : "no"}});
  }
  {
    const double ph = val("pinhead", "physik", "success_rate");
    claims.push_back({{"claim", "PhysIK meets a reachable target to 1e-3 of the reach (stops at 1e-4 of the reach or when stalled, 2000-step cap)"},
                      {"measured", "success chain3 " + pct(val("chain3", "physik", "success_rate")) + ", chain10 " +
                                       pct(val("chain10", "physik", "success_rate")) + ", pinhead " + pct(ph) +
                                       "; median steps on pinhead " + fmt(val("pinhead", "physik", "median_iterations")) +
                                       ", " + fmt(val("pinhead", "physik", "mean_time_ms")) + " ms per solve"},
                      {"holds", ph >= 0.99 ? "yes" : ph >= 0.5 ? "partly" : "no"}});
  }

  nlohmann::json notes = nlohmann::json::array();
  notes.push_back("Targets: " + std::to_string(n_reach) + " reachable + " + std::to_string(n_unreach) +
                  " unreachable per rig (seed 20240607); PhysIK gets " + std::to_string(physik_reach) +
                  " + " + std::to_string(physik_unreach) + " and no 50-bone chain (its 5 n^2 joint-pass cap "
                  "makes a 50-bone step ~3 ms); continuity on the first " + std::to_string(n_cont) +
                  " reachable targets (PhysIK " + std::to_string(physik_cont) + "), target moved by 1% of the reach.");
  notes.push_back("PhysIK's root is free, so it gets a second control point pinning the root's head; "
                  "classic solvers anchor the root's head and turn the root bone (pinhead's root is the head bone). "
                  "The pin is a spring too, so toward unreachable targets PhysIK's root is dragged along (negative "
                  "excess: the hand gets closer than |t| - reach), and its joint limits are torsion springs "
                  "(soft), hence the limit violation; classic solvers clamp and never violate.");
  notes.push_back("PhysIK stops like the classic solvers: when every control point is within 1e-4 of the "
                  "reach (scene convergence.stop_at_residual_tol), or when its residual stalls short of it "
                  "(no 1% improvement in 50 steps; then it has not converged).");
  notes.push_back("Columns: success = residual < 1e-3 reach; median res/reach = median residual on reachable targets over the reach; iters = median iterations (PhysIK: steps); "
                  "ms = mean wall time per solve; viol = largest limit violation (deg); rot = mean total joint "
                  "rotation (rad); off = mean displacement of off-path bones; unreach nc = fraction of unreachable "
                  "targets reported not converged; excess = mean residual beyond |t| - reach (over reach); "
                  "jump p95 = 95th percentile of tail motion / target motion.");
  for (const auto& r : table) {
    std::ostringstream s;
    s << r["rig"].get<std::string>() << " | " << r["solver"].get<std::string>() << " | success "
      << pct(r["success_rate"].get<double>()) << " | median res/reach "
      << fmt(r["median_residual_over_reach"].get<double>(), 2) << " | iters " << fmt(r["median_iterations"].get<double>())
      << " | ms " << fmt(r["mean_time_ms"].get<double>()) << " | viol " << fmt(r["max_limit_violation_deg"].get<double>())
      << " | rot " << fmt(r["mean_total_rotation_rad"].get<double>()) << " | off "
      << fmt(r["mean_offpath_motion"].get<double>()) << " | unreach nc "
      << pct(r["unreachable_not_converged"].get<double>()) << " | excess "
      << fmt(r["unreachable_excess_over_reach"].get<double>()) << " | jump p95 "
      << fmt(r["continuity_p95_ratio"].get<double>());
    notes.push_back(s.str());
  }
  write_json({{"experiment", "ik_comparison"},
                   {"quick", ctx.quick},
                   {"table", table},
                   {"report",
                    {{"title", "Classic IK solvers, the rotation method, KDL and PhysIK"},
                     {"section", "baselines"},
                     {"claims", claims},
                     {"notes", notes},
                     {"figures", {"ik_success.png", "ik_time.png", "ik_continuity.png"}}}}},
                  ctx.out_dir + "/summary.json");
}

}  // namespace

Experiment ik_comparison_experiment() {
  return {"ik_comparison", "study (issue 7)",
          "classic IK solvers, the rotation method, KDL LMA and PhysIK on chains and pinhead", run};
}

}  // namespace physik::experiments
