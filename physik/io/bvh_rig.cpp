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
#include "physik/model/source_pose.h"

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
  return source_axes_to_rig(axes);
}

namespace {

// joints with no bone of its own (pivot_rig.h, 2.: every child at its own position, or no child
// and no End Site): the rig cannot turn one apart from its children (source_pose.h), so a
// write-back keeps its rotation from the frame a pose came from; named when the file turns it
void held_joint_warnings(const BvhFile& bvh, const PivotBones& bones, BvhAnimation& anim) {
  std::vector<std::vector<int>> children(bvh.joints.size());
  for (std::size_t c = 1; c < bvh.joints.size(); ++c) {
    children[bvh.joints[c].parent].push_back(static_cast<int>(c));
  }
  std::vector<char> has_bone(bvh.joints.size(), 0);  // a bone follows the joint (spec_node)
  for (int node : bones.spec_node) {
    if (node >= 0) has_bone[node] = 1;
  }
  for (std::size_t j = 0; j < bvh.joints.size(); ++j) {
    const BvhJoint& joint = bvh.joints[j];
    if (has_bone[j]) continue;
    const bool turns = std::any_of(joint.channels.begin(), joint.channels.end(), [](BvhChannel c) {
      return bvh_detail::is_rotation(c) || bvh_detail::is_quaternion(c);
    });
    if (!turns) continue;
    std::string names;
    for (int c : children[j]) names += (names.empty() ? "" : ", ") + bvh.joints[c].name;
    anim.warnings.push_back(
        "joint '" + joint.name + "' (line " + std::to_string(joint.line) +
        ") has no bone of its own (" +
        (names.empty() ? std::string("no child, no End Site")
                       : "its children " + names + " sit at its position") +
        "): the rig turns its children's bones by its rotation and theirs together; written back, "
        "it keeps the rotation of the frame a pose came from (rest for a pose from none) and its "
        "children's channels take the rest");
  }
}

// non-root joints whose position channels move them off their OFFSET (a stretch): the rig keeps
// its bones' lengths, so that motion is left out of the rig (max_position_error measures it);
// named with the bone that ends at the joint and the largest move
void position_channel_warnings(const BvhFile& bvh, const PivotBones& bones, BvhAnimation& anim) {
  for (std::size_t j = 1; j < bvh.joints.size(); ++j) {
    const BvhJoint& joint = bvh.joints[j];
    const double tol = 1e-9 * std::max(1.0, joint.offset.norm());
    double moved = 0.0;
    for (const auto& row : bvh.frames) {
      moved = std::max(moved, (bvh_local_translation(joint, row) - joint.offset).norm());
    }
    if (!(moved > tol)) continue;
    // the bone that ends at the joint is the one whose length the channels would change
    const int incoming = bones.node_incoming[j];
    const std::string names = incoming >= 0 ? "'" + bones.specs[incoming].name + "'" : "none";
    std::ostringstream w;
    w << "joint '" << joint.name << "' (line " << joint.line << ", bone " << names
      << "): its position channels move it up to " << moved
      << " file units off its OFFSET, which the rig leaves out (its bones keep their lengths); "
         "written back on the source skeleton, they keep the values of the frame a pose came "
         "from (the OFFSET for a pose from none)";
    anim.warnings.push_back(w.str());
  }
}

// what the rig came from and what the conversion chose, in the rig's source notes and units
void write_bvh_notes(const std::string& source, const BvhImportOptions& options,
                     BvhAnimation& anim) {
  Rig& rig = anim.pivots.rig;
  std::ostringstream s;
  s.precision(6);
  s << "rig from-bvh " << source << ": axes "
    << (options.axes == BvhAxes::kYUp ? "y-up (file Y is the rig's Z)" : "z-up") << ", scale "
    << options.scale << " rig units per file unit; height " << rig.height() << " rig units";
  double suggested = 0.0;
  const std::string unit = guess_bvh_units(rig.height(), suggested);
  if (!unit.empty() && !anim.body.human) {
    s << " (looks like " << unit << ": --scale " << suggested << " makes metres)";
  }
  rig.source.push_back(s.str());
  s.str("");
  const SizingOptions& z = options.sizing;
  s << "sizes: radius and collision radius ";
  if (z.radius > 0.0) {
    s << z.radius << " rig units (--radius)";
  } else {
    s << kRadiusPerLength << " x each bone's length";
  }
  s << "; mass ";
  if (anim.body.human) {
    s << "and inertia the human template's (below)";
  } else if (z.mass_per_length > 0.0) {
    s << z.mass_per_length << " kg per rig unit (--mass-per-length)";
  } else {
    s << "a rod of density " << kBodyDensity << " kg per cubic rig unit";
  }
  if (z.total_mass > 0.0 && !anim.body.human) {
    s << ", scaled to " << z.total_mass << " kg in all (--total-mass)";
  }
  rig.source.push_back(s.str());
  for (const std::string& n : anim.notes) rig.source.push_back(n);
  for (const std::string& note : bvh_body_notes(anim.body)) rig.source.push_back(note);
  for (const std::string& w : anim.warnings) rig.source.push_back("warning: " + w);
  if (!anim.rest_overlaps.empty()) {
    std::string names;
    for (const BoneOverlap& o : anim.rest_overlaps) {
      names += (names.empty() ? "" : ", ") + rig.bone_name[o.a] + "/" + rig.bone_name[o.b];
    }
    rig.source.push_back("collision_exclude: " + std::to_string(anim.rest_overlaps.size()) +
                         " bone pairs whose capsules overlap at rest: " + names);
  }
  std::ostringstream u;
  u << "rig units = file units x " << options.scale << " (read as metres), kg";
  rig.units = u.str();
}

// every joint as a pivot at its rest position in rig axes and units (rig.h's coordinate range)
std::vector<PivotNode> bvh_pivots(const BvhFile& bvh, const std::string& source,
                                  const BvhImportOptions& options) {
  const Quat a = bvh_axes_to_rig(options.axes);
  const double s = options.scale;
  std::vector<Quat> rot;
  std::vector<Vec3> pos;
  bvh_world(bvh, -1, rot, pos);
  std::vector<PivotNode> nodes(bvh.joints.size());
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
  return nodes;
}

// the root's joint: the option's, else pinned for a root with no position channel (bvh.h)
RootJoint bvh_root_joint(const BvhFile& bvh, const std::string& source,
                         const BvhImportOptions& options) {
  if (options.root) {
    if (*options.root == RootJoint::kFixed) {
      throw_input_error(source, "", "root",
                        "a BVH root is free or pinned (fixed would not turn it)");
    }
    return *options.root;
  }
  const auto& ch = bvh.joints.at(0).channels;
  return std::any_of(ch.begin(), ch.end(), bvh_detail::is_position) ? RootJoint::kFree
                                                                    : RootJoint::kPinned;
}

// why the root is pinned, in the notes (and so in the rig's source)
void root_pinned_note(const BvhFile& bvh, BvhAnimation& anim) {
  const Rig& rig = anim.rig();
  std::string how = "the rig's root bone '" + rig.bone_name[0] + "' is pinned at its head";
  if (rig.root_joint == RootJoint::kFixed) {
    how = "the rig's root '" + rig.bone_name[0] +
          "' is a fixed handle below it, and the bones that start at the joint turn about its "
          "tail";
  }
  anim.notes.push_back("root joint '" + bvh.joints[0].name + "' (line " +
                       std::to_string(bvh.joints[0].line) +
                       ") has no position channels, so it never moves: its joint is pinned "
                       "where it is (" +
                       how + "); --root free frees it");
}

// the file's skeleton, kept in the rig (source_skeleton.h): its joints as the file gave them and
// the bones that turn with each (pivot_rig.h bone_node; ascending, so a joint's first bone is the
// one that carries it)
void keep_source_skeleton(const BvhFile& bvh, const BvhImportOptions& options, PivotRig& pr) {
  SourceSkeleton& s = pr.rig.source_skeleton;
  s.format = "bvh";
  s.axes = options.axes;
  s.scale = options.scale;
  s.frame_time = bvh.frame_time;
  s.joints.resize(bvh.joints.size());
  for (std::size_t i = 0; i < bvh.joints.size(); ++i) {
    const BvhJoint& j = bvh.joints[i];
    SourceJoint& out = s.joints[i];
    out.name = j.name;
    out.parent = j.parent;
    out.offset = j.offset;
    out.end_sites = j.end_sites;
    for (BvhChannel c : j.channels) out.channels.push_back(bvh_channel_name(c));
  }
  for (int b = 0; b < pr.rig.nbone; ++b) {
    if (pr.bone_node[b] >= 0) s.joints[pr.bone_node[b]].bones.push_back(b);
  }
}

// every bone's radius, then its mass and inertia: a human's (bvh_body.h) or a rod's; the welds
// of --weld-constant
void fit_bodies(const BvhFile& bvh, const std::vector<PivotNode>& nodes,
                const BvhImportOptions& options, PivotBones& bones, BvhBody& body) {
  for (BoneSpec& b : bones.specs) {
    b.radius = fitted_radius(options.sizing, (b.tail_world - b.head_world).norm());
    b.collision_radius = b.radius;
  }
  if (options.weld_constant) weld_constant_joints(bvh, bones, body);
  if (body.human) {
    fit_bvh_human(nodes, options, bones, body);
  } else {
    fit_masses(bones.specs, options.sizing);
  }
}

}  // namespace

