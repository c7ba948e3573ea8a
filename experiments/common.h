// Shared tools for the experiments: run a scene while recording a trajectory table and pose
// frames, and the pose measures several figures use (secondary motion, joint angles).
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "experiments/experiment.h"
#include "physik/engine/engine.h"

namespace physik::experiments {

struct RecordedRun {
  RunSummary summary;
  std::vector<int> frame_steps;      // steps whose poses were saved as frames
  std::vector<BoneFrames> frames;    // the poses at those steps
  std::vector<double> kinetic_energy;  // per step (index = step - 1)
  std::vector<int> passes;             // per step
  std::vector<std::vector<double>> residuals;  // per step, per control point (to the goal)
  std::vector<Pose> poses;             // per step when keep_poses, else empty
};

struct RecordOptions {
  std::string csv_path;          // per-step table (trajectory format of `physik simulate`); "" = none
  int csv_every = 1;             // a row every N steps
  std::vector<int> frame_steps;  // steps to save full poses for (0 = the initial pose)
  bool keep_poses = false;       // keep every step's local pose (for secondary-motion measures)
};

// Run a scene, recording what the options ask for. Writes the CSV if a path is given.
RecordedRun run_recorded(const Scene& scene, const RecordOptions& opt);

// Write a bones table (physik/pose_io.h) for each recorded frame: <prefix><step>.csv.
// Returns the file names (relative to the folder of the prefix).
std::vector<std::string> write_frames(const Scene& scene, const RecordedRun& run,
                                      const std::string& folder, const std::string& prefix);

// Scene loaded from models/scenes/<name>.json of the context.
Scene scene_named(const Context& ctx, const std::string& name);

// Total rotation (rad) of the bones NOT in `controlled` between two poses: the sum over those
// bones of the angle of their world-orientation change. A secondary-motion measure: how much the
// rest of the body moved to accommodate the controlled chain.
double off_chain_rotation(const Rig& rig, const BoneFrames& a, const BoneFrames& b,
                          const std::vector<int>& controlled);

// Bones from each given bone up to the root (inclusive): the chains the control points drive.
std::vector<int> chains_to_root(const Rig& rig, const std::vector<int>& bones);

// The engine settings a report states (dt, damping, control k, torsion k, eps, interpolation,
// steps), with `extra` fields added or overriding.
nlohmann::json settings_json(const Scene& scene, const nlohmann::json& extra = nlohmann::json::object());

// The scene on a rig scaled by s about the origin (heads, tails, radii, targets, caps, root start)
// with every bone's mass density x length; torsion k scaled like the inertia (density x s^3)
// when asked. k and dt stay as given. (The tuning study's 0.1x / 10x rigs.)
Scene scaled_scene(const Scene& base, double s, double density, bool scale_torsion);

// A claim row for the report.
nlohmann::json claim(const std::string& text, const std::string& measured, const std::string& holds);

// Format a double with a fixed number of significant digits.
std::string num(double v, int digits = 3);

}  // namespace physik::experiments
