// The outside_rigs experiment's pieces (experiments/outside_rigs.cpp), apart so its test can
// check them: rigs from outside the project (MuJoCo's sample models through the MJCF importer,
// reference/mjcf_import.h), the rule that places a user's targets on them, and one run of a
// scene under a named configuration with its outcome.
//
// The target rule (one fixed rule for every rig, never tuned per rig or configuration):
//   size      the largest extent of the rest pose's bounding box over x, y and z (heads and
//             tails), rig units: the rig's height for a standing rig; many converted models lie
//             flat, where the height along z would be 0
//   point 1   the tail of the leaf bone (no children) whose rest tail is farthest from the root
//             bone's head, its target moved by kTargetFraction x size along kFirstDirection
//   point 2   the tail of the leaf farthest from point 1's rest tail, moved by the same fraction
//             along kSecondDirection; a rig with one leaf has no second leaf, and its second
//             point holds the root bone's head where it is at rest (a pin)
// Ties go to the first bone in the rig's depth-first order.
#pragma once

#include <array>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "physik/model/rig.h"
#include "physik/model/types.h"

namespace physik::experiments::outside_rigs {

// where Debian's libmujoco-samples puts MuJoCo's sample models
constexpr const char* kSamplesDir = "/usr/share/mujoco/model";
constexpr double kTargetFraction = 0.25;                    // 1, of the rig size
const Vec3 kFirstDirection = Vec3(1, 0, 1).normalized();    // out and up (MuJoCo is z-up)
const Vec3 kSecondDirection = Vec3(-1, 0, 1).normalized();  // the other way out, and up
constexpr int kStepCap = 2000;      // steps a run may take (stops once converged)
constexpr int kQuickStepCap = 500;  // the quick context's
// the quick context's models, under kSamplesDir: a chain, a pair of files with one humanoid (the
// second is its duplicate), small arms
constexpr std::array<const char*, 5> kQuickFiles = {
    "composite/rope.xml", "hammock/humanoid_body.xml", "humanoid/humanoid.xml", "mug/mug.xml",
    "tendon_arm/arm26.xml"};

// rig units, the largest extent of the rest pose's bounding box (see the rule above)
double rig_size(const Rig& rig);

// One control point of the rule: on `bone` at `alpha` (0 head, 1 tail), pulled to target_world.
struct Pick {
  int bone = -1;
  double alpha = 1.0;
  Vec3 target_world = Vec3::Zero();
};
// The rule's first `points` (1 or 2) control points on the rig.
std::vector<Pick> pick_targets(const Rig& rig, int points);

// The scene file of a rig and its picks: the rig by path (relative to the scene file), the
// control points by bone name, `steps` at most and stop once converged; no "params" object, so
// it takes the engine's default preset.
nlohmann::json scene_json(const std::string& rig_path, const Rig& rig,
                          const std::vector<Pick>& picks, int steps);

// A configuration: a name and the `--set` assignments that make it (none: the default).
struct Configuration {
  std::string name;
  std::vector<std::string> sets;
};
// default, original, implicit-auto-axes, implicit-auto-gradient
const std::vector<Configuration>& configurations();

enum class Outcome { kConverged, kNotConverged, kDiverged, kRefused };
const char* to_string(Outcome o);  // converged, not_converged, diverged, refused

struct RunResult {
  Outcome outcome = Outcome::kRefused;
  std::string preset;          // the preset the loaded scene took ("" when refused at load)
  int steps_to_converge = -1;  // -1 unless converged
  int steps_run = 0;
  double max_residual = 0.0;  // rig units, largest final residual (last finite state)
  double damping = 0.0;       // N s/m the run used (damping auto's last choice when auto)
  double wall_s = 0.0;        // s, loading the scene and running it
  std::string refusal;        // the InputError's message when refused
};
// Load the scene file with the configuration's overrides and run it, as `physik simulate SCENE
// --set ...` does. An InputError while loading or running (the scene refused) is the outcome
// kRefused, its message kept; any other error propagates.
RunResult run_configuration(const std::string& scene_path, const Configuration& config);

// The same rig up to bone names and a rigid translation: equal bone counts and parents, and
// every bone's head offset in its parent, rest orientation, length, mass, radius, inertia and
// limits equal within 1e-9 (relative). MuJoCo's samples ship one humanoid in six files.
bool same_rig(const Rig& a, const Rig& b);

// A converted sample model, or a file that gave none.
struct OutsideRig {
  std::string name;  // "<folder>-<file stem>", e.g. "humanoid-humanoid"
  std::string file;  // the MJCF file
  Rig rig;
};
struct Skipped {
  std::string file;
  std::string reason;
};
struct Collection {
  std::vector<OutsideRig> rigs;
  std::vector<Skipped> skipped;
};
// Every *.xml under `dir`, recursively, in path order. Throws std::runtime_error naming `dir` when
// it is not a folder.
std::vector<std::string> sample_files(const std::string& dir);
// The files through load_mjcf, in the order given: a file MuJoCo or the importer refuses is
// skipped with its message; a rig the same as an earlier one (same_rig) is skipped as its
// duplicate.
Collection collect_rigs(const std::vector<std::string>& files);

}  // namespace physik::experiments::outside_rigs
