// Tracking: a control point dragged as a user drags it, solved once per frame.
//
// Pinhead's left-hand control point (pinhead_two_hands, the right hand held at its target) moves
// on a circle of radius 0.3 rig units in the body's frontal (x-z) plane, 0.05 rig units per
// frame, for 120 frames (three turns and a bit), starting from the scene solved. Each frame:
//   - PhysIK (the PosingSession of physik/posing: the scene's own engine) takes k = 1, 3 or 10
//     steps toward the moved target: the body follows with its secondary motion; the same with
//     scheme implicit, k = 1 and 3;
//   - DLS and the rotation method solve the frame's goals to their tolerance, starting from the
//     previous frame's pose (as an interactive tool calls them).
// Per frame: cost (wall time of the frame's call, us), lag (the largest control-point residual
// after it, rig units) and smoothness (jump ratio: the largest bone-tail motion over the frame
// divided by the target's motion, 0.05). Writes frames.csv and a summary table per solver.
#include <algorithm>
#include <chrono>
#include <cmath>

#include "experiments/common.h"
#include "experiments/table.h"
#include "physik/ik/ik_solver.h"
#include "physik/posing/posing_session.h"

namespace physik::experiments {

namespace {

constexpr double kRadius = 0.3;     // rig units
constexpr double kPerFrame = 0.05;  // rig units of target motion per frame
constexpr int kFrames = 120;

// Target of the dragged point at frame f (f = 0: where it starts).
Vec3 drag_target(const Vec3& start, int f) {
  const double a = kPerFrame * f / kRadius;
  return start + kRadius * Vec3(std::cos(a) - 1.0, 0.0, std::sin(a));
}

struct Track {
  std::string solver;
  std::vector<double> cost_us, lag, jump;  // per frame
};

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(q * (v.size() - 1) + 0.5)];
}

double largest_tail_motion(const BoneFrames& a, const BoneFrames& b) {
  double m = 0.0;
  for (std::size_t i = 0; i < a.tail_world.size(); ++i)
    m = std::max(m, (a.tail_world[i] - b.tail_world[i]).norm());
  return m;
}

using Clock = std::chrono::steady_clock;
double us_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::micro>(Clock::now() - t0).count();
}

Track track_physik(const Scene& scene, int k, const std::string& tag = "physik") {
  Track t{tag + " k=" + std::to_string(k), {}, {}, {}};
  PosingSession session(scene);
  session.solve();  // the drag starts from the solved pose (not timed)
  const Vec3 start = session.state().target_goal_world[0];
  BoneFrames previous = session.frames();
  for (int f = 1; f <= kFrames; ++f) {
    const auto t0 = Clock::now();
    session.set_target(0, drag_target(start, f));
    session.advance(k);
    t.cost_us.push_back(us_since(t0));
    t.lag.push_back(session.residual());
    t.jump.push_back(largest_tail_motion(previous, session.frames()) / kPerFrame);
    previous = session.frames();
  }
  return t;
}

Track track_classic(const Scene& scene, IkMethod method) {
  Track t{to_string(method), {}, {}, {}};
  std::vector<IkGoal> goals;
  for (const ControlPoint& cp : scene.control_points)
    goals.push_back({cp.bone, cp.alpha, cp.target_world});
  const Vec3 start = goals[0].target_world;
  Pose pose = scene.initial_pose;
  solve_ik(method, scene.rig, goals, pose, {});  // the drag starts from the solved pose
  BoneFrames previous = forward_kinematics(scene.rig, pose);
  std::vector<double> residuals;
  for (int f = 1; f <= kFrames; ++f) {
    goals[0].target_world = drag_target(start, f);
    const auto t0 = Clock::now();
    solve_ik(method, scene.rig, goals, pose, {});
    t.cost_us.push_back(us_since(t0));
    const BoneFrames now = forward_kinematics(scene.rig, pose);
    goal_residuals(now, goals, residuals);
    t.lag.push_back(*std::max_element(residuals.begin(), residuals.end()));
    t.jump.push_back(largest_tail_motion(previous, now) / kPerFrame);
    previous = now;
  }
  return t;
}

nlohmann::json row_of(const Track& t) {
  double mean_lag = 0.0;
  for (double l : t.lag) mean_lag += l / t.lag.size();
  return {{"solver", t.solver},
          {"median_cost_us", percentile(t.cost_us, 0.5)},
          {"mean_lag", mean_lag},
          {"max_lag", percentile(t.lag, 1.0)},
          {"p95_jump_ratio", percentile(t.jump, 0.95)},
          {"max_jump_ratio", percentile(t.jump, 1.0)}};
}

