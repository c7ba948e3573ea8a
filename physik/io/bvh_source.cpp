// A rig's poses written on its source skeleton, and clips of that skeleton read onto the rig
// (bvh.h "Rig -> its source skeleton"; source_skeleton.h, source_pose.h).
//
// Per frame, with A the file -> rig axes rotation and s the rig units per file unit:
//   Rf_J = A^-1 R_J A                      a joint's world rotation from rest, file axes
//   L_J  = Rf_parent^-1 Rf_J               its rotation channels (the root: Rf_J)
//   p    = A^-1 p_root / s                 the root's position channels, file units
// and back (source_clip_pose): R_J = A Rf_J A^-1, p_root = s A p, Rf_J from the clip's channels
// by the BVH forward kinematics (bvh_world).
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

#include "physik/io/bvh.h"
#include "physik/io/bvh_detail.h"
#include "physik/model/errors.h"
#include "physik/model/source_pose.h"

namespace physik {

using bvh_detail::is_position;
using bvh_detail::is_quaternion;
using bvh_detail::is_rotation;

namespace {

// 15 significant digits: a value read from a file prints as it was written
std::string num(double v, const std::string& target, const std::string& what) {
  if (!std::isfinite(v)) throw_input_error(target, what, "value", "not finite");
  if (std::abs(v) < 1e-13) v = 0.0;
  std::ostringstream s;
  s << std::setprecision(15) << v;
  return s.str();
}

std::string triple(const Vec3& v, const std::string& target, const std::string& what) {
  return num(v.x(), target, what) + " " + num(v.y(), target, what) + " " + num(v.z(), target, what);
}

char axis_letter(BvhChannel c) {
  switch (c) {
    case BvhChannel::kXpos:
    case BvhChannel::kXrot:
    case BvhChannel::kXquat:
      return 'X';
    case BvhChannel::kYpos:
    case BvhChannel::kYrot:
    case BvhChannel::kYquat:
      return 'Y';
    case BvhChannel::kZpos:
    case BvhChannel::kZrot:
    case BvhChannel::kZquat:
      return 'Z';
    case BvhChannel::kWquat:
      return 'W';
  }
  return 'W';
}

// the joint's Euler rotation channels' axes in order, then the axes it has no channel for
std::string full_order(const std::vector<BvhChannel>& channels, int& nrot) {
  std::string order;
  for (BvhChannel c : channels) {
    if (is_rotation(c)) order += axis_letter(c);
  }
  nrot = static_cast<int>(order.size());
  for (char a : std::string("XYZ")) {
    if (order.find(a) == std::string::npos) order += a;
  }
  return order;
}

// the channels written for joint `j` under the options: rotation channels replaced, at the first
// one's place, by the four quaternion channels (quaternion) or the given order (three angles)
std::vector<BvhChannel> written_channels(const std::vector<BvhChannel>& in,
                                         const BvhExportOptions& o) {
  const int nrot = static_cast<int>(std::count_if(in.begin(), in.end(), is_rotation));
  const bool to_quat = o.quaternion && nrot > 0;
  const bool reorder = !o.quaternion && nrot == 3 && !o.euler_order.empty();
  if (!to_quat && !reorder) return in;
  std::vector<BvhChannel> out;
  bool placed = false;
  for (BvhChannel c : in) {
    if (!is_rotation(c)) {
      out.push_back(c);
      continue;
    }
    if (placed) continue;
    placed = true;
    if (to_quat) {
      out.insert(out.end(),
                 {BvhChannel::kWquat, BvhChannel::kXquat, BvhChannel::kYquat, BvhChannel::kZquat});
    } else {
      for (char a : bvh_detail::upper(o.euler_order)) {
        out.push_back(a == 'X'   ? BvhChannel::kXrot
                      : a == 'Y' ? BvhChannel::kYrot
                                 : BvhChannel::kZrot);
      }
    }
  }
  return out;
}

// what the written joints could not hold, the largest over the frames
struct Dropped {
  std::vector<double> rot_deg;   // (njoint) a turn about an axis without a channel
  std::vector<Vec3> root_shift;  // (1) the root's move along an axis without a position channel
};

}  // namespace

bool writes_source_skeleton(const Rig& rig, const BvhExportOptions& options) {
  return options.source_skeleton && !rig.source_skeleton.empty();
}

void write_bvh_file(const BvhFile& bvh, const std::string& target, std::ostream& out) {
  auto indent = [](int depth) { return std::string(2 * std::min(depth, 32), ' '); };
  const int n = static_cast<int>(bvh.joints.size());
  std::vector<int> depth(n, 0);
  std::vector<int> open;  // the joints whose block is open, innermost last
  out << "HIERARCHY\n";
  for (int i = 0; i < n; ++i) {
    const BvhJoint& j = bvh.joints[i];
    while (!open.empty() && open.back() != j.parent) {
      out << indent(depth[open.back()]) << "}\n";
      open.pop_back();
    }
    depth[i] = j.parent < 0 ? 0 : depth[j.parent] + 1;
    const std::string ind = indent(depth[i]);
    const std::string el = "joint '" + j.name + "'";
    out << ind << (j.parent < 0 ? "ROOT " : "JOINT ") << j.name << "\n" << ind << "{\n";
    out << ind << "  OFFSET " << triple(j.offset, target, el) << "\n";
    out << ind << "  CHANNELS " << j.channels.size();
    for (BvhChannel c : j.channels) out << " " << bvh_channel_name(c);
    out << "\n";
    for (const Vec3& e : j.end_sites) {
      out << ind << "  End Site\n"
          << ind << "  {\n"
          << ind << "    OFFSET " << triple(e, target, el) << "\n"
          << ind << "  }\n";
    }
    open.push_back(i);
  }
  while (!open.empty()) {
    out << indent(depth[open.back()]) << "}\n";
    open.pop_back();
  }
  out << "MOTION\nFrames: " << bvh.frames.size()
      << "\nFrame Time: " << num(bvh.frame_time, target, "Frame Time") << "\n";
  for (std::size_t f = 0; f < bvh.frames.size(); ++f) {
    const std::string el = "frame " + std::to_string(f);
    const auto& row = bvh.frames[f];
    for (std::size_t k = 0; k < row.size(); ++k) {
      out << (k ? " " : "") << num(row[k], target, el);
    }
    out << "\n";
  }
}

BvhFile source_skeleton_bvh(const SourceSkeleton& skeleton) {
  BvhFile bvh;
  int col = 0;
  for (const SourceJoint& sj : skeleton.joints) {
    BvhJoint j;
    j.name = sj.name;
    j.parent = sj.parent;
    j.offset = sj.offset;
    j.end_sites = sj.end_sites;
    for (const std::string& c : sj.channels) {
      BvhChannel ch;
      if (!bvh_channel_from_name(c, ch)) {
        throw_input_error("", "source_skeleton", "channels", "unknown channel '" + c + "'");
      }
      j.channels.push_back(ch);
    }
    j.channel_start = col;
    col += static_cast<int>(j.channels.size());
    bvh.joints.push_back(std::move(j));
  }
  bvh.nchannel = col;
  return bvh;
}

std::string source_skeleton_mismatch(const SourceSkeleton& skeleton, const BvhFile& clip) {
  const BvhFile src = source_skeleton_bvh(skeleton);
  if (src.joints.size() != clip.joints.size()) {
    return "the clip has " + std::to_string(clip.joints.size()) +
           " joints, the rig's source "
           "skeleton " +
           std::to_string(src.joints.size());
  }
  double size = 1.0;
  for (const BvhJoint& j : src.joints) size = std::max(size, j.offset.norm());
  const double tol = 1e-6 * size;
  for (std::size_t i = 0; i < src.joints.size(); ++i) {
    const BvhJoint& a = src.joints[i];
    const BvhJoint& b = clip.joints[i];
    const std::string at = "joint " + std::to_string(i);
    if (a.name != b.name) {
      return at + " is '" + b.name + "' in the clip, '" + a.name + "' in the rig's source skeleton";
    }
    const std::string jn = "joint '" + a.name + "'";
    if (a.parent != b.parent) return jn + " has another parent in the clip";
    if (a.channels != b.channels) return jn + " has other channels in the clip";
    if ((a.offset - b.offset).norm() > tol) {
      return jn + "'s OFFSET differs from the rig's source skeleton by " +
             std::to_string((a.offset - b.offset).norm()) + " file units";
    }
    if (a.end_sites.size() != b.end_sites.size()) return jn + " has other End Sites in the clip";
    for (std::size_t e = 0; e < a.end_sites.size(); ++e) {
      if ((a.end_sites[e] - b.end_sites[e]).norm() > tol) {
        return jn + "'s End Site differs from the rig's source skeleton";
      }
    }
  }
  return "";
}

void source_clip_pose(const Rig& rig, const BvhFile& clip, int frame, BoneFrames& scratch,
                      Pose& out) {
  const SourceSkeleton& s = rig.source_skeleton;
  const Quat a = source_axes_to_rig(s.axes);
  std::vector<Quat> rot;
  std::vector<Vec3> pos;
  bvh_world(clip, frame, rot, pos);
  for (Quat& q : rot) q = (a * q * a.conjugate()).normalized();
  pose_from_source(rig, rot, s.scale * (a * pos[0]), scratch, out);
}

void checked_clip_pose(const Rig& rig, const BvhFile& clip, int frame, const std::string& source,
                       const std::string& element, BoneFrames& scratch, Pose& out) {
  source_clip_pose(rig, clip, frame, scratch, out);
  const Vec3& r = out.root_head_world;
  if (r.cwiseAbs().maxCoeff() <= kMaxCoordinate) return;  // false for NaN too
  std::ostringstream why;
  why << std::setprecision(6) << "frame " << frame << " puts the rig's root "
      << r.cwiseAbs().maxCoeff() << " rig units out along an axis, past +-" << kMaxCoordinate
      << " (rig.h kMaxCoordinate): the clip's root position times the rig's source_skeleton "
         "scale "
      << rig.source_skeleton.scale;
  throw_input_error(source, element, "frame", why.str());
}

namespace {

// The source skeleton's frames, one row per pose, and what the file could not hold.
struct SourceWriter {
  BvhFile bvh;
  std::vector<std::string> order;   // (njoint) rotation channels' axes, then the missing ones
  std::vector<int> nrot;            // (njoint) Euler rotation channels
  std::vector<Quat> prev_q;         // (njoint) last frame's quaternion (hemisphere)
  std::vector<Vec3> prev_e;         // (njoint) last frame's angles (branch), rad
  std::vector<double> dropped_deg;  // (njoint) largest turn about an axis without a channel
  Vec3 root_shift = Vec3::Zero();   // largest root move along an axis without a channel

