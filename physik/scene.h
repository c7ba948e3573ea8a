// Scenes: a rig, engine parameters, control points, a schedule of target changes, and how long
// to run. The JSON format is documented in models/README.md ("Scenes").
#pragma once

#include <string>
#include <vector>

#include "physik/json_fields.h"
#include "physik/kinematics.h"
#include "physik/params.h"
#include "physik/rig.h"

namespace physik {

// A point fixed on a bone, pulled toward a target by a zero-rest-length spring:
//   linear  F = k (t - a)
//   capped  F = k min(|t - a|, c) (t - a)/|t - a|
// (paper Sec. 3.3; the original hard-codes c = 1). Forces in N, positions in rig units.
struct ControlPoint {
  std::string name;            // optional label
  int bone = -1;               // index into the rig
  double alpha = 1.0;          // position along the bone: 0 = head, 1 = tail
  Vec3 target_world = Vec3::Zero();
  SpringLaw spring = SpringLaw::kLinear;
  double k = 10.0;             // N/m
  double cap = 1.0;            // rig units
};

// At `step`, control point `control_point` gets a new target (interpolated per the params).
struct TargetChange {
  int step = 0;
  int control_point = 0;
  Vec3 target_world = Vec3::Zero();
};

struct ConvergenceParams {
  double residual_tol = 0.0;   // rig units; 0 = 1e-3 of the rig's height. Reported, and a run
                               // whose final residuals exceed it is "converged" only if at rest
  double speed_tol = 0.0;      // rig units/s; 0 = 1e-3 of the rig's height per second.
                               // at rest when sqrt(2 KE / total mass) is below this
  int settle_steps = 10;       // consecutive steps at rest to call the run converged
  bool stop_when_converged = false;
  bool stop_at_residual_tol = false;  // IK use: converged = every control point within
                                      // residual_tol; stop there, or at rest short of it
  double divergence_energy = 0.0;  // J; 0 = 1e6 * total mass * height^2. Above it: diverged
};

struct Scene {
  std::string file;            // where it came from ("" if built in code)
  std::string rig_file;        // resolved rig path
  Rig rig;
  EngineParams params;
  std::vector<ControlPoint> control_points;
  std::vector<TargetChange> schedule;  // sorted by step
  int steps = 200;
  ConvergenceParams convergence;
  Pose initial_pose;
  Vec3 initial_velocity_world = Vec3::Zero();  // rig units/s, a rigid translation of every bone

  double residual_tol() const;
  double speed_tol() const;
  double divergence_energy() const;
};

// Load and validate a scene file. Errors name the file, the element and the field.
Scene load_scene(const std::string& path);
// The same, with parameter overrides merged into the file's "params" before it is parsed, so
// control points that take their spring, k and cap from the params see the overrides too. A
// "preset" override swaps the base preset; the file's other params still apply on top of it.
Scene load_scene(const std::string& path, const nlohmann::json& param_overrides);
// "key=value" strings (values parsed as JSON, else taken as a string) into an overrides object;
// unknown keys are an InputError naming `source` (e.g. "--set").
nlohmann::json parse_param_overrides(const std::vector<std::string>& assignments,
                                     const std::string& source);
// Parse a scene from JSON; relative rig paths resolve against `base_dir`.
Scene scene_from_json(const nlohmann::json& doc, const std::string& source,
                      const std::string& base_dir);
// Apply "params" overrides on top of `base` (shared with the tuner).
EngineParams params_from_json(const nlohmann::json& params, const std::string& source);
nlohmann::json params_to_json(const EngineParams& p);
// The scene back to JSON (rig given by its path), e.g. for a tuned scene.
nlohmann::json scene_to_json(const Scene& scene);

}  // namespace physik