// frames.csv: every solver's every frame
Table frames_table(const std::vector<Track>& tracks) {
  Table t(
      "frames", "frames.csv",
      {text("solver", "the solver, and PhysIK's steps per frame"),
       integer("frame", "", "the frame (1: the first move)"),
       real("cost_us", "us", "wall time of the frame's call"),
       real("lag", "rig units", "the largest control-point residual after the call"),
       real("jump_ratio", "", "the largest bone-tail motion over the frame / the drag (0.05)")});
  for (const Track& tr : tracks) {
    for (std::size_t f = 0; f < tr.lag.size(); ++f) {
      t.add({tr.solver, f + 1, tr.cost_us[f], tr.lag[f], tr.jump[f]});
    }
  }
  return t;
}

void add_claims(Report& report, const nlohmann::json& rows) {
  const auto find = [&](const std::string& s) -> const nlohmann::json& {
    for (const auto& r : rows)
      if (r["solver"] == s) return r;
    throw std::logic_error("tracking: no row " + s);
  };
  const nlohmann::json &p3 = find("physik k=3"), &dls = find("dls"), &rot = find("rotation");
  const double pj = p3["p95_jump_ratio"], dj = dls["p95_jump_ratio"], rj = rot["p95_jump_ratio"];
  report.claim(
      "Tracking: PhysIK (3 steps per frame) follows a dragged point at least as smoothly "
      "as DLS and the rotation method",
      "p95 jump ratio: PhysIK " + num(pj) + ", DLS " + num(dj) + ", rotation " + num(rj),
      pj <= std::min(dj, rj)   ? "yes"
      : pj <= std::max(dj, rj) ? "partly"
                               : "no");
  const double pl = p3["mean_lag"], dl = dls["mean_lag"];
  const double pc = p3["median_cost_us"], dc = dls["median_cost_us"];
  report.claim(
      "Tracking: PhysIK's per-frame cost is at most DLS's, with a lag of a few "
      "per cent of the drag per frame",
      "median us per frame: PhysIK " + num(pc) + ", DLS " + num(dc) + "; mean lag PhysIK " +
          num(pl) + " rig units (" + num(100 * pl / kPerFrame) + "% of the per-frame drag), DLS " +
          num(dl),
      pc <= dc && pl < 0.1 * kPerFrame   ? "yes"
      : pc <= dc || pl < 0.1 * kPerFrame ? "partly"
                                         : "no");
}

void run(const Context& ctx) {
  const Scene scene = scene_named(ctx, "pinhead_two_hands");
  std::vector<Track> tracks;
  for (int k : {1, 3, 10}) tracks.push_back(track_physik(scene, k));
  Scene implicit = scene;  // the same scene on the implicit step (its exact joint solve)
  implicit.params.scheme = Scheme::kImplicit;
  for (int k : {1, 3}) tracks.push_back(track_physik(implicit, k, "physik implicit"));
  tracks.push_back(track_classic(scene, IkMethod::kDampedLeastSquares));
  tracks.push_back(track_classic(scene, IkMethod::kRotation));
  const Table frames = frames_table(tracks);
  frames.write_csv(ctx.out_dir);
  nlohmann::json rows = nlohmann::json::array();
  for (const Track& t : tracks) {
    rows.push_back(row_of(t));
    if (ctx.log) *ctx.log << "  " << rows.back().dump() << "\n";
  }
  Report report("Tracking: a control point dragged in a circle, one solve per frame");
  add_claims(report, rows);
  report.settings(settings_json(scene))
      .note(
          "Pinhead's left-hand point on a circle of radius 0.3 rig units in the x-z plane, 0.05 "
          "rig units per frame, " +
          std::to_string(kFrames) +
          " frames; the right hand held. "
          "Lag = the largest residual after the frame's call; jump ratio = the largest bone-tail "
          "motion over the frame / 0.05. Per-solver rows in summary.json, per frame in frames.csv.")
      .figures({"tracking.png"});
  write_summary(ctx, {{"experiment", "tracking"}, {"rows", rows}}, report, {&frames});
}

const Registration registered{
    245,
    {"tracking", "study: dragging",
     "a control point dragged in a circle: cost, lag, smoothness per frame", run}};

}  // namespace

}  // namespace physik::experiments
