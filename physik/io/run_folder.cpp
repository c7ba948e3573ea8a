// Run folders (run_folder.h): the writer shared by `physik simulate`, the reference run and
// the experiments, and pose folders for one pose.
#include "physik/io/run_folder.h"

#include <filesystem>
#include <system_error>

#include "physik/engine/engine.h"
#include "physik/io/json_fields.h"
#include "physik/io/output_files.h"
#include "physik/io/pose_io.h"
#include "physik/io/rig_io.h"
#include "physik/io/scene_io.h"
#include "physik/io/summary_io.h"
#include "physik/model/errors.h"

namespace physik {

namespace {

// `path` removed if it is there (a file, or a folder that is empty); InputError naming `option`
// when it cannot be (a folder that is not empty is kept: it holds the user's files)
void remove_owned(const std::filesystem::path& path, const std::string& option) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::exists(fs::symlink_status(path, ec))) return;
  if (fs::is_directory(fs::symlink_status(path, ec)) && !fs::is_empty(path, ec)) return;
  fs::remove(path, ec);
  if (ec) {
    throw_input_error(path.string(), "", option,
                      "cannot remove the earlier run's file (" + ec.message() + ")");
  }
}

// The rig as its file gave it: the rig file's document, or the scene file's inline "rig" object,
// when that document builds the scene's rig exactly (rig_to_json of both equal: the run did not
// change the rig after loading it); null otherwise. Written into scene.json, it makes a rerun of
// scene.json the same run bit for bit: rig_to_json writes each rest frame as the matrix of the
// rig's quaternion, and reading that matrix back (a quaternion again, normalised, its y axis
// folded onto the bone) lands an ulp or so away (a reread rig differed by 4e-16 in its rest
// frames, and the run's final_state_hash with it).
nlohmann::json rig_as_read(const Scene& scene) {
  try {
    nlohmann::json doc;
    if (!scene.rig_file.empty()) {
      doc = read_json_file(scene.rig_file);
    } else if (!scene.file.empty()) {
      const nlohmann::json top = read_json_file(scene.file);
      if (top.is_object() && top.contains("rig") && top["rig"].is_object()) doc = top["rig"];
    }
    if (doc.is_object() && rig_to_json(rig_from_json(doc, "rig")) == rig_to_json(scene.rig)) {
      return doc;
    }
  } catch (const std::exception&) {
    // a file that changed or went since the scene was read: the rig as the writer writes it
  }
  return nullptr;
}

}  // namespace

void clear_run_folder(const std::string& dir, const std::string& option,
                      const std::vector<std::string>& also_files,
                      const std::vector<std::string>& also_folders) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::is_regular_file(fs::path(dir) / kSummaryFile, ec)) return;  // not a run folder
  for (const char* name : {kSceneFile, kTrajectoryFile, kTargetsLimitsFile, kSummaryFile,
                           kFinalPoseFile, kContactsFile}) {
    remove_owned(fs::path(dir) / name, option);
  }
  for (const std::string& name : also_files) remove_owned(fs::path(dir) / name, option);
  for (const std::string& name : also_folders) {
    const fs::path sub = fs::path(dir) / name;
    if (!fs::is_directory(fs::symlink_status(sub, ec))) continue;  // a file of that name: kept
    clear_run_folder(sub.string(), option);
    remove_owned(sub, option);
  }
}

RunFolderWriter::RunFolderWriter(const Scene& scene, const std::string& dir,
                                 const std::string& option)
    : scene_(scene), dir_(dir), option_(option) {
  create_output_dir(dir, option);
  nlohmann::json doc = scene_to_json(scene, /*rig_inline=*/true);
  doc["params"] = params_as_run_json(scene);  // as summary.json: every row the run reads
  const nlohmann::json rig = rig_as_read(scene);
  if (!rig.is_null()) doc["rig"] = rig;  // the rig's own numbers: a rerun is the same run
  write_json(doc, dir + "/" + kSceneFile);
  trajectory_ = open_output_file(dir + "/" + kTrajectoryFile, option);
  targets_limits_ = open_output_file(dir + "/" + kTargetsLimitsFile, option);
}

RecordOptions RunFolderWriter::record_options(int every) {
  RecordOptions o;
  o.csv_stream = &trajectory_;
  o.targets_limits_stream = &targets_limits_;
  o.csv_every = every;
  o.csv_rows = RowRule::kEveryAndLast;
  return o;
}

RecordOptions RunFolderWriter::engine_record_options(int every) {
  RecordOptions o = record_options(every);
  if (scene_.collision.any()) {
    contacts_ = open_output_file(dir_ + "/" + kContactsFile, option_);
    o.contacts_stream = &contacts_;
  }
  return o;
}

void RunFolderWriter::finish(const nlohmann::json& summary, const BoneFrames& final_frames) {
  trajectory_.close();
  targets_limits_.close();
  if (contacts_.is_open()) contacts_.close();
  write_json(summary, dir_ + "/" + kSummaryFile);
  std::ofstream pose = open_output_file(dir_ + "/" + kFinalPoseFile, option_);
  write_bones_csv(scene_.rig, final_frames, pose);
}

RunSummary simulate_into_folder(const Scene& scene, const std::string& dir, int every,
                                const StepObserver& also, const std::string& option) {
  RunFolderWriter folder(scene, dir, option);
  RecordedRun run = record_run(scene, folder.engine_record_options(every), also);
  folder.finish(summary_to_json(scene, run.summary), run.summary.final_frames);
  return std::move(run.summary);
}

void write_pose_folder(const Scene& scene, const std::string& dir, const BoneFrames& frames,
                       nlohmann::json summary) {
  RunFolderWriter folder(scene, dir, "--out");
  // the pose as a state at rest at step 0: its residuals, targets and joint angles are real,
  // its velocities (and so its kinetic energy and joint mismatch) zero; the targets are the
  // goals (a pose has no interpolation under way)
  SimState s;
  init_state(scene, s);
  s.target_effective_world = s.target_goal_world;
  s.frames = frames;
  local_rotations_from_world(scene.rig, frames, s.pose);
  StepStats st;
  st.joint_separation = max_joint_separation(scene.rig, frames);
  std::vector<double> residuals;
  control_residuals(scene, s, residuals);
  {
    RecordOptions o = folder.record_options(1);
    TrajectoryCsv table(scene, *o.csv_stream, 1, RowRule::kEveryAndLast);
    TargetsLimitsCsv extra(scene, *o.targets_limits_stream);
    if (table.write_row(s, st, residuals)) extra.write_row(s);
  }
  summary["kind"] = "pose";
  folder.finish(summary, frames);
}

}  // namespace physik
