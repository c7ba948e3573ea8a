// A run folder: one run of one scene, written so that it stands alone. `physik simulate --out DIR`
// writes one, `simulate --reference` writes another for the reference run (DIR/mujoco), the
// experiments leave theirs for the report's viewers, and `physik view` reads them.
//
//   scene.json               the scene as run (overrides applied, the rig inline, every
//                            parameter the run reads at its value: params_as_run_json, scene_io.h);
//                            the rig as its file gave it when that is the rig the run used (so
//                            that `physik simulate DIR/scene.json` reruns the run bit for bit)
//   trajectory.csv           the trajectory table (recorder.h): step 0, every N-th step, the last
//   targets_and_limits.csv   targets and joint-limit excess, the same rows (targets_limits.h)
//   summary.json             the run's summary (summary_io.h), with what the writer adds
//   final_pose.csv           the final pose as a bones table (pose_io.h)
//   contacts.csv             the PhysIK engine's contacts, the same rows (contacts_table.h); only
//                            for a scene with a ground or self-collision, and only from the
//                            engine's runs (MuJoCo resolves its contacts itself: its run folder
//                            has none)
//
// A folder that held an earlier run: `physik simulate` first clears it (clear_run_folder) of the
// files a run folder's writers own (the names above, and what its caller adds: `--reference`'s
// mujoco/ and comparison.json), so that a run without a reference leaves none of the last
// run's. Only those names go, and only from a folder that is a run folder (it holds a
// summary.json, the file a run writes last); any other file or folder in it is the user's and
// stays, and a folder without a summary.json (not a run folder, or a run that stopped before its
// end) has only the files the new run writes overwritten.
//
// A pose folder is the same for one pose that no run produced (an IK solver's answer): a
// trajectory of one row at step 0, time 0, with no motion (kinetic energy, passes and joint
// mismatch 0), its summary.json saying "kind": "pose".
#pragma once

#include <fstream>
#include <string>
#include <vector>

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

// Removes from `dir`, if it is a run folder (above), its own files (the names above), the
// `also_files` and the `also_folders`: each such folder is cleared by the same rule and removed
// when it is then empty (one that holds a file of the user's stays, with that file). A missing
// `dir` is nothing to clear; a name that cannot be removed is an InputError naming `option`.
void clear_run_folder(const std::string& dir, const std::string& option,
                      const std::vector<std::string>& also_files = {},
                      const std::vector<std::string>& also_folders = {});

// A pose folder for `frames`, a pose of the scene's rig; `summary` is summary.json (its "kind"
// is set to "pose").
void write_pose_folder(const Scene& scene, const std::string& dir, const BoneFrames& frames,
                       nlohmann::json summary);

}  // namespace physik
