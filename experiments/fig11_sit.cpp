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

#include "experiments/columns.h"
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

Vec3 axis(const BoneFrames& f, int b) {
  return f.tail_world[b] - f.head_world[b];
}

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
  return {{"pelvis_z", p.pelvis_z},      {"knee_flex_L_deg", p.knee_l},
          {"knee_flex_R_deg", p.knee_r}, {"hip_flex_L_deg", p.hip_l},
          {"hip_flex_R_deg", p.hip_r},   {"torso_tilt_deg", p.torso_tilt}};
}

// The control points the schedule moves (1) and those it never moves (0, the static ones).
std::vector<char> moving_points(const Scene& scene) {
  std::vector<char> moving(scene.control_points.size(), 0);
  for (const TargetChange& t : scene.schedule) moving[t.control_point] = 1;
  return moving;
}

struct StaticResidual {
  double max = 0.0;  // rig units, over the run and the static points
  int max_step = 0;
  double final = 0.0;  // rig units, largest at the end
};

// residuals.csv: every step, every point's residual
Table residuals_table(const Scene& scene, const RecordedRun& run) {
  std::vector<Column> cols = {columns::kStep, real("kinetic_energy", "J", "the kinetic energy", 9)};
  for (const ControlPoint& c : scene.control_points) {
    cols.push_back(real("residual_" + c.name, "rig units",
                        "control point " + c.name + "'s distance to its goal target", 9));
  }
  Table t("residuals", "residuals.csv", cols);
  for (std::size_t k = 0; k < run.residuals.size(); ++k) {
    std::vector<Cell> row = {k + 1, run.stats[k].kinetic_energy};
    for (double r : run.residuals[k]) row.push_back(r);
    t.add(std::move(row));
  }
  return t;
}

// the static points' largest residual over the run, and at the end
StaticResidual static_residual(const RecordedRun& run, const std::vector<char>& moving) {
  StaticResidual out;
  for (std::size_t k = 0; k < run.residuals.size(); ++k) {
    for (std::size_t c = 0; c < moving.size(); ++c) {
      const double r = run.residuals[k][c];
      if (!moving[c] && r > out.max) {
        out.max = r;
        out.max_step = static_cast<int>(k) + 1;
      }
    }
  }
  for (std::size_t c = 0; c < moving.size(); ++c) {
    if (!moving[c]) out.final = std::max(out.final, run.summary.final_residuals[c]);
  }
  return out;
}

// the posture at every recorded frame
nlohmann::json frame_postures(const Rig& rig, const RecordedRun& run,
                              const std::vector<std::string>& files) {
  nlohmann::json frames = nlohmann::json::array();
  for (std::size_t k = 0; k < run.frames.size(); ++k) {
    nlohmann::json f = posture_json(posture(rig, run.frames[k]));
    f["step"] = run.frame_steps[k];
    f["file"] = files[k];
    frames.push_back(f);
  }
  return frames;
}

void add_claims(Report& report, const Rig& rig, const Posture& start, const Posture& end,
                double final_pelvis, const StaticResidual& st) {
  const double foot_len =
      0.5 * (rig.bone_length[bone(rig, "foot.L")] + rig.bone_length[bone(rig, "foot.R")]);
  const double h = rig.height();
  const double knee = std::min(end.knee_l, end.knee_r), hip = std::min(end.hip_l, end.hip_r);
  const bool sits = final_pelvis < 0.02 * h && knee > 45 && hip > 45;
  const bool sits_partly = start.pelvis_z - end.pelvis_z > 0.1 * h;
  report.claim("Fig 11: one moving control point (pelvis) makes the rig sit",
               "pelvis lowered by " + num(start.pelvis_z - end.pelvis_z) + " rig units (" +
                   num(100 * (start.pelvis_z - end.pelvis_z) / h, 2) +
                   "% of the rig height), final pelvis "
                   "residual " +
                   num(final_pelvis) + "; knees bent " + num(end.knee_l) + " / " + num(end.knee_r) +
                   " deg, hips " + num(end.hip_l) + " / " + num(end.hip_r) + " deg, torso tilt " +
                   num(end.torso_tilt) + " deg",
               sits ? "yes" : (sits_partly ? "partly" : "no"));
  report.claim("Fig 11: the four static control points (heels, toes) keep the feet planted",
               "largest static residual " + num(st.max) + " rig units at step " +
                   std::to_string(st.max_step) + " (" + num(100 * st.max / foot_len, 2) +
                   "% of a foot's length), final " + num(st.final),
               st.max < 0.1 * foot_len ? "yes" : (st.final < 0.1 * foot_len ? "partly" : "no"));
}

