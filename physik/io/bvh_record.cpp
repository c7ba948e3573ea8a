// The recorder that collects a run's frames and writes them as one BVH animation (bvh.h).
#include "physik/io/bvh.h"

#include <utility>

#include "physik/model/errors.h"

namespace physik {

BvhRecorder::BvhRecorder(const Rig& rig, double dt, int every, BvhExportOptions options)
    : rig_(rig), every_(every), options_(std::move(options)) {
  if (every < 1) throw_input_error("", "", "every", "must be at least 1");
  if (!(dt > 0.0)) throw_input_error("", "", "dt", "must be positive");
  options_.frame_time = dt * every;
}

void BvhRecorder::record(const Pose& pose) {
  if (calls_++ % every_ != 0) return;
  poses_.push_back(pose);
  source_.frame_of_pose.push_back(held_);
}

void BvhRecorder::record(const BoneFrames& frames) {
  if (calls_++ % every_ != 0) return;
  Pose p;
  local_rotations_from_world(rig_, frames, p);
  poses_.push_back(std::move(p));
  source_.frame_of_pose.push_back(held_);
}

void BvhRecorder::hold_source_row(const std::vector<double>& row) {
  if (row.empty()) {
    held_ = -1;
  } else if (held_ < 0 || source_.rows[held_] != row) {
    source_.rows.push_back(row);
    held_ = static_cast<int>(source_.rows.size()) - 1;
  }
}

BvhWriteReport BvhRecorder::write(std::ostream& out) const {
  return write_bvh(rig_, poses_, options_, out, source_);
}

BvhWriteReport BvhRecorder::save(const std::string& path) const {
  BvhExportOptions o = options_;
  o.quaternion = o.quaternion || is_qbvh_path(path);
  return save_bvh(path, rig_, poses_, o, source_);
}

}  // namespace physik
