// A scene that follows a clip (clip_follow.h).
#include "physik/io/clip_follow.h"

#include <algorithm>
#include <cmath>

#include "physik/model/errors.h"

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
                                            int last) {
  std::vector<std::vector<Vec3>> out;
  BoneFrames scratch, fk;
  Pose pose;
  for (int f = first; f <= last; ++f) {
    source_clip_pose(rig, clip, f, scratch, pose);
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
  for (std::size_t i = 0; i < points.size(); ++i) {
    const FollowPoint& p = points[i];
    const std::string field = "points[" + std::to_string(i) + "]";
    if (rig.find_bone(p.bone) < 0) {
      throw_input_error(src, field, "bone", "unknown bone '" + p.bone + "'");
    }
    if (!(p.alpha >= 0.0 && p.alpha <= 1.0)) {
      throw_input_error(src, field, "alpha", "must be within [0, 1] (0 head, 1 tail)");
    }
  }
  return last;
}

}  // namespace

Scene follow_scene(const Rig& rig, const BvhFile& clip, EngineParams params,
                   const FollowOptions& o) {
  const std::vector<FollowPoint> points = o.points.empty() ? default_follow_points(rig) : o.points;
  const int last = checked_last_frame(rig, clip, o, points);
  Scene s;
  s.file = o.source;
  s.rig = rig;
  const int per_frame = std::max(1, static_cast<int>(std::lround(clip.frame_time / params.dt)));
  params.interpolation_steps = per_frame;
  s.params = params;
  const auto targets = clip_targets(rig, clip, points, o.first, last);
  BoneFrames scratch;
  source_clip_pose(rig, clip, o.first, scratch, s.initial_pose);
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

int followed_clip_frame(const Scene& scene, const BvhFile& clip, const FollowOptions& o, int step) {
  const int last = o.last < 0 ? static_cast<int>(clip.frames.size()) - 1 : o.last;
  const int per_frame = std::max(1, scene.params.interpolation_steps);
  const long f = o.first + std::lround(static_cast<double>(step) / per_frame);
  return static_cast<int>(std::clamp<long>(f, o.first, std::max(o.first, last)));
}

}  // namespace physik
