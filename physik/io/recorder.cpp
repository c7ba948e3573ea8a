#include "physik/io/recorder.h"

#include <algorithm>
#include <cmath>
#include <iomanip>

#include "physik/engine/engine.h"
#include "physik/io/pose_io.h"
#include "physik/model/errors.h"
#include "physik/model/unique_names.h"

namespace physik {

std::vector<std::string> residual_column_names(const Scene& scene) {
  UniqueNames taken;
  std::vector<std::string> names;
  for (std::size_t c = 0; c < scene.control_points.size(); ++c) {
    const std::string& name = scene.control_points[c].name;
    names.push_back(csv_field(taken.make("residual_" + (name.empty() ? std::to_string(c) : name))));
  }
  return names;
}

TrajectoryCsv::TrajectoryCsv(const Scene& scene, std::ostream& out, int every, RowRule rule)
    : out_(out), every_(std::max(1, every)), rule_(rule), last_step_(scene.steps) {
  out_ << "step,time,kinetic_energy,passes,joint_mismatch,joint_separation";
  for (const std::string& name : residual_column_names(scene)) out_ << "," << name;
  for (const std::string& name : bone_column_names(scene.rig)) out_ << "," << name;
  out_ << "\n" << std::setprecision(9);
  row_.reserve(3 + scene.control_points.size() + 6 * scene.rig.nbone);
}

bool TrajectoryCsv::wants(int step) const {
  if (step % every_ == 0) return true;  // step 0, the initial state, among them
  return rule_ == RowRule::kEveryAndLast ? step == last_step_ : step == 1;
}

bool TrajectoryCsv::write_row(const SimState& s, const StepStats& st,
                              const std::vector<double>& residuals) {
  // the doubles of the row after step and time, in column order (passes is an int, not stored)
  row_.clear();
  row_.push_back(st.kinetic_energy);
  row_.push_back(st.mismatch);
  row_.push_back(st.joint_separation);
  row_.insert(row_.end(), residuals.begin(), residuals.end());
  append_bone_values(s.frames, row_);
  if (!std::isfinite(s.time) ||
      !std::all_of(row_.begin(), row_.end(), [](double v) { return std::isfinite(v); })) {
    return false;
  }
  out_ << s.step << "," << s.time << "," << row_[0] << "," << st.iterations() << "," << row_[1]
       << "," << row_[2];
  for (std::size_t i = 3; i < row_.size(); ++i) out_ << "," << row_[i];
  out_ << "\n";
  return true;
}

Recorder::Recorder(const Scene& scene, RecordOptions options)
    : scene_(scene), opt_(std::move(options)) {
  std::ostream* out = opt_.csv_stream;
  if (!out && !opt_.csv_path.empty()) {
    file_.open(opt_.csv_path);
    if (!file_) throw_input_error(opt_.csv_path, "", "", "cannot write file");
    out = &file_;
  }
  if (out) csv_ = std::make_unique<TrajectoryCsv>(scene, *out, opt_.csv_every, opt_.csv_rows);
  if (csv_ && opt_.targets_limits_stream) {
    targets_limits_ = std::make_unique<TargetsLimitsCsv>(scene, *opt_.targets_limits_stream);
  }
  if (csv_ && opt_.contacts_stream)
    contacts_ = std::make_unique<ContactsCsv>(*opt_.contacts_stream);
  if (!opt_.all_frames &&
      std::find(opt_.frame_steps.begin(), opt_.frame_steps.end(), 0) != opt_.frame_steps.end()) {
    run_.frame_steps.push_back(0);
    run_.frames.push_back(forward_kinematics(scene.rig, scene.initial_pose));
  }
}

StepObserver Recorder::observer() {
  return [this](const SimState& s, const StepStats& st) { observe(s, st); };
}

// the trajectory row, and its targets-and-limits and contacts rows when it was written
void Recorder::write_rows(const SimState& s, const StepStats& st) {
  if (!csv_->write_row(s, st, res_)) return;
  if (targets_limits_) targets_limits_->write_row(s);
  if (contacts_) contacts_->write_rows(s);
}

bool Recorder::wants_frame(int step) const {
  return opt_.all_frames || std::find(opt_.frame_steps.begin(), opt_.frame_steps.end(), step) !=
                                opt_.frame_steps.end();
}

void Recorder::observe(const SimState& s, const StepStats& st) {
  if (s.step == 0) {  // the initial state: its table row only (frame 0 is kept at construction)
    if (csv_) {
      control_residuals(scene_, s, res_);
      write_rows(s, st);
    }
    return;
  }
  const bool row = csv_ && csv_->wants(s.step);
  if (row || opt_.residuals) control_residuals(scene_, s, res_);
  if (opt_.stats) run_.stats.push_back(st);
  if (opt_.residuals) run_.residuals.push_back(res_);
  if (opt_.poses) run_.poses.push_back(s.pose);
  if (wants_frame(s.step)) {
    run_.frame_steps.push_back(s.step);
    run_.frames.push_back(s.frames);
  }
  if (row) write_rows(s, st);
}

RecordedRun Recorder::finish(RunSummary summary) {
  targets_limits_.reset();
  contacts_.reset();
  if (csv_) csv_.reset();
  if (file_.is_open()) file_.close();
  run_.summary = std::move(summary);
  return std::move(run_);
}

RecordedRun record_run(const Scene& scene, const RecordOptions& options, const StepObserver& also) {
  Recorder rec(scene, options);
  RunSummary summary = run_scene(
      scene,
      [&](const SimState& s, const StepStats& st) {
        rec.observe(s, st);
        if (also && s.step > 0) also(s, st);  // `also` sees steps only
      },
      rec.wants_initial());
  return rec.finish(std::move(summary));
}

std::vector<std::string> write_frames(const Scene& scene, const RecordedRun& run,
                                      const std::string& folder, const std::string& prefix) {
  std::vector<std::string> names;
  for (std::size_t k = 0; k < run.frames.size(); ++k) {
    const std::string name = prefix + std::to_string(run.frame_steps[k]) + ".csv";
    std::ofstream out(folder + "/" + name);
    write_bones_csv(scene.rig, run.frames[k], out);
    names.push_back(name);
  }
  return names;
}

}  // namespace physik
