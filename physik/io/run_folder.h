// A run folder: one run of one scene, written so that it stands alone. `physik simulate --out DIR`
// writes one, `simulate --reference` writes another for the reference run (DIR/mujoco), the
// experiments leave theirs for the report's viewers, and `physik view` reads them.
//
//   scene.json               the scene as run (overrides applied, the rig inline; scene_io.h)
//   trajectory.csv           the trajectory table (recorder.h): step 0, every N-th step, the last
//   targets_and_limits.csv   targets and joint-limit excess, the same rows (targets_limits.h)
//   summary.json             the run's summary (summary_io.h), with what the writer adds
//   final_pose.csv           the final pose as a bones table (pose_io.h)
//   contacts.csv             the PhysIK engine's contacts, the same rows (contacts_table.h); only
//                            for a scene with a ground or self-collision, and only from the
//                            engine's runs (MuJoCo resolves its contacts itself: its run folder
//                            has none)
//
// A pose folder is the same for one pose that no run produced (an IK solver's answer): a
// trajectory of one row at step 0, time 0, with no motion (kinetic energy, passes and joint
// mismatch 0), its summary.json saying "kind": "pose".
#pragma once

#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "physik/io/recorder.h"

namespace physik {

inline constexpr const char* kSceneFile = "scene.json";
inline constexpr const char* kTrajectoryFile = "trajectory.csv";
inline constexpr const char* kSummaryFile = "summary.json";
inline constexpr const char* kFinalPoseFile = "final_pose.csv";

class RunFolderWriter {
 public:
  // Creates `dir` and writes scene.json, then opens both tables; a path that cannot be written
  // is an InputError naming `option` (the command-line option that named the folder).
  RunFolderWriter(const Scene& scene, const std::string& dir, const std::string& option);

  // Recorder options that write both tables: a row every `every` steps, the initial state and
  // the scene's last step.
  RecordOptions record_options(int every);
  // The same, and, when the scene has a ground or self-collision, contacts.csv of the state's
  // contacts (SimState::contacts: the PhysIK engine's; a scene without either gets no file).
  RecordOptions engine_record_options(int every);
  // summary.json and final_pose.csv; the tables are closed first.
  void finish(const nlohmann::json& summary, const BoneFrames& final_frames);

  const std::string& dir() const { return dir_; }

 private:
  const Scene& scene_;
  std::string dir_, option_;
  std::ofstream trajectory_, targets_limits_, contacts_;
};

// `physik simulate`'s run: the PhysIK engine on `scene` into a run folder (a trajectory row
// every `every` steps); `also` (if given) sees every step after it. Returns the run's summary.
RunSummary simulate_into_folder(const Scene& scene, const std::string& dir, int every,
                                const StepObserver& also = nullptr,
                                const std::string& option = "--out");

// A pose folder for `frames`, a pose of the scene's rig; `summary` is summary.json (its "kind"
// is set to "pose").
void write_pose_folder(const Scene& scene, const std::string& dir, const BoneFrames& frames,
                       nlohmann::json summary);

}  // namespace physik
