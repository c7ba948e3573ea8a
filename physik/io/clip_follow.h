// Following a clip: a scene whose control points track a BVH clip's joints frame by frame, so
// the engine reproduces the motion with its own dynamics (secondary motion, contacts: a floor
// keeps the feet out of it). For `physik follow` and experiments/clip_following.cpp.
//
// The defaults (follow_params: the clip_following experiment's settings, which hold a walking
// figure on its feet under gravity, where the engine's own dt 0.05 s and control_k 10 N/m let it
// sink into a heap):
//   dt  = T / s,  s = ceil(T / kFollowMaxDt)     T the clip's frame time (s): one step a frame
//                                                 for clips of 120 fps or more, 4 at 30 fps
//   k   = M g / (n kFollowSag)                    every followed point's spring (N/m): the n
//         points carrying the rig's weight M g in equal shares would sag kFollowSag
//         (M the rig's mass, kg; g = kFollowGravity, rig units/s^2, as --gravity pulls)
// A `--set dt=` or `--set control_k=` wins over its default.
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
// The state that stands for clip frame f is the start for f = first and the step
// (f - first + 1) * s, where the targets have reached frame f, after it (followed_frame): a run
// written one pose per clip frame has the clip's frame count at s dt a frame, the clip's frame
// time under the defaults.
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
#include "physik/model/params.h"
#include "physik/model/scene.h"

namespace physik {

constexpr double kFollowMaxDt = 1.0 / 120.0;  // s, the longest default step
constexpr double kFollowSag = 0.01;           // rig units, a point's sag under its weight share
constexpr double kFollowGravity = 9.81;       // rig units/s^2, --gravity's pull along -Z

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

// Every followed point's target at every frame first..last: targets[f - first][p]; InputError
// naming `source` (the clip) for a frame whose root lies past +-kMaxCoordinate (checked_clip_pose).
std::vector<std::vector<Vec3>> clip_targets(const Rig& rig, const BvhFile& clip,
                                            const std::vector<FollowPoint>& points, int first,
                                            int last, const std::string& source);

// The engine parameters a follow runs with: `overrides` (--set) on the default preset, then dt
// and control_k from the clip and the rig as above where the overrides give neither. The points
// are options.points (empty: default_follow_points).
EngineParams follow_params(const Rig& rig, const BvhFile& clip, const FollowOptions& options,
                           const ParamOverrides& overrides = {});

// The engine steps per clip frame of a follow scene (follow_scene keeps it in the params'
// interpolation_steps) and the time they take, s: the clip's frame time under the defaults.
int follow_steps_per_frame(const Scene& follow);
double follow_frame_time(const Scene& follow);

// The clip frame, counted from the first followed (0 = options.first), that a follow scene's
// state after `step` steps stands for, or -1 for a step between them (clip_follow.h above).
int followed_frame(const Scene& follow, int step);

// The scene that follows `clip` on `rig` with `params` (a scene's params; the control points
// take their springs from them). InputError naming options.source and the field for a clip of
// another skeleton, a rig without a source skeleton, frames outside the clip, an unknown bone, an
// alpha outside [0, 1], a frame whose root lies past +-kMaxCoordinate, a run longer than
// INT_MAX steps (field "Frame Time"); naming "--ground" for a floor height that is not finite
// or lies past +-kMaxCoordinate.
Scene follow_scene(const Rig& rig, const BvhFile& clip, EngineParams params,
                   const FollowOptions& options);

}  // namespace physik
