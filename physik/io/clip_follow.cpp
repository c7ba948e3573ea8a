// A scene that follows a clip (clip_follow.h).
#include "physik/io/clip_follow.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

#include "physik/io/scene_io.h"
#include "physik/model/errors.h"
#include "physik/model/names.h"

namespace physik {

std::vector<FollowPoint> default_follow_points(const Rig& rig) {
  std::vector<FollowPoint> out{{rig.bone_name[0], 1.0}};
  for (int b = 1; b < rig.nbone; ++b) {
    if (rig.bone_children[b].empty()) out.push_back({rig.bone_name[b], 1.0});
  }
  return out;
}

std::vector<std::vector<Vec3>> clip_targets(const Rig& rig, const BvhFile& clip,
                                            const std::vector<FollowPoint>& points, int first,
                                            int last, const std::string& source) {
  std::vector<std::vector<Vec3>> out;
  BoneFrames scratch, fk;
  Pose pose;
  for (int f = first; f <= last; ++f) {
    checked_clip_pose(rig, clip, f, source, "", scratch, pose);
    forward_kinematics(rig, pose, fk);
    std::vector<Vec3> row;
    for (const FollowPoint& p : points) {
      const int b = rig.find_bone(p.bone);
      row.push_back(fk.head_world[b] + p.alpha * (fk.tail_world[b] - fk.head_world[b]));
    }
    out.push_back(std::move(row));
  }
  return out;
}

namespace {

// the rig's mass (kg) and the followed points' count: control_k's default (clip_follow.h)
double default_control_k(const Rig& rig, std::size_t npoint) {
  return rig.total_mass() * kFollowGravity / (static_cast<double>(npoint) * kFollowSag);
}

// the clip, the frames and the points checked (InputError as follow_scene says); the last frame
int checked_last_frame(const Rig& rig, const BvhFile& clip, const FollowOptions& o,
                       const std::vector<FollowPoint>& points) {
  const std::string& src = o.source;
  if (rig.source_skeleton.empty()) {
    throw_input_error(src, "", "rig",
                      "the rig has no source skeleton (make it with `physik rig from-bvh` from "
                      "this clip's skeleton)");
  }
  const std::string mismatch = source_skeleton_mismatch(rig.source_skeleton, clip);
  if (!mismatch.empty()) {
    throw_input_error(src, "", "skeleton", "not a clip of the rig's source skeleton: " + mismatch);
  }
  const int nframe = static_cast<int>(clip.frames.size());
  const int last = o.last < 0 ? nframe - 1 : o.last;
  if (o.first < 0 || o.first >= nframe) {
    throw_input_error(src, "", "first frame",
                      std::to_string(o.first) + " is outside the clip (" + std::to_string(nframe) +
                          " frames, 0 to " + std::to_string(nframe - 1) + ")");
  }
  if (last < o.first || last >= nframe) {
    throw_input_error(src, "", "last frame",
                      std::to_string(last) + " is outside frames " + std::to_string(o.first) +
                          " to " + std::to_string(nframe - 1));
  }
  if (o.ground && !(std::abs(*o.ground) <= kMaxCoordinate)) {  // false for NaN too
    throw_input_error("--ground", "", "",
                      "the floor's height must be a finite number within +-1e9 rig units (rig.h "
                      "kMaxCoordinate)");
  }
  for (std::size_t i = 0; i < points.size(); ++i) {
    const FollowPoint& p = points[i];
    const std::string field = "points[" + std::to_string(i) + "]";
    if (rig.find_bone(p.bone) < 0) {
      throw_input_error(src, field, "bone", unknown_bone(p.bone, rig));
    }
    if (!(p.alpha >= 0.0 && p.alpha <= 1.0)) {
      throw_input_error(src, field, "alpha", "must be within [0, 1] (0 head, 1 tail)");
    }
  }
  return last;
}

// the steps per clip frame at dt (at least 1) and the run's steps, checked to fit an int
// (InputError naming the clip's Frame Time)
int checked_steps_per_frame(const BvhFile& clip, double dt, int nframe, const std::string& src) {
  const double per_frame = std::max(1.0, std::round(clip.frame_time / dt));
  const double steps = per_frame * nframe;
  if (!(steps <= static_cast<double>(std::numeric_limits<int>::max()))) {
    std::ostringstream why;
    why << std::setprecision(6) << clip.frame_time << " s a frame at dt " << dt << " s is "
        << per_frame << " steps a frame, " << steps << " steps for " << nframe
        << " frames: more than a run counts (" << std::numeric_limits<int>::max()
        << "); check the clip's frame time, or follow fewer frames (--frames)";
    throw_input_error(src, "", "Frame Time", why.str());
  }
  return static_cast<int>(per_frame);
}

}  // namespace

EngineParams follow_params(const Rig& rig, const BvhFile& clip, const FollowOptions& o,
                           const ParamOverrides& overrides) {
  EngineParams p = params_from_json(nlohmann::json(nullptr), overrides.source, overrides);
  if (!overrides.has("dt")) {
    // the ratio's round-off (1/30 written with 12 digits is 3.99999999999 frames of 1/120) is
    // not a step more
    const double ratio = clip.frame_time / kFollowMaxDt;
    p.dt = clip.frame_time / std::max(1.0, std::ceil(ratio * (1.0 - 1e-9)));
  }
  if (!overrides.has("control_k")) {
    const std::size_t n = o.points.empty() ? default_follow_points(rig).size() : o.points.size();
    p.control_k = default_control_k(rig, n);
  }
  return p;
}

int follow_steps_per_frame(const Scene& follow) {
  return follow.params.interpolation_steps;
}

double follow_frame_time(const Scene& follow) {
  return follow_steps_per_frame(follow) * follow.params.dt;
}

int followed_frame(const Scene& follow, int step) {
  const int s = follow_steps_per_frame(follow);
  if (step == 0) return 0;
  if (step % s != 0 || step < 2 * s) return -1;
  return step / s - 1;
}

Scene follow_scene(const Rig& rig, const BvhFile& clip, EngineParams params,
                   const FollowOptions& o) {
  const std::vector<FollowPoint> points = o.points.empty() ? default_follow_points(rig) : o.points;
  const int last = checked_last_frame(rig, clip, o, points);
  Scene s;
  s.file = o.source;
  s.rig = rig;
  const int per_frame = checked_steps_per_frame(clip, params.dt, last - o.first + 1, o.source);
  params.interpolation_steps = per_frame;
  s.params = params;
  const auto targets = clip_targets(rig, clip, points, o.first, last, o.source);
  BoneFrames scratch;
  source_clip_pose(rig, clip, o.first, scratch, s.initial_pose);  // checked with the targets
  for (std::size_t i = 0; i < points.size(); ++i) {
    ControlPoint c;
    c.name = points[i].bone + (points[i].alpha == 1.0   ? ":tail"
                               : points[i].alpha == 0.0 ? ":head"
                                                        : "");
    c.bone = rig.find_bone(points[i].bone);
    c.alpha = points[i].alpha;
    c.target_world = targets[0][i];
    s.control_points.push_back(c);
  }
  for (int f = o.first + 1; f <= last; ++f) {
    for (std::size_t i = 0; i < points.size(); ++i) {
      s.schedule.push_back(
          {(f - o.first) * per_frame, static_cast<int>(i), targets[f - o.first][i]});
    }
  }
  s.steps = (last - o.first + 1) * per_frame;
  if (o.ground) {
    GroundPlane g;
    g.height = *o.ground;
    s.collision.ground = g;
  }
  if (o.gravity) s.gravity_world = Vec3(0.0, 0.0, -9.81);
  check_scene_joints(s);
  return s;
}

}  // namespace physik
