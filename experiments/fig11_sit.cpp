// Paper Fig 11 / Sec. 4: a sitting animation from one moving control point (the pelvis, lowered
// and pushed back in stages by the scene's schedule) and four static ones (heel and toe of each
// foot), models/scenes/fig11_sit.json. Frames at six instants in the side view (y-z), the
// paper's sit-0..5.
//
// Measures (world frame, Z up, character facing -Y):
//   residual_c(k)     distance of control point c to its goal target after step k, rig units
//   pelvis_drop       z of the pelvis (tail of torso) at the start minus at the end, rig units
//   knee_flex_deg     angle between the thigh's and the shin's axes (0 = straight leg)
//   hip_flex_deg      angle between the torso's downward axis (head -> tail) and the thigh's
//                     axis (0 = standing straight)
//   torso_tilt_deg    angle of the torso's up axis (tail -> head) from +Z
// "Sits": the pelvis follows its target (final residual under 2% of the rig height) and the knees
// and hips bend past 45 deg. "Feet planted": the four static points stay within 10% of a foot's
// length of their targets over the whole run.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>

#include "experiments/common.h"
#include "physik/io/summary_io.h"
#include "physik/model/errors.h"

namespace physik::experiments {

namespace {

constexpr double kDeg = 180.0 / 3.14159265358979323846;

double angle_between(const Vec3& a, const Vec3& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

int bone(const Rig& rig, const std::string& name) {
  const int b = rig.find_bone(name);
  if (b < 0) throw_input_error(rig.name, "bone '" + name + "'", "", "missing; fig11 needs pinhead");
  return b;
}

Vec3 axis(const BoneFrames& f, int b) { return f.tail_world[b] - f.head_world[b]; }

struct Posture {
  double pelvis_z = 0, knee_l = 0, knee_r = 0, hip_l = 0, hip_r = 0, torso_tilt = 0;
};

Posture posture(const Rig& rig, const BoneFrames& f) {
  const int torso = bone(rig, "torso");
  Posture p;
  p.pelvis_z = f.tail_world[torso].z();
  p.knee_l = kDeg * angle_between(axis(f, bone(rig, "thigh.L")), axis(f, bone(rig, "shin.L")));
  p.knee_r = kDeg * angle_between(axis(f, bone(rig, "thigh.R")), axis(f, bone(rig, "shin.R")));
  p.hip_l = kDeg * angle_between(axis(f, torso), axis(f, bone(rig, "thigh.L")));
  p.hip_r = kDeg * angle_between(axis(f, torso), axis(f, bone(rig, "thigh.R")));
  p.torso_tilt = kDeg * angle_between(-axis(f, torso), Vec3::UnitZ());
  return p;
}

nlohmann::json posture_json(const Posture& p) {
  return {{"pelvis_z", p.pelvis_z},     {"knee_flex_L_deg", p.knee_l}, {"knee_flex_R_deg", p.knee_r},
          {"hip_flex_L_deg", p.hip_l},  {"hip_flex_R_deg", p.hip_r},
          {"torso_tilt_deg", p.torso_tilt}};
}

void run(const Context& ctx) {
  Scene scene = scene_named(ctx, "fig11_sit");
  if (ctx.quick) scene.steps = std::min(scene.steps, 130);
  const Rig& rig = scene.rig;
  std::vector<int> frame_steps = {0, 60, 120, 180, 240, scene.steps};
  frame_steps.erase(std::remove_if(frame_steps.begin(), frame_steps.end(),
                                   [&](int s) { return s > scene.steps; }),
                    frame_steps.end());

  RecordOptions ro = trajectory_table(ctx.out_dir + "/trajectory.csv", 5);
  ro.frame_steps = frame_steps;
  ro.stats = true;
  ro.residuals = true;
  const RecordedRun run = record_run(scene, ro);
  const std::vector<std::string> frame_files = write_frames(scene, run, ctx.out_dir, "sit_");
  if (ctx.log) *ctx.log << "  " << run.summary.steps_run << " steps\n";

  // which control points are static: those the schedule never moves
  const int nc = static_cast<int>(scene.control_points.size());
  std::vector<char> moving(nc, 0);
  for (const TargetChange& t : scene.schedule) moving[t.control_point] = 1;
  int pelvis = -1;
  for (int c = 0; c < nc; ++c) pelvis = moving[c] && pelvis < 0 ? c : pelvis;
  if (pelvis < 0) throw_input_error(scene.file, "schedule", "", "no moving control point");

  // per-step residuals
  double max_static = 0.0, final_static = 0.0;
  int max_static_step = 0;
  {
    std::ofstream out(ctx.out_dir + "/residuals.csv");
    out << "step,kinetic_energy";
    for (const ControlPoint& c : scene.control_points) out << ",residual_" << c.name;
    out << "\n" << std::setprecision(9);
    for (std::size_t k = 0; k < run.residuals.size(); ++k) {
      out << k + 1 << "," << run.stats[k].kinetic_energy;
      for (int c = 0; c < nc; ++c) {
        const double r = run.residuals[k][c];
        out << "," << r;
        if (!moving[c] && r > max_static) {
          max_static = r;
          max_static_step = static_cast<int>(k) + 1;
        }
      }
      out << "\n";
    }
  }
  for (int c = 0; c < nc; ++c) {
    if (!moving[c]) final_static = std::max(final_static, run.summary.final_residuals[c]);
  }
  const double final_pelvis = run.summary.final_residuals[pelvis];

  // posture at each frame
  nlohmann::json frames = nlohmann::json::array();
  for (std::size_t k = 0; k < run.frames.size(); ++k) {
    nlohmann::json f = posture_json(posture(rig, run.frames[k]));
    f["step"] = run.frame_steps[k];
    f["file"] = frame_files[k];
    frames.push_back(f);
  }
  const Posture start = posture(rig, forward_kinematics(rig, scene.initial_pose));
  const Posture end = posture(rig, run.summary.final_frames);
  const double foot_len = 0.5 * (rig.bone_length[bone(rig, "foot.L")] + rig.bone_length[bone(rig, "foot.R")]);
  const double h = rig.height();
  const double knee = std::min(end.knee_l, end.knee_r), hip = std::min(end.hip_l, end.hip_r);

  const bool sits = final_pelvis < 0.02 * h && knee > 45 && hip > 45;
  const bool sits_partly = start.pelvis_z - end.pelvis_z > 0.1 * h;
  nlohmann::json claims = nlohmann::json::array();
  claims.push_back(claim(
      "Fig 11: one moving control point (pelvis) makes the rig sit",
      "pelvis lowered by " + num(start.pelvis_z - end.pelvis_z) + " rig units (" +
          num(100 * (start.pelvis_z - end.pelvis_z) / h, 2) + "% of the rig height), final pelvis "
          "residual " + num(final_pelvis) + "; knees bent " + num(end.knee_l) + " / " +
          num(end.knee_r) + " deg, hips " + num(end.hip_l) + " / " + num(end.hip_r) +
          " deg, torso tilt " + num(end.torso_tilt) + " deg",
      sits ? "yes" : (sits_partly ? "partly" : "no")));
  claims.push_back(claim(
      "Fig 11: the four static control points (heels, toes) keep the feet planted",
      "largest static residual " + num(max_static) + " rig units at step " +
          std::to_string(max_static_step) + " (" + num(100 * max_static / foot_len, 2) +
          "% of a foot's length), final " + num(final_static),
      max_static < 0.1 * foot_len ? "yes" : (final_static < 0.1 * foot_len ? "partly" : "no")));

  const nlohmann::json notes = {
      "Pelvis = tail of the torso bone. Knee flexion = angle between thigh and shin axes, hip "
      "flexion = angle between the torso's downward axis and the thigh's axis (both 0 standing).",
      "Sits = yes when the final pelvis residual is under 2% of the rig height and knees and hips "
      "bend past 45 deg; partly when the pelvis drops by more than 10% of the height. Feet planted "
      "= yes when the static points stay within 10% of a foot's length over the whole run, partly "
      "when only at the end.",
      "Run: " + std::to_string(run.summary.steps_run) + " steps, diverged " +
          (run.summary.diverged ? "yes" : "no") + ", peak KE " +
          num(run.summary.peak_kinetic_energy) + " J, max joint-limit violation " +
          num(run.summary.max_limit_violation_deg) + " deg, mean passes per step " +
          num(run.summary.mean_passes_per_step) + "."};

  write_json({{"experiment", "fig11_sit"},
                   {"scene", scene.file},
                   {"frames", frames},
                   {"start", posture_json(start)},
                   {"end", posture_json(end)},
                   {"control_points",
                    [&] {
                      nlohmann::json a = nlohmann::json::array();
                      for (int c = 0; c < nc; ++c)
                        a.push_back({{"name", scene.control_points[c].name},
                                     {"moving", bool(moving[c])},
                                     {"target",
                                      {scene.control_points[c].target_world.x(),
                                       scene.control_points[c].target_world.y(),
                                       scene.control_points[c].target_world.z()}},
                                     {"final_residual", run.summary.final_residuals[c]}});
                      return a;
                    }()},
                   {"max_static_residual", max_static},
                   {"schedule_steps",
                    [&] {
                      nlohmann::json a = nlohmann::json::array();
                      for (const TargetChange& t : scene.schedule) a.push_back(t.step);
                      return a;
                    }()},
                   {"run", summary_to_json(scene, run.summary)},
                   {"report",
                    {{"title", "Fig 11: sitting from one moving and four static control points"},
                     {"claims", claims},
                     {"notes", notes},
                     {"figures", {"fig11_frames.png", "fig11_residuals.png"}},
                     {"settings", settings_json(scene)}}}},
                  ctx.out_dir + "/summary.json");
}

}  // namespace

Experiment fig11_sit_experiment() {
  return {"fig11_sit", "Fig 11", "sitting animation from one moving and four static control points",
          run};
}

}  // namespace physik::experiments
