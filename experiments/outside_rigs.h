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

#include "physik/model/kinematics.h"
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
// the rig of MuJoCo's arm26 (its shoulder hinged to the world)
constexpr const char* kArm26 = "tendon_arm-arm26";

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

// What a run or a solve did to the rig's own body, the largest over every step (a step whose
// frames are not finite is left out; a diverged run's last finite steps count):
//   weld_turn   rad, of any welded bone against its rest frame in the frame of the bone it is
//               welded to (experiments/weld_turn.h): 0 while every welded group moves as one rigid
//               body
//   root_turn   rad, the same over the root's body alone (a BVH's pelvis: its root's segments)
//   root_drift  rig units, the root's head from its rest position (0 for a pinned or fixed root)
struct BodyMeasure {
  double weld_turn = 0.0;
  double root_turn = 0.0;
  double root_drift = 0.0;
  void observe(const Rig& rig, const BoneFrames& frames);
  void add(const BodyMeasure& other);  // the larger of each
};

struct RunResult {
  Outcome outcome = Outcome::kRefused;
  std::string preset;          // the preset the loaded scene took ("" when refused at load)
  int steps_to_converge = -1;  // -1 unless converged
  int steps_run = 0;
  double max_residual = 0.0;  // rig units, largest final residual (last finite state)
  double damping = 0.0;       // N s/m the run used (damping auto's last choice when auto)
  double wall_s = 0.0;        // s, loading the scene and running it
  std::string refusal;        // the InputError's message when refused
  BodyMeasure body;           // over every step (nothing when refused)
};
// Load the scene file with the configuration's overrides and run it, as `physik simulate SCENE
// --set ...` does. An InputError while loading or running (the scene refused) is the outcome
// kRefused, its message kept; any other error propagates.
RunResult run_configuration(const std::string& scene_path, const Configuration& config);

// Load the scene file and solve it as `physik solve SCENE --solver physik` does (the engine's
// solve mode, physik/posing/scene_solve.h), measuring the body over every physics step. The
// outcome is the solve's: converged within its tolerance, not (stalled or out of steps),
// diverged, or refused (the InputError's message kept).
RunResult solve_configuration(const std::string& scene_path);

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

// --- the rig's own body: the checks of one rig, converted from a MuJoCo model or a BVH

// The same rig with its root free, the limits it had against the world dropped (a free root
// holds against nothing): the root as the converters left it before an anchored root existed.
Rig with_free_root(const Rig& rig);

constexpr int kRestSteps = 100;  // steps of the rest check

struct RigChecks {
  std::string name;
  std::string source;  // "mjcf" or "bvh"
  const Rig* rig = nullptr;
  int bodies = 0;  // rigid bodies (a bone that is not welded starts one)
  int welded = 0;  // welded bones
  // over the default configuration's runs of its scenes (simulate) and their solves (solve mode)
  BodyMeasure run, solve;
  int runs = 0, solves = 0;  // that ran (not refused)
  int runs_converged = 0, solves_converged = 0;
  // J, the largest kinetic energy over kRestSteps steps at rest, no targets, no gravity,
  // self_collision on: gauss-seidel (preset original), exact, implicit (preset robust)
  double rest_ke_gauss_seidel = 0.0, rest_ke_exact = 0.0, rest_ke_implicit = 0.0;
  int rest_overlaps = 0;                      // bone pairs whose capsules overlap at rest
  int open_overlaps = 0;                      // those not excluded
  double radius_min = 0.0, radius_max = 0.0;  // rig units, the bones' (inertia) radii
  double collision_radius_min = 0.0, collision_radius_max = 0.0;  // rig units
};

// The structural and rest parts of the checks (bodies, welds, the rest check in every scheme,
// the rest overlaps, radii); the run and solve parts are the caller's.
RigChecks check_rig(const std::string& name, const std::string& source, const Rig& rig);

// The motion-capture skeleton of experiments/mocap_bvh.h converted as `physik rig from-bvh FILE
// --scale 0.01` converts it (Y up, centimetres): written to `path`, then loaded from there.
struct MocapRig {
  Rig rig;
  std::vector<int> pelvis;       // the bones that follow its root joint (the synthetic root and the
                                 // root's segments)
  bool pelvis_one_body = false;  // every one of them in one rigid body
};
MocapRig convert_mocap(const std::string& path);

}  // namespace physik::experiments::outside_rigs
