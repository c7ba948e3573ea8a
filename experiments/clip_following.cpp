// Clip following: PhysIK tracks a walk clip with control points (physik/io/clip_follow.h), on a
// floor, under gravity; foot penetration, foot sliding while a foot is planted, and the lag to the
// clip, against the clip itself.
//
// The clip is written here (walk.bvh in the output folder): a 19-joint figure in centimetres,
// Y up (Hips with three children, Chest with three), walking along file +z at v = 90 cm/s with a
// gait period T = 1.1 s (stride v T = 99 cm), 30 frames per second. Each ankle follows a footprint
// schedule: planted (stance) for phase p in [0, 0.6) at z_c = v T (k + 0.3 - p0) (under the hip at
// mid-stance; p0 = 0 left, 0.5 right), then a swing to the next footprint,
//   z = z_c + v T (1 - cos(pi s)) / 2,   y = 6 + 8 sin(pi s),   s = (p - 0.6) / 0.4   (cm),
// the hips at height 86 + 1.5 cos(4 pi t / T) cm. The legs reach the ankles by the two-link
// solution in the sagittal plane (thigh and shin 42 cm, the knee forward): with d = P - H the
// hip-to-ankle vector (y, z), D = |d|, phi = acos((L1^2 + D^2 - L2^2) / (2 L1 D)), the knee is
// K = H + L1 (cos(phi) d/D + sin(phi) n), n = (d_z, -d_y) / D; a joint turning a rest direction
// (0, -1, 0) to u by Rx(a) has a = atan2(-u_z, -u_y); the foot stays flat. The arms hang 75 deg
// down and swing 20 deg against the legs. So the clip's feet are planted exactly (its own sliding
// is 0 up to rounding) and its capsules stand on the floor.
//
// The rig: `rig from-bvh` of the clip at scale 0.01 (metres, default sizes). The floor: at the
// clip's lowest capsule bottom (the lowest point of any bone's capsule in any frame), so the clip
// itself does not penetrate. Runs (the scene follow_scene builds: the root joint and every leaf
// bone's tail followed, hips, head, hands, toes; physik follow's defaults, follow_params: the
// default preset at dt = 1/120 s, 4 steps per clip frame, and every point's spring
// k = M g / (n * 1 cm): the n points holding the body's weight M g in equal shares would sag 1 cm):
//   floor:     the floor and gravity (-9.81 m/s^2)
//   no floor:  gravity alone, to see what the floor does
// Measured per clip frame f (the engine's state when the targets have reached frame f):
//   penetration  the largest depth of a foot bone's capsule (Foot, LeftLeg/RightLeg) under the
//                floor, max over frames (cm);
//   sliding      the toe's (Foot tail's) horizontal speed over the frames where the clip's foot
//                is planted (stance, 2 frames in from each end), mean and max (cm/s);
//   lag          the followed points' mean distance to the clip's (cm), and the time lag: the
//                shift k (0 .. 10 frames) minimising the mean distance to the clip k frames
//                earlier.
#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <limits>

#include "experiments/common.h"
#include "experiments/table.h"
#include "physik/io/clip_follow.h"

