// The targets-and-limits table (targets_limits.h): control-point targets and joint-limit
// excess, one row per trajectory row.
#include "physik/io/targets_limits.h"

#include <cmath>
#include <iomanip>

#include "physik/io/pose_io.h"
#include "physik/model/joint_angles.h"
#include "physik/model/unique_names.h"

namespace physik {

std::vector<std::string> targets_limits_column_names(const Scene& scene) {
  std::vector<std::string> names;
  UniqueNames taken;  // control-point names may repeat; columns may not
  for (std::size_t c = 0; c < scene.control_points.size(); ++c) {
    const std::string& name = scene.control_points[c].name;
    const std::string base = taken.make(name.empty() ? std::to_string(c) : name);
    for (const char* axis : {"x", "y", "z"}) {
      names.push_back(csv_field(base + ".target_" + axis));
    }
  }
  for (const std::string& bone : scene.rig.bone_name) {
    for (const char* axis : {"x", "y", "z"}) {
      names.push_back(csv_field(bone + ".limit_excess_" + axis));
    }
  }
  for (const std::string& bone : scene.rig.bone_name) {
    for (const char* part : {"w", "x", "y", "z"}) {
      names.push_back(csv_field(bone + ".orient_" + part));
    }
  }
  return names;
}

TargetsLimitsCsv::TargetsLimitsCsv(const Scene& scene, std::ostream& out)
    : scene_(scene), out_(out) {
  out_ << "step";
  for (const std::string& name : targets_limits_column_names(scene)) out_ << "," << name;
  out_ << "\n" << std::setprecision(9);
}

bool TargetsLimitsCsv::write_row(const SimState& s) {
  joint_angles_and_excess(scene_.rig, scene_.params.locked_axes(), s.pose, angles_, excess_);
  const auto finite = [](const Vec3& v) { return v.allFinite(); };
  for (const Vec3& t : s.target_effective_world) {
    if (!finite(t)) return false;
  }
  for (const Vec3& e : excess_) {
    if (!finite(e)) return false;
  }
  for (const Quat& q : s.frames.orient_world) {
    if (!q.coeffs().allFinite()) return false;
  }
  out_ << s.step;
  for (const Vec3& t : s.target_effective_world) {
    out_ << "," << t.x() << "," << t.y() << "," << t.z();
  }
  for (const Vec3& e : excess_) out_ << "," << e.x() << "," << e.y() << "," << e.z();
  for (const Quat& q : s.frames.orient_world) {
    out_ << "," << q.w() << "," << q.x() << "," << q.y() << "," << q.z();
  }
  out_ << "\n";
  return true;
}

}  // namespace physik
