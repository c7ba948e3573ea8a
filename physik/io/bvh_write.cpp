// A rig and its poses as BVH or qBVH text (bvh.h).
#include "physik/io/bvh.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <sstream>

#include "physik/io/bvh_detail.h"
#include "physik/io/output_files.h"
#include "physik/model/errors.h"
#include "physik/model/unique_names.h"

namespace physik {

using bvh_detail::check_order;
using bvh_detail::upper;

namespace {

std::string fmt(double v) {
  if (std::abs(v) < 1e-12) v = 0.0;
  std::ostringstream s;
  s << std::setprecision(12) << v;
  return s.str();
}

std::string bvh_name(std::string n, UniqueNames& used) {
  for (char& c : n) {
    if (std::isspace(static_cast<unsigned char>(c)) || c == '{' || c == '}') c = '_';
  }
  if (n.empty()) n = "bone";
  return used.make(n);
}

}  // namespace

// ---------------------------------------------------------------- writing

bool is_qbvh_path(const std::string& path) {
  return path.size() >= 5 && upper(path.substr(path.size() - 5)) == ".QBVH";
}

namespace {

// the destination in messages
std::string target_name(const BvhExportOptions& o) {
  return o.target.empty() ? std::string("<bvh output>") : o.target;
}

// stage 1: options that would write nan, inf or an unreadable file
void check_export_options(const BvhExportOptions& o) {
  const std::string t = target_name(o);
  if (!o.euler_order.empty()) check_order(o.euler_order, t);
  if (!(o.scale > 0.0) || !std::isfinite(o.scale)) {
    throw_input_error(t, "", "scale", "must be a positive finite number");
  }
  if (!(o.frame_time > 0.0) || !std::isfinite(o.frame_time)) {
    throw_input_error(t, "", "frame time", "must be a positive finite number");
  }
}

// a number for the file; a value the scale pushed past double range is bad input, not "inf"
std::string fmt_checked(double v, const BvhExportOptions& o, const std::string& what) {
  if (!std::isfinite(v)) {
    throw_input_error(target_name(o), what, "scale",
                      "the value is not finite (scale " + fmt(o.scale) + ")");
  }
  return fmt(v);
}

// stage 2: HIERARCHY, one joint per bone, iteratively (a rig may be a 10^6-bone chain);
// indentation stops deepening at 32 levels so the file stays linear in the bone count
void write_hierarchy(const Rig& rig, const std::vector<std::string>& names,
                     const std::string& rot_channels, int nrot, const BvhExportOptions& o,
                     std::ostream& out) {
  const Quat ainv = bvh_axes_to_rig(o.axes).conjugate();
  auto triple = [&](const Vec3& v_rig, const std::string& what) {
    const Vec3 v = o.scale * (ainv * v_rig);
    return fmt_checked(v.x(), o, what) + " " + fmt_checked(v.y(), o, what) + " " +
           fmt_checked(v.z(), o, what);
  };
  auto indent = [](int depth) { return std::string(2 * std::min(depth, 32), ' '); };
  out << "HIERARCHY\n";
  // (bone, depth) to open; a negative bone closes joint -bone-1
  std::vector<std::pair<int, int>> stack{{0, 0}};
  while (!stack.empty()) {
    const auto [b, depth] = stack.back();
    stack.pop_back();
    const std::string ind = indent(depth);
    if (b < 0) {
      out << ind << "}\n";
      continue;
    }
    const int p = rig.bone_parent[b];
    const Vec3 off = p < 0 ? rig.bone_rest_head_world[b]
                           : Vec3(rig.bone_rest_head_world[b] - rig.bone_rest_head_world[p]);
    const std::string el = "bone '" + names[b] + "'";
    out << ind << (p < 0 ? "ROOT " : "JOINT ") << names[b] << "\n" << ind << "{\n";
    out << ind << "  OFFSET " << triple(off, el) << "\n";
    if (p < 0) {
      out << ind << "  CHANNELS " << 3 + nrot << " Xposition Yposition Zposition " << rot_channels
          << "\n";
    } else {
      out << ind << "  CHANNELS " << nrot << " " << rot_channels << "\n";
    }
    if (rig.bone_children[b].empty()) {
      const Vec3 e = rig.bone_rest_tail_world[b] - rig.bone_rest_head_world[b];
      out << ind << "  End Site\n"
          << ind << "  {\n"
          << ind << "    OFFSET " << triple(e, el) << "\n"
          << ind << "  }\n";
    }
    stack.push_back({-b - 1, depth});
    const auto& kids = rig.bone_children[b];
    for (auto it = kids.rbegin(); it != kids.rend(); ++it) stack.push_back({*it, depth + 1});
  }
}

// stage 2b: the own skeleton as physik's reader reads it back (bvh.h): every OFFSET and End
// Site, every rest head and tail (the sums of OFFSETs bvh_to_rig checks at scale 1) and the
// root's head in every frame within +-kMaxCoordinate file units
void check_own_skeleton_readable(const Rig& rig, const std::vector<Pose>& poses,
                                 const BvhExportOptions& o) {
  const Quat ainv = bvh_axes_to_rig(o.axes).conjugate();
  const auto inside = [&](const Vec3& v_rig) {
    return (o.scale * (ainv * v_rig)).cwiseAbs().maxCoeff() <= kMaxCoordinate;
  };
  const auto refuse = [&](const std::string& el, const std::string& what) {
    throw_input_error(target_name(o), el, "scale",
                      what + " beyond +-1e9 file units at scale " + fmt(o.scale) +
                          " (rig.h kMaxCoordinate), which a BVH reader (physik's own) refuses; "
                          "nothing is written");
  };
  for (int b = 0; b < rig.nbone; ++b) {
    const Vec3& head = rig.bone_rest_head_world[b];
    const Vec3& tail = rig.bone_rest_tail_world[b];
    const int p = rig.bone_parent[b];
    const std::string el = "bone '" + rig.bone_name[b] + "'";
    if (!inside(head) || !inside(tail)) refuse(el, "its rest head or tail lies");
    if (p >= 0 && !inside(head - rig.bone_rest_head_world[p])) refuse(el, "its OFFSET is");
    if (rig.bone_children[b].empty() && !inside(tail - head)) refuse(el, "its End Site is");
  }
  BoneFrames fk;
  for (std::size_t f = 0; f < poses.size(); ++f) {
    forward_kinematics(rig, poses[f], fk);
    if (!inside(fk.head_world[0])) refuse("frame " + std::to_string(f), "the root's head lies");
  }
}

// per-bone continuity across frames: Euler branch and quaternion hemisphere
struct FrameMemory {
  std::vector<Quat> rw;          // (nbone) world rotation from rest, this frame
  std::vector<Vec3> prev_euler;  // (nbone) rad
  std::vector<Quat> prev_quat;   // (nbone)
};

// stage 3: one frame row: the root's head, then every bone's rotation relative to its parent's
void write_frame(const Rig& rig, const Pose& pose, std::size_t f, const std::string& order,
                 const BvhExportOptions& o, BoneFrames& fk, FrameMemory& mem, std::ostream& out) {
  const Quat a = bvh_axes_to_rig(o.axes);
  const Quat ainv = a.conjugate();
  const std::string el = "frame " + std::to_string(f);
  forward_kinematics(rig, pose, fk);
  const Vec3 root = o.scale * (ainv * fk.head_world[0]);
  out << fmt_checked(root.x(), o, el) << " " << fmt_checked(root.y(), o, el) << " "
      << fmt_checked(root.z(), o, el);
  for (int b = 0; b < rig.nbone; ++b) {
    // world rotation from rest, then relative to the parent's, in file axes
    mem.rw[b] = (fk.orient_world[b] * rig.bone_rest_orient_world[b].conjugate()).normalized();
    const int p = rig.bone_parent[b];
    const Quat local = p < 0 ? mem.rw[b] : Quat(mem.rw[p].conjugate() * mem.rw[b]);
    Quat lf = (ainv * local * a).normalized();
    if (!lf.coeffs().allFinite()) {
      throw_input_error(target_name(o), el, "pose",
                        "bone " + std::to_string(b) + ": the rotation is not finite");
    }
    if (o.quaternion) {
      if (lf.coeffs().dot(mem.prev_quat[b].coeffs()) < 0.0) lf.coeffs() *= -1.0;
      mem.prev_quat[b] = lf;
      out << " " << fmt(lf.w()) << " " << fmt(lf.x()) << " " << fmt(lf.y()) << " " << fmt(lf.z());
    } else {
      Vec3 e = euler_from_rotation(lf, order);
      if (f > 0) e = bvh_detail::closest_euler(e, mem.prev_euler[b]);
      mem.prev_euler[b] = e;
      out << " " << fmt(rad2deg(e[0])) << " " << fmt(rad2deg(e[1])) << " " << fmt(rad2deg(e[2]));
    }
  }
  out << "\n";
}

}  // namespace

BvhWriteReport write_bvh(const Rig& rig, const std::vector<Pose>& poses_in,
                         const BvhExportOptions& options, std::ostream& out,
                         const SourceFrames& source) {
  check_export_options(options);
  const std::vector<Pose> rest{rest_pose(rig)};
  const std::vector<Pose>& poses = poses_in.empty() ? rest : poses_in;
  if (writes_source_skeleton(rig, options)) {
    return bvh_detail::write_source_bvh(rig, poses, options, source, out);
  }
  check_own_skeleton_readable(rig, poses, options);
  const std::string order = options.euler_order.empty() ? "ZXY" : upper(options.euler_order);

  UniqueNames used;
  std::vector<std::string> names(rig.nbone);
  for (int b = 0; b < rig.nbone; ++b) names[b] = bvh_name(rig.bone_name[b], used);

  std::string rot_channels;
  if (options.quaternion) {
    rot_channels = "Wquaternion Xquaternion Yquaternion Zquaternion";
  } else {
    for (char c : order)
      rot_channels += std::string(rot_channels.empty() ? "" : " ") + c + "rotation";
  }
  write_hierarchy(rig, names, rot_channels, options.quaternion ? 4 : 3, options, out);

  out << "MOTION\nFrames: " << poses.size() << "\nFrame Time: " << fmt(options.frame_time) << "\n";
  BoneFrames fk;
  FrameMemory mem{std::vector<Quat>(rig.nbone), std::vector<Vec3>(rig.nbone, Vec3::Zero()),
                  std::vector<Quat>(rig.nbone, Quat::Identity())};
  for (std::size_t f = 0; f < poses.size(); ++f) {
    write_frame(rig, poses[f], f, order, options, fk, mem, out);
  }
  return {};
}

BvhWriteReport save_bvh(const std::string& path, const Rig& rig, const std::vector<Pose>& poses,
                        const BvhExportOptions& options, const SourceFrames& source) {
  BvhExportOptions o = options;
  o.target = path;
  check_export_options(o);  // before a file is created
  // the text first: a refusal (a value the reader would refuse) leaves no file behind
  std::ostringstream text;
  BvhWriteReport report = write_bvh(rig, poses, o, text, source);
  std::ofstream out = open_output_file(path, "");
  out << text.str();
  if (!out) throw_input_error(path, "", "", "write failed");
  return report;
}

}  // namespace physik