  SourceWriter(const SourceSkeleton& s, const BvhExportOptions& o) : bvh(source_skeleton_bvh(s)) {
    bvh.frame_time = o.frame_time;
    const std::size_t nj = bvh.joints.size();
    order.resize(nj);
    nrot.resize(nj);
    prev_q.assign(nj, Quat::Identity());
    prev_e.assign(nj, Vec3::Zero());
    dropped_deg.assign(nj, 0.0);
    for (std::size_t j = 0; j < nj; ++j) {
      bvh.joints[j].channels = written_channels(bvh.joints[j].channels, o);
      order[j] = full_order(bvh.joints[j].channels, nrot[j]);
    }
  }

  // joint j's channels for its rotation `local` (file axes) and the root at `p` (file units)
  void joint_row(int j, Quat local, const Vec3& p, std::vector<double>& row) {
    const BvhJoint& joint = bvh.joints[j];
    Vec3 e = Vec3::Zero();
    if (nrot[j] > 0) {
      e = bvh_detail::closest_euler(euler_from_rotation(local, order[j]), prev_e[j]);
      prev_e[j] = e;
      for (int k = nrot[j]; k < 3; ++k) {
        dropped_deg[j] = std::max(dropped_deg[j], std::abs(rad2deg(e[k])));
      }
    }
    if (std::any_of(joint.channels.begin(), joint.channels.end(), is_quaternion)) {
      if (local.coeffs().dot(prev_q[j].coeffs()) < 0.0) local.coeffs() *= -1.0;
      prev_q[j] = local;
    } else if (nrot[j] == 0) {
      const double angle = rad2deg(2.0 * std::atan2(local.vec().norm(), std::abs(local.w())));
      dropped_deg[j] = std::max(dropped_deg[j], angle);
    }
    int next_rot = 0;
    bool has_pos[3] = {false, false, false};
    for (BvhChannel c : joint.channels) {
      const int axis = bvh_detail::axis_index(axis_letter(c));
      if (is_position(c)) {
        has_pos[axis] = true;
        row.push_back(joint.parent >= 0 ? joint.offset[axis] : p[axis]);
      } else if (is_rotation(c)) {
        row.push_back(rad2deg(e[next_rot++]));
      } else {
        row.push_back(c == BvhChannel::kWquat ? local.w() : local.vec()[axis]);
      }
    }
    if (joint.parent >= 0) return;
    for (int k = 0; k < 3; ++k) {
      if (!has_pos[k]) root_shift[k] = std::max(root_shift[k], std::abs(p[k] - joint.offset[k]));
    }
  }

