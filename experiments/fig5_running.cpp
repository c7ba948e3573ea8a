// Paper Fig 5: a static running pose from 8 control points at k = 30. Claim: the reachable
// control points are met; an infeasible pair (left shoulder and left hand, further apart than the
// arm reaches) is left as a compromise.
//
//   run             the recorded run (trajectory table, first and last frames), then:
//   measure_pair    the pair's shortfall (target distance - arm reach) and each point's residual
//   control_points  per control point: target, final residual, in the infeasible pair or not
//   add_claims      met within 1% of the rig height; a compromise when both miss by > 10% of the
//                   shortfall and together by < 1.5 x the shortfall
#include <algorithm>
#include <stdexcept>

#include "experiments/common.h"
#include "physik/io/summary_io.h"

namespace physik::experiments {

namespace {

// the infeasible pair: control points "shoulder.L" and "hand.L", found by name
struct Pair {
  int hand = -1, shoulder = -1;
  double gap = 0.0;        // rig units, between their targets
  double arm = 0.0;        // rig units, upper arm + forearm + hand
  double shortfall = 0.0;  // gap - arm: what the springs must split between them
  double hand_res = 0.0, shoulder_res = 0.0;
};

bool in_pair(const ControlPoint& cp) {
  return cp.name == "shoulder.L" || cp.name == "hand.L";
}

Pair measure_pair(const Scene& scene, const RunSummary& s) {
  Pair p;
  for (std::size_t c = 0; c < scene.control_points.size(); ++c) {
    if (scene.control_points[c].name == "hand.L") p.hand = static_cast<int>(c);
    if (scene.control_points[c].name == "shoulder.L") p.shoulder = static_cast<int>(c);
  }
  if (p.hand < 0 || p.shoulder < 0)
    throw std::runtime_error("fig5_running: scene lacks hand.L/shoulder.L");
  p.gap =
      (scene.control_points[p.hand].target_world - scene.control_points[p.shoulder].target_world)
          .norm();
  for (const char* bone : {"upper_arm.L", "forearm.L", "hand.L"}) {
    p.arm += scene.rig.bone_length[scene.rig.find_bone(bone)];
  }
  p.shortfall = p.gap - p.arm;
  p.hand_res = s.final_residuals[p.hand];
  p.shoulder_res = s.final_residuals[p.shoulder];
  return p;
}

nlohmann::json control_points(const Scene& scene, const RunSummary& s) {
  nlohmann::json points = nlohmann::json::array();
  for (std::size_t c = 0; c < scene.control_points.size(); ++c) {
    const ControlPoint& cp = scene.control_points[c];
    points.push_back({{"name", cp.name},
                      {"bone", scene.rig.bone_name[cp.bone]},
                      {"target", {cp.target_world.x(), cp.target_world.y(), cp.target_world.z()}},
                      {"final_residual", s.final_residuals[c]},
                      {"final_residual_over_height", s.final_residuals[c] / scene.rig.height()},
                      {"infeasible_pair", in_pair(cp)}});
  }
  return points;
}

void add_claims(Report& report, const Scene& scene, const RunSummary& s, const Pair& p) {
  const double h = scene.rig.height();
  double worst_reachable = 0.0;
  for (std::size_t c = 0; c < scene.control_points.size(); ++c) {
    if (!in_pair(scene.control_points[c]))
      worst_reachable = std::max(worst_reachable, s.final_residuals[c]);
  }
  const double pair_residual = p.hand_res + p.shoulder_res;
  // a compromise: both miss, each by at least 10% of the shortfall, and together by not much
  // more than the shortfall (the arm stretched toward both)
  const bool split = std::min(p.hand_res, p.shoulder_res) > 0.1 * p.shortfall;
  // the reachable points are "met" within 1% of the rig's height
  const bool met = worst_reachable < 0.01 * h;
  report.claim("Fig 5: the reachable control points of a running pose (k = 30) are met",
               "largest final residual of the " + std::to_string(scene.control_points.size() - 2) +
                   " reachable points " + num(worst_reachable) + " (" +
                   num(100 * worst_reachable / h, 2) + "% of the rig height) after " +
                   std::to_string(s.steps_run) +
                   " steps; converged: " + (s.converged ? "yes" : "no"),
               met ? "yes" : (worst_reachable < 0.03 * h ? "partly" : "no"));
  report.claim("Fig 5: an infeasible pair (left shoulder, left hand) is left as a compromise",
               "targets " + num(p.gap) + " apart, arm reach " + num(p.arm) + ": shortfall " +
                   num(p.shortfall) + "; final residuals " + num(p.shoulder_res) +
                   " (shoulder) + " + num(p.hand_res) + " (hand) = " + num(pair_residual),
               !split ? "no (one point takes the whole error)"
               : pair_residual < 1.5 * p.shortfall
                   ? "yes"
                   : "partly (the pair misses by more than the shortfall)");
}

void run(const Context& ctx) {
  Scene scene = scene_named(ctx, "fig5_running");
  if (ctx.quick) scene.steps = 100;
  RecordOptions opt = trajectory_table(ctx.out_dir + "/trajectory.csv", 10);
  opt.frame_steps = {0, scene.steps};
  const RecordedRun run = record_run(scene, opt);
  const auto frames = write_frames(scene, run, ctx.out_dir, "frame_");
  const RunSummary& s = run.summary;

  Report report("Fig 5: a running pose from 8 control points");
  add_claims(report, scene, s, measure_pair(scene, s));
  report.settings(settings_json(scene, {{"k", scene.control_points[0].k_in(scene.params)}}))
      .note(
          "Rig pinhead; the damping is the original code's 3 N s/m because the paper's 20 "
          "diverges on this rig (see the damping sweep).")
      .note("Max joint-limit violation over the run: " + num(s.max_limit_violation_deg) +
            " deg (torsion springs are soft, k = " + num(scene.params.torsion_k) + " N m/rad).")
      .figures({"fig5_running.png"});
  write_summary(ctx,
                {{"experiment", "fig5_running"},
                 {"summary", summary_to_json(scene, s)},
                 {"control_points", control_points(scene, s)},
                 {"frames", frames},
                 {"final_frame", frames.back()}},
                report);
}

const Registration registered{
    50, {"fig5_running", "Fig 5", "running pose from 8 control points, k = 30", run}};

}  // namespace

}  // namespace physik::experiments
