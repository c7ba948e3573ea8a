// Shared tools for the experiments: the scenes, the pose measures several figures use (secondary
// motion), the report's settings and number format. Runs are recorded with
// physik/io/recorder.h, reports built with experiments/report.h.
#pragma once

#include <random>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "experiments/experiment.h"
#include "experiments/report.h"
#include "physik/engine/engine.h"
#include "physik/io/json_fields.h"
#include "physik/io/recorder.h"
#include "physik/model/scaled_scene.h"

namespace physik::experiments {

// The experiments' trajectory table (recorder.h): a row every `every` steps and at step 1.
RecordOptions trajectory_table(const std::string& path, int every = 1);

// A run folder of `scene` (physik/io/run_folder.h) at <out>/runs/<name>, for `physik view` and
// the report's viewers: the scene run again (runs are deterministic: the same run), a trajectory
// row every run_folder_every(scene) steps; <out>/runs/order.txt lists the folders in the order
// written.
RunSummary write_run_folder(const Context& ctx, const std::string& name, const Scene& scene);
// ceil(steps / 600): at most ~600 frames a run, so a report page stays small
int run_folder_every(const Scene& scene);
// A pose folder (one pose that no run produced, e.g. an IK solver's) at <out>/runs/<name>;
// `summary` is its summary.json.
void write_pose_run_folder(const Context& ctx, const std::string& name, const Scene& scene,
                           const BoneFrames& frames, const nlohmann::json& summary);
// <out>/runs/<name>, listed in <out>/runs/order.txt (for writers of other run folders).
std::string run_folder_path(const Context& ctx, const std::string& name);

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
nlohmann::json settings_json(const Scene& scene,
                             const nlohmann::json& extra = nlohmann::json::object());

// Format a double with a fixed number of significant digits.
std::string num(double v, int digits = 3);

// A claim row as JSON {claim, measured, holds} (for reports assembled by hand; Report::claim
// builds the same row); `holds` a verdict (report.h check_verdict).
nlohmann::json claim(const std::string& text, const std::string& measured,
                     const std::string& holds);

// A uniformly random unit vector.
Vec3 random_direction(std::mt19937& rng);

// A random pose within the rig's limits: each limited axis of a non-root bone uniform in its
// range, every other axis uniform in [-1, 1] rad (a rotation vector per bone).
Pose random_legal_pose(const Rig& rig, std::mt19937& rng);

// The engine as an IK solver on one effector (ik_comparison, linearisation): control point 0 on
// `bone`'s tail, its target at the rest tail until moved; control point 1 pins the root's head
// (PhysIK's root is free). Preset original (the paper's scheme), from the rest pose; with
// solve_mode the solve mode's engine (posing_session.h use_solve_mode: implicit, the gradient
// torsion torque).
Scene effector_scene(const std::string& file, const Rig& rig, int bone, bool solve_mode);

}  // namespace physik::experiments
