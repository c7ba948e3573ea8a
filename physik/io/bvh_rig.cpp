// A BvhFile as a rig and its poses (pivot_rig.h), and the rig's world view of a frame (bvh.h).
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
#include "physik/model/errors.h"
#include "physik/model/names.h"

namespace physik {

using bvh_detail::upper;

Quat bvh_local_rotation(const BvhJoint& joint, const std::vector<double>& row) {
  Quat q = Quat::Identity();
  double quat[4] = {1, 0, 0, 0};  // w x y z
  bool have_quat = false;
  for (std::size_t c = 0; c < joint.channels.size(); ++c) {
    const double v = row.empty() ? 0.0 : row[joint.channel_start + c];
    switch (joint.channels[c]) {
      case BvhChannel::kXrot:
        q = q * Eigen::AngleAxisd(deg2rad(v), Vec3::UnitX());
        break;
      case BvhChannel::kYrot:
        q = q * Eigen::AngleAxisd(deg2rad(v), Vec3::UnitY());
        break;
      case BvhChannel::kZrot:
        q = q * Eigen::AngleAxisd(deg2rad(v), Vec3::UnitZ());
        break;
      case BvhChannel::kWquat:
        quat[0] = row.empty() ? 1.0 : v;
        have_quat = true;
        break;
      case BvhChannel::kXquat:
        quat[1] = v;
        have_quat = true;
        break;
      case BvhChannel::kYquat:
        quat[2] = v;
        have_quat = true;
        break;
      case BvhChannel::kZquat:
        quat[3] = v;
        have_quat = true;
        break;
      default:
        break;
    }
  }
  if (have_quat) q = Quat(quat[0], quat[1], quat[2], quat[3]);
  return q.normalized();
}

Vec3 bvh_local_translation(const BvhJoint& joint, const std::vector<double>& row) {
  Vec3 t = joint.offset;
  if (row.empty()) return t;
  for (std::size_t c = 0; c < joint.channels.size(); ++c) {
    const double v = row[joint.channel_start + c];
    switch (joint.channels[c]) {
      case BvhChannel::kXpos:
        t.x() = v;
        break;
      case BvhChannel::kYpos:
        t.y() = v;
        break;
      case BvhChannel::kZpos:
        t.z() = v;
        break;
      default:
        break;
    }
  }
  return t;
}

void bvh_world(const BvhFile& bvh, int frame, std::vector<Quat>& rot_world,
               std::vector<Vec3>& pos_world) {
  static const std::vector<double> kRest;
  const std::vector<double>& row = frame < 0 ? kRest : bvh.frames[frame];
  const std::size_t n = bvh.joints.size();
  rot_world.resize(n);
  pos_world.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const BvhJoint& j = bvh.joints[i];
    const Quat local = bvh_local_rotation(j, row);
    const Vec3 t = bvh_local_translation(j, row);
    if (j.parent < 0) {
      rot_world[i] = local;
      pos_world[i] = t;
    } else {
      rot_world[i] = (rot_world[j.parent] * local).normalized();
      pos_world[i] = pos_world[j.parent] + rot_world[j.parent] * t;
    }
  }
}

Quat bvh_axes_to_rig(BvhAxes axes) {
  if (axes == BvhAxes::kZUp) return Quat::Identity();
  return Quat(Eigen::AngleAxisd(kPi / 2, Vec3::UnitX()));  // file Y -> rig Z, file Z -> rig -Y
}

BvhAnimation bvh_to_rig(const BvhFile& bvh, const std::string& source,
                        const BvhImportOptions& options) {
  if (!(options.scale > 0.0) || !std::isfinite(options.scale)) {
    throw_input_error(source, "", "scale", "must be a positive number");
  }
  const Quat a = bvh_axes_to_rig(options.axes);
  const double s = options.scale;

  std::vector<Quat> rot;
  std::vector<Vec3> pos;
  bvh_world(bvh, -1, rot, pos);
  std::vector<PivotNode> nodes(bvh.joints.size());
  // rest positions in rig units must stay within the rig's coordinate range (rig.h)
  auto rig_point = [&](const BvhJoint& j, const Vec3& file_pos) {
    const Vec3 p = s * (a * file_pos);
    if (!(p.cwiseAbs().maxCoeff() <= kMaxCoordinate)) {
      throw_input_error(source, "line " + std::to_string(j.line), "OFFSET",
                        "joint '" + j.name + "' lies beyond +-" + std::to_string(kMaxCoordinate) +
                            " rig units at rest (sum of OFFSETs times the scale; rig.h "
                            "kMaxCoordinate)");
    }
    return p;
  };
  for (std::size_t i = 0; i < bvh.joints.size(); ++i) {
    const BvhJoint& j = bvh.joints[i];
    nodes[i].name = j.name;
    nodes[i].parent = j.parent;
    nodes[i].rest_world = rig_point(j, pos[i]);
    for (const Vec3& e : j.end_sites) nodes[i].ends_world.push_back(rig_point(j, pos[i] + e));
  }
  const PivotBones bones = pivot_bones(nodes, source, options.mass_per_length, options.radius);
  BvhAnimation anim;
  anim.pivots = finish_pivot_rig(nodes, bones, source, "");
  anim.frame_time = bvh.frame_time;

  // per frame: every pivot's rotation and position in rig axes -> pose; check FK against BVH
  std::vector<Quat> node_rot(nodes.size());
  std::vector<Vec3> node_pos(nodes.size());
  BoneFrames scratch, fk;
  std::vector<Vec3> want_head, want_tail;
  anim.poses.resize(bvh.frames.size());
  for (std::size_t f = 0; f < bvh.frames.size(); ++f) {
    bvh_world(bvh, static_cast<int>(f), rot, pos);
    for (std::size_t i = 0; i < nodes.size(); ++i) {
      node_rot[i] = (a * rot[i] * a.conjugate()).normalized();
      node_pos[i] = s * (a * pos[i]);
    }
    pivot_pose(anim.pivots, node_rot, node_pos[0], scratch, anim.poses[f]);
    forward_kinematics(anim.rig(), anim.poses[f], fk);
    pivot_bone_targets(anim.pivots, node_pos, node_rot, want_head, want_tail);
    for (int b = 0; b < anim.rig().nbone; ++b) {
      anim.max_position_error =
          std::max({anim.max_position_error, (fk.head_world[b] - want_head[b]).norm(),
                    (fk.tail_world[b] - want_tail[b]).norm()});
    }
  }
  return anim;
}

BvhAnimation load_bvh(const std::string& path, const BvhImportOptions& options) {
  return bvh_to_rig(read_bvh_file(path), path, options);
}

}  // namespace physik