  BvhWriteReport report() const {
    BvhWriteReport r;
    r.source_skeleton = true;
    const double pos_tol = 1e-9 * std::max(1.0, bvh.joints[0].offset.norm());
    const char* axis_name[3] = {"x", "y", "z"};
    for (int k = 0; k < 3; ++k) {
      if (root_shift[k] <= pos_tol) continue;
      std::ostringstream w;
      w << "root joint '" << bvh.joints[0].name << "' has no " << static_cast<char>('X' + k)
        << "position channel: the rig's root moved up to " << root_shift[k]
        << " file units along file " << axis_name[k] << ", which the file leaves out";
      r.warnings.push_back(w.str());
    }
    for (std::size_t j = 0; j < bvh.joints.size(); ++j) {
      if (dropped_deg[j] <= 1e-7) continue;
      std::ostringstream w;
      w << "joint '" << bvh.joints[j].name << "' has " << nrot[j]
        << " rotation channels: turns of up to " << dropped_deg[j]
        << " deg about the axes it has none for are left out";
      r.warnings.push_back(w.str());
    }
    return r;
  }
};

}  // namespace

// the source skeleton's frames: every joint's channels from the rig's pose (bvh.h)
BvhWriteReport bvh_detail::write_source_bvh(const Rig& rig, const std::vector<Pose>& poses,
                                            const BvhExportOptions& o, std::ostream& out) {
  const std::string target = o.target.empty() ? std::string("<bvh output>") : o.target;
  const SourceSkeleton& s = rig.source_skeleton;
  SourceWriter w(s, o);
  const int nj = static_cast<int>(w.bvh.joints.size());
  const Quat a = source_axes_to_rig(s.axes);
  const Quat ainv = a.conjugate();
  BoneFrames fk;
  std::vector<Quat> rw, rf(nj);
  Vec3 root;
  for (std::size_t f = 0; f < poses.size(); ++f) {
    forward_kinematics(rig, poses[f], fk);
    source_from_frames(rig, fk, rw, root);
    const Vec3 p = ainv * root / s.scale;
    std::vector<double> row;
    for (int j = 0; j < nj; ++j) {
      const int parent = w.bvh.joints[j].parent;
      rf[j] = (ainv * rw[j] * a).normalized();
      const Quat local = (parent < 0 ? rf[j] : Quat(rf[parent].conjugate() * rf[j])).normalized();
      if (!local.coeffs().allFinite()) {
        throw_input_error(target, "frame " + std::to_string(f), "pose",
                          "joint '" + w.bvh.joints[j].name + "': rotation not finite");
      }
      w.joint_row(j, local, p, row);
    }
    w.bvh.frames.push_back(std::move(row));
  }
  write_bvh_file(w.bvh, target, out);
  return w.report();
}

}  // namespace physik