BvhAnimation bvh_to_rig(const BvhFile& bvh, const std::string& source,
                        const BvhImportOptions& given) {
  if (!(given.scale > 0.0) || !std::isfinite(given.scale)) {
    throw_input_error(source, "", "scale", "must be a positive number");
  }
  check_sizing_options(given.sizing);
  BvhBody body = plan_bvh_body(bvh, source, given);
  BvhImportOptions options = given;
  options.scale = body.scale;  // --height's
  const Quat a = bvh_axes_to_rig(options.axes);
  const double s = options.scale;
  const std::vector<PivotNode> nodes = bvh_pivots(bvh, source, options);
  PivotBones bones = pivot_bones(nodes, source);
  const RootJoint root = bvh_root_joint(bvh, source, options);
  if (root == RootJoint::kPinned) pin_root_pivot(bones);
  fit_bodies(bvh, nodes, options, bones, body);
  BvhAnimation anim;
  anim.body = body;
  anim.pivots = finish_pivot_rig(nodes, bones, source, "");
  keep_source_skeleton(bvh, options, anim.pivots);
  anim.frame_time = bvh.frame_time;
  if (root == RootJoint::kPinned && !options.root) root_pinned_note(bvh, anim);
  if (options.exclude_rest_overlaps) anim.rest_overlaps = exclude_rest_overlaps(anim.pivots.rig);
  held_joint_warnings(bvh, bones, anim);
  position_channel_warnings(bvh, bones, anim);
  weld_turn_warnings(bvh, anim.pivots, anim.warnings);
  write_bvh_notes(source, options, anim);

  // per frame: every pivot's rotation and position in rig axes -> pose; check FK against BVH
  std::vector<Quat> rot, node_rot(nodes.size());
  std::vector<Vec3> pos;
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

const char* bvh_channel_name(BvhChannel channel) {
  return bvh_detail::channel_name(channel);
}

bool bvh_channel_from_name(const std::string& name, BvhChannel& out) {
  return bvh_detail::channel_from_name(name, out);
}

std::string guess_bvh_units(double height, double& suggested_scale) {
  suggested_scale = 0.0;
  if (height >= 100.0 && height <= 250.0) {
    suggested_scale = 0.01;
    return "centimetres";
  }
  if (height >= 1000.0 && height <= 2500.0) {
    suggested_scale = 0.001;
    return "millimetres";
  }
  return "";
}

BvhAnimation load_bvh(const std::string& path, const BvhImportOptions& options) {
  return bvh_to_rig(read_bvh_file(path), path, options);
}

}  // namespace physik