void add_notes(Report& report, const RunSummary& s) {
  report
      .note(
          "Pelvis = tail of the torso bone. Knee flexion = angle between thigh and shin axes, hip "
          "flexion = angle between the torso's downward axis and the thigh's axis (both 0 "
          "standing).")
      .note(
          "Sits = yes when the final pelvis residual is under 2% of the rig height and knees and "
          "hips "
          "bend past 45 deg; partly when the pelvis drops by more than 10% of the height. Feet "
          "planted "
          "= yes when the static points stay within 10% of a foot's length over the whole run, "
          "partly "
          "when only at the end.")
      .note("Run: " + std::to_string(s.steps_run) + " steps, diverged " +
            (s.diverged ? "yes" : "no") + ", peak KE " + num(s.peak_kinetic_energy) +
            " J, max joint-limit violation " + num(s.max_limit_violation_deg) +
            " deg, mean passes per step " + num(s.mean_passes_per_step) + ".");
}

nlohmann::json control_points_json(const Scene& scene, const RunSummary& s,
                                   const std::vector<char>& moving) {
  nlohmann::json a = nlohmann::json::array();
  for (std::size_t c = 0; c < scene.control_points.size(); ++c) {
    const Vec3& t = scene.control_points[c].target_world;
    a.push_back({{"name", scene.control_points[c].name},
                 {"moving", bool(moving[c])},
                 {"target", {t.x(), t.y(), t.z()}},
                 {"final_residual", s.final_residuals[c]}});
  }
  return a;
}

void run(const Context& ctx) {
  Scene scene = scene_named(ctx, "fig11_sit");
  if (ctx.quick) scene.steps = std::min(scene.steps, 130);
  const Rig& rig = scene.rig;
  RecordOptions ro = trajectory_table(ctx.out_dir + "/trajectory.csv", 5);
  ro.frame_steps = {0, 60, 120, 180, 240, scene.steps};
  ro.frame_steps.erase(std::remove_if(ro.frame_steps.begin(), ro.frame_steps.end(),
                                      [&](int s) { return s > scene.steps; }),
                       ro.frame_steps.end());
  ro.stats = ro.residuals = true;
  const RecordedRun run = record_run(scene, ro);
  write_run_folder(ctx, "sit", scene);  // for the viewer
  const std::vector<std::string> frame_files = write_frames(scene, run, ctx.out_dir, "sit_");
  if (ctx.log) *ctx.log << "  " << run.summary.steps_run << " steps\n";

  const std::vector<char> moving = moving_points(scene);
  const auto pelvis = std::find(moving.begin(), moving.end(), 1);  // the first moving point
  if (pelvis == moving.end())
    throw_input_error(scene.file, "schedule", "", "no moving control point");
  const Table residuals = residuals_table(scene, run);
  residuals.write_csv(ctx.out_dir);
  const StaticResidual st = static_residual(run, moving);
  const Posture start = posture(rig, forward_kinematics(rig, scene.initial_pose));
  const Posture end = posture(rig, run.summary.final_frames);

  Report report("Fig 11: sitting from one moving and four static control points");
  add_claims(report, rig, start, end, run.summary.final_residuals[pelvis - moving.begin()], st);
  add_notes(report, run.summary);
  report.figures({"fig11_frames.png", "fig11_residuals.png"}).settings(settings_json(scene));
  nlohmann::json schedule_steps = nlohmann::json::array();
  for (const TargetChange& t : scene.schedule) schedule_steps.push_back(t.step);
  write_summary(ctx,
                {{"experiment", "fig11_sit"},
                 {"scene", scene.file},
                 {"frames", frame_postures(rig, run, frame_files)},
                 {"start", posture_json(start)},
                 {"end", posture_json(end)},
                 {"control_points", control_points_json(scene, run.summary, moving)},
                 {"max_static_residual", st.max},
                 {"schedule_steps", schedule_steps},
                 {"run", summary_to_json(scene, run.summary)}},
                report, {&residuals});
}

const Registration registered{
    110,
    {"fig11_sit", "Fig 11", "sitting animation from one moving and four static control points",
     run}};

}  // namespace

}  // namespace physik::experiments
