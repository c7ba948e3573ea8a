// Following a clip: a scene whose control points track a BVH clip's joints frame by frame, so
// the engine reproduces the motion with its own dynamics (secondary motion, contacts: a floor
// keeps the feet out of it). For `physik follow` and experiments/clip_following.cpp.
//
// The clip is a clip of the rig's source skeleton (source_skeleton_mismatch empty). Each followed
// point sits on a bone at alpha (0 head, 1 tail); its target at clip frame f is where that point
// is when the rig takes the clip's pose of frame f (source_clip_pose, forward kinematics):
//   t_p(f) = h_b(f) + alpha (t_b(f) - h_b(f))          rig world frame and units
// The scene starts in the pose of the first frame, at rest, with every target on its point; at
// step n_f = (f - first) * s, s = max(1, round(frame_time / dt)) steps per clip frame, every
// point's target moves to t_p(f), spread over the s steps by the params' target interpolation
// (interpolation_steps = s), so a target runs through the clip's frames at the
// clip's speed. The run lasts (last - first + 1) * s steps: one clip frame past the last change.
//
// Extension point: a followed orientation (the clip's joint rotation as a bone's orientation
// target) becomes a FollowPoint kind of its own once the engine has orientation targets (today
// only position control points exist); source_clip_pose (bvh.h) already gives each frame's
// joint rotations, and follow_scene is where such targets would be scheduled.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "physik/io/bvh.h"
#include "physik/model/scene.h"

namespace physik {

struct FollowPoint {
  std::string bone;    // a bone of the rig
  double alpha = 1.0;  // 0 head, 1 tail
};

struct FollowOptions {
  std::vector<FollowPoint> points;  // empty: default_follow_points
  int first = 0;                    // clip frames, 0-based, inclusive
  int last = -1;                    // -1: the clip's last frame
  std::optional<double> ground;     // a floor at this height (rig units, rig Z up)
  bool gravity = false;             // -9.81 rig units/s^2 along rig Z (rig units read as metres)
  std::string source;               // the clip's name, for messages
};

// The root bone's tail (the root joint, e.g. Hips) and every leaf bone's tail (head, hands,
// feet): the points a clip is followed by unless others are chosen.
std::vector<FollowPoint> default_follow_points(const Rig& rig);

// Every followed point's target at every frame first..last: targets[f - first][p].
std::vector<std::vector<Vec3>> clip_targets(const Rig& rig, const BvhFile& clip,
                                            const std::vector<FollowPoint>& points, int first,
                                            int last);

// The scene that follows `clip` on `rig` with `params` (a scene's params; the control points
// take their springs from them). InputError naming options.source and the field for a clip of
// another skeleton, a rig without a source skeleton, frames outside the clip, an unknown bone, an
// alpha outside [0, 1].
Scene follow_scene(const Rig& rig, const BvhFile& clip, EngineParams params,
                   const FollowOptions& options);

// The clip frame that step `step` of `scene` (follow_scene's) follows: the nearest on its
// schedule, first + round(step / interpolation_steps), within first..last. A pose of the run
// written back on the source skeleton keeps from that frame what the rig cannot hold (bvh.h
// SourceFrames).
int followed_clip_frame(const Scene& scene, const BvhFile& clip, const FollowOptions& options,
                        int step);

}  // namespace physik
