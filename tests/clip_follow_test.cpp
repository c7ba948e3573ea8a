// Following a clip (physik/io/clip_follow.h): the defaults hold a standing figure on its feet
// under gravity (the engine's own dt 0.05 s and control_k 10 N/m left it in a heap), the steps
// per clip frame and the frame each step stands for, the overrides, and the refusals: a floor
// height that is not a finite number within +-1e9, a frame time whose run no int counts, a clip
// whose root the source skeleton's scale puts past +-1e9 (here and in a scene's initial pose).
#include "physik/io/clip_follow.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <sstream>

#include <gtest/gtest.h>

#include "physik/engine/engine.h"
#include "physik/engine/measures.h"
#include "physik/io/rig_io.h"
#include "physik/io/scene_io.h"
#include "physik/model/errors.h"
#include "test_util.h"

namespace physik {
namespace {

// A standing figure in centimetres, Y up (hips with a spine to the head, two arms, two legs with
// feet), `frames` frames of `frame_time` s, every frame the rest pose held still (its root `rise`
// cm higher each frame): a follow of it should stand where it is.
std::string standing_clip(int frames, double frame_time, double rise = 0.0) {
  const std::string rot = "CHANNELS 3 Zrotation Xrotation Yrotation\n";
  auto joint = [&](const std::string& name, const std::string& off, const std::string& inner) {
    return "JOINT " + name + "\n{\nOFFSET " + off + "\n" + rot + inner + "}\n";
  };
  auto end = [](const std::string& off) { return "End Site\n{\nOFFSET " + off + "\n}\n"; };
  std::string body = joint(
      "Spine", "0 10 0",
      joint("Chest", "0 25 0",
            joint("Head", "0 25 0", end("0 25 0")) +
                joint("LeftArm", "18 20 0", joint("LeftForeArm", "28 0 0", end("26 0 0"))) +
                joint("RightArm", "-18 20 0", joint("RightForeArm", "-28 0 0", end("-26 0 0")))));
  for (const char* side : {"Left", "Right"}) {
    const std::string sx = side[0] == 'L' ? "9" : "-9";
    body += joint(std::string(side) + "UpLeg", sx + " -5 0",
                  joint(std::string(side) + "Leg", "0 -42 0",
                        joint(std::string(side) + "Foot", "0 -42 0", end("0 -6 14"))));
  }
  std::ostringstream text;
  text << "HIERARCHY\nROOT Hips\n{\nOFFSET 0 95 0\n"
       << "CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n"
       << body << "}\nMOTION\nFrames: " << frames << "\nFrame Time: " << std::setprecision(12)
       << frame_time << "\n";
  for (int f = 0; f < frames; ++f) {
    text << "0 " << 95.0 + rise * f << " 0";
    for (int c = 3; c < 6 + 13 * 3; ++c) text << " 0";
    text << "\n";
  }
  return text.str();
}

struct Figure {
  BvhFile clip;
  Rig rig;
};

Figure figure(int frames, double frame_time) {
  Figure f;
  f.clip = parse_bvh(standing_clip(frames, frame_time), "stand.bvh");
  BvhImportOptions io;
  io.scale = 0.01;
  f.rig = bvh_to_rig(f.clip, "stand.bvh", io).rig();
  return f;
}

// the lowest capsule bottom of the rig at rest (rig units, Z up): where a floor holds it
double floor_under(const Rig& rig) {
  double low = 1e300;
  for (int b = 0; b < rig.nbone; ++b) {
    low = std::min(low, std::min(rig.bone_rest_head_world[b].z(), rig.bone_rest_tail_world[b].z()) -
                            rig.bone_collision_radius[b]);
  }
  return low;
}

TEST(ClipFollow, DefaultsTakeTheClipsFrameTimeAndTheRigsWeight) {
  const Figure fig = figure(5, 1.0 / 30.0);
  FollowOptions o;
  const EngineParams p = follow_params(fig.rig, fig.clip, o);
  const double n = static_cast<double>(default_follow_points(fig.rig).size());
  EXPECT_EQ(n, 6);  // hips, head, two hands, two feet
  // 4 steps a frame of 1/30 s (the file's 0.0333333333333: 12 digits)
  EXPECT_DOUBLE_EQ(p.dt, fig.clip.frame_time / 4.0);
  EXPECT_NEAR(p.dt, 1.0 / 120.0, 1e-13);
  EXPECT_DOUBLE_EQ(p.control_k, fig.rig.total_mass() * kFollowGravity / (n * kFollowSag));
  const Scene s = follow_scene(fig.rig, fig.clip, p, o);
  EXPECT_EQ(follow_steps_per_frame(s), 4);
  EXPECT_DOUBLE_EQ(follow_frame_time(s), fig.clip.frame_time);
  EXPECT_EQ(s.steps, 5 * 4);

  // 120 fps and faster: one step a frame; 50 fps: 3 steps of 1/150 s
  const Figure fast = figure(5, 1.0 / 240.0);
  EXPECT_DOUBLE_EQ(follow_params(fast.rig, fast.clip, o).dt, fast.clip.frame_time);
  const Figure fifty = figure(5, 0.02);
  EXPECT_DOUBLE_EQ(follow_params(fifty.rig, fifty.clip, o).dt, 0.02 / 3.0);

  // chosen points count: k follows their number
  o.points = {{"Head", 1.0}, {"LeftFoot", 1.0}};
  EXPECT_DOUBLE_EQ(follow_params(fig.rig, fig.clip, o).control_k,
                   fig.rig.total_mass() * kFollowGravity / (2.0 * kFollowSag));

  // --set wins over both defaults
  const ParamOverrides set = parse_param_overrides({"dt=0.01", "control_k=55"}, "--set");
  const EngineParams q = follow_params(fig.rig, fig.clip, o, set);
  EXPECT_EQ(q.dt, 0.01);
  EXPECT_EQ(q.control_k, 55.0);
}

TEST(ClipFollow, EachClipFrameIsTheStepWhereTheTargetsHaveReachedIt) {
  const Figure fig = figure(6, 1.0 / 30.0);
  const Scene s = follow_scene(fig.rig, fig.clip, follow_params(fig.rig, fig.clip, {}), {});
  // frame 0 the start, frame f >= 1 the step (f + 1) s, s = 4: one state per clip frame
  int frames = 0;
  for (int step = 0; step <= s.steps; ++step) {
    const int f = followed_frame(s, step);
    if (f < 0) continue;
    EXPECT_EQ(f, frames) << step;
    EXPECT_EQ(step, f == 0 ? 0 : 4 * (f + 1));
    ++frames;
  }
  EXPECT_EQ(frames, 6);
  // the schedule moves every target to frame f at step 4 f and interpolates over 4 steps
  ASSERT_FALSE(s.schedule.empty());
  EXPECT_EQ(s.schedule.front().step, 4);
  EXPECT_EQ(s.params.interpolation_steps, 4);
}

// The issue's case: a figure under gravity on its floor, followed at 120 fps for 61 frames. On
// the defaults it stands: the floor carries the feet and the points the rest, so no followed
// point sags by more than the share of the weight the defaults are sized for, a few times
// kFollowSag. (The engine's own defaults, dt 0.05 and control_k 10 N/m: a 70 kg figure held by
// six 10 N/m springs sinks until the floor holds it, a residual near a metre.)
TEST(ClipFollow, OnItsDefaultsAFigureUnderGravityStandsOnItsFloor) {
  const Figure fig = figure(61, 1.0 / 120.0);
  FollowOptions o;
  o.gravity = true;
  o.ground = floor_under(fig.rig);
  const Scene s = follow_scene(fig.rig, fig.clip, follow_params(fig.rig, fig.clip, o), o);
  const RunSummary r = run_scene(s);
  ASSERT_FALSE(r.diverged) << r.divergence_reason;
  double worst = 0.0;
  for (double d : r.final_residuals) worst = std::max(worst, d);
  std::cout << "standing figure, 61 frames at 120 fps, gravity and floor: mass "
            << fig.rig.total_mass() << " kg, control_k " << s.params.control_k
            << " N/m, largest final residual " << worst << " rig units\n";
  EXPECT_LT(worst, 3.0 * kFollowSag);

  // the same on the engine's defaults: the heap
  const Scene old = follow_scene(fig.rig, fig.clip, preset_params(kDefaultPreset), o);
  const RunSummary h = run_scene(old);
  double heap = 0.0;
  for (double d : h.final_residuals) heap = std::max(heap, d);
  std::cout << "  on dt 0.05, control_k 10: largest final residual " << heap << "\n";
  EXPECT_GT(heap, 10.0 * worst);
}

TEST(ClipFollow, AFloorHeightThatIsNotAFiniteCoordinateIsRefused) {
  const Figure fig = figure(3, 1.0 / 30.0);
  const double inf = std::numeric_limits<double>::infinity();
  for (double g : {std::nan(""), -inf, inf, -1e10, 2e9}) {
    FollowOptions o;
    o.source = "stand.bvh";
    o.ground = g;
    try {
      follow_scene(fig.rig, fig.clip, follow_params(fig.rig, fig.clip, o), o);
      ADD_FAILURE() << "accepted --ground " << g;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("--ground: the floor's height must be a finite number "
                                           "within +-1e9"),
                std::string::npos)
          << e.what();
    }
  }
  FollowOptions ok;
  ok.ground = -1e9;
  EXPECT_NO_THROW(follow_scene(fig.rig, fig.clip, follow_params(fig.rig, fig.clip, ok), ok));
}

// Frame Time 5e7 s: 6e9 steps a frame at the default dt; the old count overflowed an int into
// "steps": -1294967296 and exited 0
TEST(ClipFollow, ARunLongerThanAnIntCountsIsRefusedNamingTheFrameTime) {
  Figure fig = figure(3, 1.0 / 30.0);
  FollowOptions o;
  o.source = "slow.bvh";
  for (double t : {5e7, 1e300}) {
    fig.clip.frame_time = t;
    try {
      follow_scene(fig.rig, fig.clip, follow_params(fig.rig, fig.clip, o), o);
      ADD_FAILURE() << "accepted Frame Time " << t;
    } catch (const InputError& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find("slow.bvh: field 'Frame Time': "), std::string::npos) << m;
      EXPECT_NE(m.find("more than a run counts (2147483647)"), std::string::npos) << m;
    }
  }
  // at the old dt 0.05 the same clip is 1e9 steps a frame, 3e9 steps: refused too
  fig.clip.frame_time = 5e7;
  EXPECT_THROW(follow_scene(fig.rig, fig.clip, preset_params(kDefaultPreset), o), InputError);
  // one that fits runs as many steps as it says
  fig.clip.frame_time = 1.0;
  const Scene s = follow_scene(fig.rig, fig.clip, follow_params(fig.rig, fig.clip, o), o);
  EXPECT_EQ(s.steps, 3 * 120);
}