namespace physik::experiments {

namespace {

constexpr double kSpeed = 90.0;  // cm/s
constexpr double kPeriod = 1.1;  // s
constexpr double kFrameTime = 1.0 / 30.0;
constexpr double kDuty = 0.6;                  // stance fraction
constexpr double kThigh = 42.0, kShin = 42.0;  // cm
constexpr double kAnkleHeight = 6.0;           // cm, the flat foot's ankle over its toe
constexpr double kLift = 8.0;                  // cm

// the walk skeleton (no frames): Hips, spine to head, two arms, two legs; ZXY rotations
BvhFile walk_skeleton() {
  BvhFile b;
  const std::vector<BvhChannel> rot{BvhChannel::kZrot, BvhChannel::kXrot, BvhChannel::kYrot};
  auto add = [&](const std::string& name, int parent, const Vec3& off,
                 std::vector<Vec3> ends = {}) {
    BvhJoint j;
    j.name = name;
    j.parent = parent;
    j.offset = off;
    j.channels = rot;
    j.end_sites = std::move(ends);
    b.joints.push_back(j);
    return static_cast<int>(b.joints.size()) - 1;
  };
  const int hips = add("Hips", -1, Vec3(0, 95, 0));
  b.joints[hips].channels.insert(b.joints[hips].channels.begin(),
                                 {BvhChannel::kXpos, BvhChannel::kYpos, BvhChannel::kZpos});
  const int spine = add("Spine", hips, Vec3(0, 10, 0));
  const int chest = add("Chest", spine, Vec3(0, 25, 0));
  const int neck = add("Neck", chest, Vec3(0, 25, 0));
  add("Head", neck, Vec3(0, 10, 0), {Vec3(0, 18, 0)});
  for (double sx : {1.0, -1.0}) {
    const std::string side = sx > 0 ? "Left" : "Right";
    const int sh = add(side + "Shoulder", chest, Vec3(sx * 4, 20, 0));
    const int arm = add(side + "Arm", sh, Vec3(sx * 14, 0, 0));
    const int fore = add(side + "ForeArm", arm, Vec3(sx * 28, 0, 0));
    add(side + "Hand", fore, Vec3(sx * 26, 0, 0), {Vec3(sx * 18, 0, 0)});
  }
  for (double sx : {1.0, -1.0}) {
    const std::string side = sx > 0 ? "Left" : "Right";
    const int up = add(side + "UpLeg", hips, Vec3(sx * 9, -5, 0));
    const int leg = add(side + "Leg", up, Vec3(0, -kThigh, 0));
    add(side + "Foot", leg, Vec3(0, -kShin, 0), {Vec3(0, -kAnkleHeight, 14)});
  }
  int col = 0;
  for (BvhJoint& j : b.joints) {
    j.channel_start = col;
    col += static_cast<int>(j.channels.size());
  }
  b.nchannel = col;
  b.frame_time = kFrameTime;
  return b;
}

// a foot's ankle (y, z) at time t, and whether it is planted (stance)
struct Ankle {
  double y, z;
  bool planted;
};
Ankle ankle_at(double t, double p0) {
  const double praw = t / kPeriod + p0;
  const double k = std::floor(praw);
  const double p = praw - k;
  const double zc = kSpeed * kPeriod * (k + 0.3 - p0);
  if (p < kDuty) return {kAnkleHeight, zc, true};
  const double s = (p - kDuty) / (1.0 - kDuty);
  return {kAnkleHeight + kLift * std::sin(kPi * s),
          zc + kSpeed * kPeriod * (1.0 - std::cos(kPi * s)) / 2.0, false};
}

// the rotation about X (deg) taking (0, -1, 0) to the direction (u_y, u_z)
double down_to(double uy, double uz) {
  return rad2deg(std::atan2(-uz, -uy));
}

// the clip's frame at time t; planted[0], [1]: left, right foot in stance
std::vector<double> walk_frame(const BvhFile& b, double t, bool planted[2]) {
  std::vector<double> row(b.nchannel, 0.0);
  auto set_rot = [&](const std::string& name, double z, double x, double y) {
    for (const BvhJoint& j : b.joints) {
      if (j.name != name) continue;
      const int c = j.channel_start + (j.parent < 0 ? 3 : 0);
      row[c] = z;
      row[c + 1] = x;
      row[c + 2] = y;
    }
  };
  const double hip_y = 86.0 + 1.5 * std::cos(4.0 * kPi * t / kPeriod);
  row[0] = 0.0;
  row[1] = hip_y;
  row[2] = kSpeed * t;
  for (int side = 0; side < 2; ++side) {
    const std::string name = side == 0 ? "Left" : "Right";
    const Ankle a = ankle_at(t, side == 0 ? 0.0 : 0.5);
    planted[side] = a.planted;
    const double hy = hip_y - 5.0, hz = kSpeed * t;
    const double dy = a.y - hy, dz = a.z - hz;
    const double d = std::hypot(dy, dz);
    const double phi = std::acos(
        std::clamp((kThigh * kThigh + d * d - kShin * kShin) / (2 * kThigh * d), -1.0, 1.0));
    const double ky = hy + kThigh * (std::cos(phi) * dy / d + std::sin(phi) * dz / d);
    const double kz = hz + kThigh * (std::cos(phi) * dz / d - std::sin(phi) * dy / d);
    const double thigh = down_to((ky - hy) / kThigh, (kz - hz) / kThigh);
    const double shin_world = down_to((a.y - ky) / kShin, (a.z - kz) / kShin);
    set_rot(name + "UpLeg", 0.0, thigh, 0.0);
    set_rot(name + "Leg", 0.0, shin_world - thigh, 0.0);
    set_rot(name + "Foot", 0.0, -shin_world, 0.0);
    // the arm against its leg: the left arm forward when the right leg is
    const double swing = 20.0 * std::sin(2.0 * kPi * (t / kPeriod + (side == 0 ? 0.5 : 0.0)));
    set_rot(name + "Arm", side == 0 ? -75.0 : 75.0, 0.0, side == 0 ? -swing : swing);
  }
  return row;
}

struct Walk {
  BvhFile clip;
  std::vector<std::array<bool, 2>> planted;  // per frame, left and right
};

Walk make_walk(int frames) {
  Walk w{walk_skeleton(), {}};
  for (int f = 0; f < frames; ++f) {
    bool planted[2];
    w.clip.frames.push_back(walk_frame(w.clip, f * kFrameTime, planted));
    w.planted.push_back({planted[0], planted[1]});
  }
  return w;
}

// the frames of the clip (or a run) as rig frames, one per clip frame
using Track = std::vector<BoneFrames>;

Track clip_track(const Rig& rig, const BvhFile& clip) {
  Track out(clip.frames.size());
  BoneFrames scratch;
  Pose pose;
  for (std::size_t f = 0; f < clip.frames.size(); ++f) {
    source_clip_pose(rig, clip, static_cast<int>(f), scratch, pose);
    forward_kinematics(rig, pose, out[f]);
  }
  return out;
}

// the lowest capsule bottom of any bone in any frame (rig units)
double lowest_capsule(const Rig& rig, const Track& t) {
  double low = std::numeric_limits<double>::infinity();
  for (const BoneFrames& f : t) {
    for (int b = 0; b < rig.nbone; ++b) {
      low = std::min(
          low, std::min(f.head_world[b].z(), f.tail_world[b].z()) - rig.bone_collision_radius[b]);
    }
  }
  return low;
}

struct RunResult {
  std::string name;
  Track track;  // per clip frame
  bool diverged = false;
  std::string reason;
};

RunResult follow(const std::string& name, const Scene& scene, int nframe) {
  RunResult r{name, Track(nframe), false, ""};
  r.track[0] = forward_kinematics(scene.rig, scene.initial_pose);
  const RunSummary sum = run_scene(scene, [&](const SimState& s, const StepStats&) {
    const int f = followed_frame(scene, s.step);  // where the targets have reached frame f
    if (f >= 1 && f < nframe) r.track[f] = s.frames;
  });
  r.diverged = sum.diverged;
  r.reason = sum.divergence_reason;
  // a run that ended early keeps its last frame (its measures then say so)
  for (int f = 1; f < nframe; ++f) {
    if (r.track[f].head_world.empty()) r.track[f] = r.track[f - 1];
  }
  return r;
}

struct Measures {
  double penetration_cm = 0.0;
  double slide_mean = 0.0, slide_max = 0.0;  // cm/s
  double mean_distance_cm = 0.0;
  int time_lag_frames = 0;
};

Measures measure(const Rig& rig, const Track& run, const Track& clip, const Walk& w,
                 const std::vector<FollowPoint>& points, double floor) {
  Measures m;
  const char* sides[2] = {"Left", "Right"};
  std::vector<int> foot(2), leg(2);
  for (int s = 0; s < 2; ++s) {
    foot[s] = rig.find_bone(std::string(sides[s]) + "Foot");
    leg[s] = rig.find_bone(std::string(sides[s]) + "Leg");
  }
  const int n = static_cast<int>(run.size());
  for (int f = 0; f < n; ++f) {
    for (int s = 0; s < 2; ++s) {
      for (int b : {foot[s], leg[s]}) {
        const double bottom = std::min(run[f].head_world[b].z(), run[f].tail_world[b].z()) -
                              rig.bone_collision_radius[b];
        m.penetration_cm = std::max(m.penetration_cm, 100.0 * (floor - bottom));
      }
    }
  }
  int count = 0;
  for (int f = 1; f < n; ++f) {
    for (int s = 0; s < 2; ++s) {
      // planted from 2 frames before to 2 frames after: away from the stance's ends
      bool planted = true;
      for (int g = std::max(0, f - 3); g <= std::min(n - 1, f + 2); ++g) planted &= w.planted[g][s];
      if (!planted) continue;
      Vec3 d = run[f].tail_world[foot[s]] - run[f - 1].tail_world[foot[s]];
      d.z() = 0.0;
      const double speed = 100.0 * d.norm() / kFrameTime;
      m.slide_mean += speed;
      m.slide_max = std::max(m.slide_max, speed);
      ++count;
    }
  }
  if (count) m.slide_mean /= count;
  auto point = [&](const BoneFrames& fr, const FollowPoint& p) {
    const int b = rig.find_bone(p.bone);
    return Vec3(fr.head_world[b] + p.alpha * (fr.tail_world[b] - fr.head_world[b]));
  };
  double best = std::numeric_limits<double>::infinity();
  for (int k = 0; k <= 10; ++k) {
    double sum = 0.0;
    int c = 0;
    for (int f = 10; f < n; ++f) {
      for (const FollowPoint& p : points) {
        sum += (point(run[f], p) - point(clip[f - k], p)).norm();
        ++c;
      }
    }
    const double mean = 100.0 * sum / std::max(1, c);
    if (k == 0) m.mean_distance_cm = mean;
    if (mean < best) {
      best = mean;
      m.time_lag_frames = k;
    }
  }
  return m;
}

// frames.csv: per clip frame, the toes' heights and the followed points' distance, per run
Table frames_table(const Rig& rig, const std::vector<RunResult>& runs, const Walk& w,
                   const std::vector<FollowPoint>& points) {
  Table t("frames", "frames.csv",
          {text("run", "clip, or the PhysIK run"), integer("frame", "", "clip frame"),
           real("time", "s", "clip time"), real("left_toe_z", "cm", "LeftFoot's tail height"),
           real("right_toe_z", "cm", "RightFoot's tail height"),
           real("left_planted", "", "1 where the clip's left foot is planted"),
           real("distance", "cm", "the followed points' mean distance to the clip's")});
  const int lf = rig.find_bone("LeftFoot"), rf = rig.find_bone("RightFoot");
  const Track& clip = runs[0].track;
  for (const RunResult& r : runs) {
    for (std::size_t f = 0; f < r.track.size(); ++f) {
      double dist = 0.0;
      for (const FollowPoint& p : points) {
        const int b = rig.find_bone(p.bone);
        const Vec3 a = r.track[f].head_world[b] +
                       p.alpha * (r.track[f].tail_world[b] - r.track[f].head_world[b]);
        const Vec3 c =
            clip[f].head_world[b] + p.alpha * (clip[f].tail_world[b] - clip[f].head_world[b]);
        dist += 100.0 * (a - c).norm() / points.size();
      }
      t.add({r.name, static_cast<int>(f), f * kFrameTime, 100.0 * r.track[f].tail_world[lf].z(),
             100.0 * r.track[f].tail_world[rf].z(), w.planted[f][0] ? 1.0 : 0.0, dist});
    }
  }
  return t;
}

// the measures of each run, as summary rows
nlohmann::json measure_rows(const Context& ctx, const Rig& rig, const std::vector<RunResult>& runs,
                            const Walk& w, const std::vector<FollowPoint>& points, double floor,
                            std::vector<Measures>& ms) {
  nlohmann::json rows = nlohmann::json::array();
  for (const RunResult& r : runs) {
    ms.push_back(measure(rig, r.track, runs[0].track, w, points, floor));
    const Measures& m = ms.back();
    rows.push_back({{"run", r.name},
                    {"diverged", r.diverged},
                    {"max_foot_penetration_cm", m.penetration_cm},
                    {"planted_toe_speed_mean_cm_s", m.slide_mean},
                    {"planted_toe_speed_max_cm_s", m.slide_max},
                    {"mean_point_distance_cm", m.mean_distance_cm},
                    {"time_lag_frames", m.time_lag_frames}});
    if (ctx.log) *ctx.log << "  " << rows.back().dump() << "\n";
  }
  return rows;
}

// the claims on the clip's own measures (c), the floor run's (f) and the run without (n)
void add_claims(Report& report, const std::vector<Measures>& ms, bool diverged) {
  const Measures &c = ms[0], &f = ms[1], &n = ms[2];
  report
      .claim(
          "Clip following: the clip written here stands on its floor with its feet planted "
          "(the measures' own check)",
          "clip: penetration " + num(c.penetration_cm) + " cm, planted toe speed mean " +
              num(c.slide_mean) + " cm/s",
          c.penetration_cm <= 1e-6 && c.slide_mean <= 1e-6 ? "yes" : "no")
      .named("clip-planted");
  report
      .claim(
          "Clip following: the floor keeps the feet out: the deepest foot penetration is at "
          "most 1 cm with the floor, and less than without it",
          "floor " + num(f.penetration_cm) + " cm, no floor " + num(n.penetration_cm) + " cm",
          diverged                                                         ? "no (a run diverged)"
          : f.penetration_cm <= 1.0 && f.penetration_cm < n.penetration_cm ? "yes"
          : f.penetration_cm < n.penetration_cm                            ? "partly"
                                                                           : "no")
      .named("floor");
  report
      .claim("Clip following: a planted foot slides less than 5 cm/s on average (the clip: 0)",
             "planted toe speed, mean / max: floor " + num(f.slide_mean) + " / " +
                 num(f.slide_max) + " cm/s, no floor " + num(n.slide_mean) + " / " +
                 num(n.slide_max) + " cm/s",
             diverged             ? "no (a run diverged)"
             : f.slide_mean < 5.0 ? "yes"
                                  : "no")
      .named("sliding");
  report
      .claim(
          "Clip following: PhysIK lags the clip by at most 2 frames, its followed points "
          "within 5 cm of the clip's on average",
          "floor: time lag " + std::to_string(f.time_lag_frames) + " frames (" +
              num(1000.0 * f.time_lag_frames * kFrameTime) + " ms), mean distance " +
              num(f.mean_distance_cm) + " cm; no floor: " + std::to_string(n.time_lag_frames) +
              " frames, " + num(n.mean_distance_cm) + " cm",
          diverged                                              ? "no (a run diverged)"
          : f.time_lag_frames <= 2 && f.mean_distance_cm <= 5.0 ? "yes"
          : f.time_lag_frames <= 2 || f.mean_distance_cm <= 5.0 ? "partly"
                                                                : "no")
      .named("lag");
}

void run(const Context& ctx) {
  const int nframe = ctx.quick ? 40 : 132;  // 4.4 s: four gait cycles
  Walk w = make_walk(nframe);
  const std::string clip_path = ctx.out_dir + "/walk.bvh";
  {
    std::ofstream out(clip_path);
    write_bvh_file(w.clip, clip_path, out);
  }
  const BvhFile clip = read_bvh_file(clip_path);  // as a user's tool would read it
  BvhImportOptions io;
  io.scale = 0.01;
  const BvhAnimation anim = bvh_to_rig(clip, clip_path, io);
  const Rig& rig = anim.rig();
  const Track clip_frames = clip_track(rig, clip);
  const double floor = lowest_capsule(rig, clip_frames);

  FollowOptions fo;
  fo.source = clip_path;
  fo.gravity = true;
  fo.ground = floor;
  // physik follow's defaults: dt 1/120 s (4 steps a clip frame), control_k = M g / (n 1 cm)
  const EngineParams params = follow_params(rig, clip, fo);
  const Scene with_floor = follow_scene(rig, clip, params, fo);
  fo.ground.reset();
  const Scene no_floor = follow_scene(rig, clip, params, fo);
  const std::vector<FollowPoint> points = default_follow_points(rig);

  std::vector<RunResult> runs{{"clip", clip_frames, false, ""}};
  runs.push_back(follow("floor", with_floor, nframe));
  runs.push_back(follow("no floor", no_floor, nframe));
  std::vector<Measures> ms;
  const nlohmann::json rows = measure_rows(ctx, rig, runs, w, points, floor, ms);
  const Table frames = frames_table(rig, runs, w, points);
  frames.write_csv(ctx.out_dir);
  write_run_folder(ctx, "clip_following_floor", with_floor);

  Report report("Clip following: a walk clip followed on a floor under gravity");
  add_claims(report, ms, runs[1].diverged || runs[2].diverged);
  report
      .settings(
          settings_json(with_floor, {{"steps_per_clip_frame", follow_steps_per_frame(with_floor)},
                                     {"rig_mass_kg", rig.total_mass()},
                                     {"floor_height", floor},
                                     {"clip_frames", nframe}}))
      .note(
          "A walk written here (walk.bvh: 19 joints, cm, Y up, 90 cm/s, 1.1 s gait, 30 fps), "
          "made a rig by rig from-bvh at scale 0.01 and followed by physik follow's scene "
          "(physik/io/clip_follow.h: hips, head, hands and toes followed, the default preset at "
          "dt 1/120 s, control_k = M g / (n x 1 cm), gravity). The floor sits at the clip's lowest "
          "capsule bottom. Penetration: foot and "
          "shin capsules under the floor; sliding: the toe's horizontal speed where the clip's "
          "foot is planted; lag: the shift (frames) minimising the followed points' mean "
          "distance to the clip.")
      .figures({"clip_following.png"});
  write_summary(ctx, {{"experiment", "clip_following"}, {"rows", rows}}, report, {&frames});
}

const Registration registered{
    295,
    {"clip_following", "study: clips",
     "a walk clip followed on a floor: foot penetration, sliding and lag against the clip", run}};

}  // namespace

}  // namespace physik::experiments
