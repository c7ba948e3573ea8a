// PhysIK against the MuJoCo reference on one scene: both runs from the same initial pose, and the
// gap between them (docs/engine.md "MuJoCo as the reference").
//
// Metrics (rig units; endpoints = every bone's head and tail, world frame):
//   per step k,  g_k  = the largest endpoint distance between the two runs
//   rms_gap      = sqrt(mean over steps and endpoints of the squared endpoint distance)
//   max_gap      = max_k g_k
//   final_pose_gap = the largest endpoint distance between the two final poses
//                (final_pose_rms_gap: the rms over endpoints)
// Steps are compared while both runs last (a run stops early when it diverges, or when the scene
// stops at convergence). Whether the final gap measures the joint-force heuristic or path
// dependence depends on the equilibrium being unique: with J_c the Jacobian of every control
// point's position and J_e that of every bone endpoint (MuJoCo's mj_jac, rig-joint model at
// MuJoCo's final pose), the endpoints are locally fixed by the control points iff
//   free_endpoint_dof = rank([J_c; J_e]) - rank(J_c) = 0
// (rolls about a bone's own axis move no endpoint and do not count). Otherwise the equilibrium is
// a family and the final gap measures path dependence.
// The free-rods scheme is run too (PhysIK with free_rods true), for its joint separation
// and its own gap to MuJoCo.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "physik/io/recorder.h"
#include "reference/mujoco_runner.h"

namespace physik {

// "mujoco" (= same-forces), "mujoco:same-forces", "mujoco:exact-constraints". Throws InputError
// naming `source` otherwise.
ReferenceMode parse_reference_spec(const std::string& spec,
                                   const std::string& source = "--reference");

struct GapStats {
  int steps_compared = 0;
  double rms_gap = 0.0;         // rig units
  double max_gap = 0.0;         // rig units
  double final_pose_gap = 0.0;  // rig units, max over endpoints
  double final_pose_rms_gap = 0.0;
};

// Largest endpoint distance between two poses of the same rig.
double pose_gap(const BoneFrames& a, const BoneFrames& b);
// Gap over two per-step trajectories (index k = after step k + 1) and their final poses.
GapStats trajectory_gap(const std::vector<BoneFrames>& a, const std::vector<BoneFrames>& b,
                        const BoneFrames& final_a, const BoneFrames& final_b);

// Endpoint degrees of freedom the control points leave free at a pose (see above).
int free_endpoint_dof(const Scene& scene, const BoneFrames& frames);

struct Comparison {
  ReferenceMode mode = ReferenceMode::kSameForces;
  RecordedRun physik, mujoco, free_rods;  // each with its frames after every step
  GapStats gap;                           // PhysIK (the scene's integration) vs MuJoCo
  GapStats free_rods_gap;                 // PhysIK free-rods vs MuJoCo
  int free_endpoint_dof = 0;              // at MuJoCo's final pose
};

// MuJoCo's run of a scene (run_mujoco) with a recorder (physik/io/recorder.h); `also` (if given)
// sees every step after it.
RecordedRun record_mujoco(const Scene& scene, ReferenceMode mode, const RecordOptions& options,
                          const StepObserver& also = nullptr);
// The three runs and their gaps. `mujoco_record`: what else to record of the MuJoCo run (e.g.
// its trajectory table); every run keeps its frames after every step regardless.
Comparison compare_with_mujoco(const Scene& scene, ReferenceMode mode,
                               const RecordOptions& mujoco_record = {});

// The runs that diverged: "physik", "mujoco" (empty when neither did).
std::vector<std::string> diverged_runs(const Comparison& c);

// comparison.json: the gaps (null when a run diverged: they would measure nothing), "diverged"
// (diverged_runs), each run's summary, the free rods' gap.
nlohmann::json comparison_to_json(const Scene& scene, const Comparison& c);

// MuJoCo's run of `scene` as a run folder at `dir` (physik/io/run_folder.h), a trajectory row
// every `every` steps; its summary.json names the engine and the mode. Returns the summary.
RunSummary write_reference_run_folder(const Scene& scene, ReferenceMode mode,
                                      const std::string& dir, int every);

// The reference run's folder under `simulate --reference`'s output folder.
inline constexpr const char* kReferenceFolder = "mujoco";
inline constexpr const char* kComparisonFile = "comparison.json";

// The `simulate --reference` output: the MuJoCo run as a run folder of its own,
// <out>/mujoco (physik/io/run_folder.h: scene.json, trajectory.csv, targets_and_limits.csv,
// summary.json with the engine and mode, final_pose.csv), and <out>/comparison.json.
// Returns comparison.json's content; its "diverged" lists the runs that diverged.
nlohmann::json write_reference_comparison(const Scene& scene, const std::string& spec,
                                          const std::string& out_dir, int every, bool verbose);

}  // namespace physik
