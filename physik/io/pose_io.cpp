#include "physik/io/pose_io.h"

#include <iomanip>

namespace physik {

std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
  std::string out = "\"";
  for (char c : text) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

void write_bones_csv(const Rig& rig, const BoneFrames& frames, std::ostream& out) {
  out << "bone,parent,head_x,head_y,head_z,tail_x,tail_y,tail_z\n";
  out << std::setprecision(10);
  for (int i = 0; i < rig.nbone; ++i) {
    const int p = rig.bone_parent[i];
    out << csv_field(rig.bone_name[i]) << "," << (p < 0 ? "" : csv_field(rig.bone_name[p]));
    for (const Vec3* v : {&frames.head_world[i], &frames.tail_world[i]}) {
      out << "," << v->x() << "," << v->y() << "," << v->z();
    }
    out << "\n";
  }
}

std::vector<std::string> bone_column_names(const Rig& rig) {
  std::vector<std::string> names;
  names.reserve(6 * rig.nbone);
  for (const std::string& b : rig.bone_name) {
    for (const char* end : {"head", "tail"}) {
      for (const char* axis : {"x", "y", "z"}) {
        names.push_back(csv_field(b + "." + end + "_" + axis));
      }
    }
  }
  return names;
}

void append_bone_values(const BoneFrames& frames, std::vector<double>& row) {
  for (std::size_t i = 0; i < frames.head_world.size(); ++i) {
    for (const Vec3* v : {&frames.head_world[i], &frames.tail_world[i]}) {
      row.push_back(v->x());
      row.push_back(v->y());
      row.push_back(v->z());
    }
  }
}

}  // namespace physik