// A source skeleton scaled by 1e12: a root that rises 1 cm a frame moves the rig's root 1e12 rig
// units a frame, past the bound every scene coordinate keeps (frame 0, where the root sits at its
// OFFSET, stays at rest). Refused by follow and by a scene whose initial pose is a frame of the
// clip (the old reader took it: runs exited 0, or 4 with null residuals).
TEST(ClipFollow, AClipRootPastTheCoordinateBoundIsRefused) {
  Figure fig = figure(3, 1.0 / 30.0);
  fig.clip = parse_bvh(standing_clip(3, 1.0 / 30.0, 1.0), "stand.bvh");
  fig.rig.source_skeleton.scale = 1e12;
  FollowOptions o;
  o.source = "stand.bvh";
  try {
    follow_scene(fig.rig, fig.clip, follow_params(fig.rig, fig.clip, o), o);
    ADD_FAILURE() << "accepted a root at 1e12";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("stand.bvh: field 'frame': frame 1 puts the rig's root "
                                         "1e+12 rig units out along an axis, past +-1e+09"),
              std::string::npos)
        << e.what();
  }
  o.last = 0;  // frame 0 alone is within the bound
  EXPECT_NO_THROW(follow_scene(fig.rig, fig.clip, follow_params(fig.rig, fig.clip, o), o));

  const std::filesystem::path d = std::filesystem::temp_directory_path() / "physik_clip_follow";
  std::filesystem::create_directories(d);
  const std::string dir = d.string();
  {
    std::ofstream(dir + "/stand.bvh") << standing_clip(3, 1.0 / 30.0, 1.0);
    std::ofstream(dir + "/rig.json") << rig_to_json(fig.rig).dump();
    std::ofstream(dir + "/scene.json")
        << R"({"rig": "rig.json", "steps": 5, "initial_pose": {"bvh": "stand.bvh", "frame": 2}})";
  }
  try {
    load_scene(dir + "/scene.json");
    ADD_FAILURE() << "accepted an initial pose at 2e12";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("scene.json: initial_pose: field 'frame': frame 2 puts "
                                         "the rig's root 2e+12 rig units out"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace physik
