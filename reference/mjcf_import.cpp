// MJCF -> rig through MuJoCo's own loader; the mapping is documented in mjcf_import.h.
//
// Inertia carried to a bone (world axes, kg m^2 with the model's lengths in m): a body of mass m
// shared by k bones gives bone s the mass m/k and, about the bone's midpoint c_s,
//   I_s = R I_body R^T / k + (m/k) (|r|^2 1 - r r^T),   r = c_s - x_com
// where I_body = diag(body_inertia) about the body's centre of mass x_com = xipos, in the body's
// inertial frame R = ximat (the parallel-axis / Steiner theorem; the sum over the k bones is the
// body's inertia about each bone's own midpoint, as the rig's rod model places each bone's mass
// there). In the bone's rest frame B (columns x, y, z): I_local = B^T I_s B; the rig keeps only
// diag(I_local). Dropped, and reported: the products of inertia (off-diagonal of I_local, which
// include -(m/k) r r^T whenever r is not along a bone axis; report.max_offdiag_inertia), and the
// centre-of-mass offset itself (report.max_com_shift): the rig's bone has its mass at its
// midpoint, so the body's first moment m r (gravity torque about the joint, translation-rotation
// coupling) is not carried. Moments about the midpoint are exact; about the joint they follow
// from the rig's own (midpoint) mass placement, not the body's.
#include "reference/mjcf_import.h"
#include "reference/mujoco_log.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "physik/engine/bone_overlaps.h"
#include "physik/model/errors.h"
#include "physik/model/params.h"
#include "physik/model/rest_limits.h"

namespace physik {

namespace {

Vec3 v3(const mjtNum* p) {
  return Vec3(p[0], p[1], p[2]);
}
Quat q4(const mjtNum* p) {
  return Quat(p[0], p[1], p[2], p[3]);
}
Mat3 m9(const mjtNum* p) {
  Mat3 m;
  m << p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], p[8];
  return m;
}

std::string body_name(const mjModel* m, int b) {
  const char* n = mj_id2name(m, mjOBJ_BODY, b);
  return n && *n ? std::string(n) : "body" + std::to_string(b);
}

// the geometric tip of a leaf body: farthest geom end from the body origin (rest, world)
Vec3 leaf_tip(const mjModel* m, const mjData* d, int b, const Vec3& dir) {
  const Vec3 origin = v3(d->xpos + 3 * b);
  Vec3 best = origin;
  double best_d = 0.0, rbound = 0.0;
  auto consider = [&](const Vec3& p) {
    const double dist = (p - origin).norm();
    if (dist > best_d) {
      best_d = dist;
      best = p;
    }
  };
  for (int g = m->body_geomadr[b]; g >= 0 && g < m->body_geomadr[b] + m->body_geomnum[b]; ++g) {
    const Vec3 c = v3(d->geom_xpos + 3 * g);
    const Mat3 r = m9(d->geom_xmat + 9 * g);
    const mjtNum* size = m->geom_size + 3 * g;
    rbound = std::max(rbound, static_cast<double>(m->geom_rbound[g]));
    switch (m->geom_type[g]) {
      case mjGEOM_CAPSULE:
      case mjGEOM_CYLINDER: {
        const double half = size[1] + (m->geom_type[g] == mjGEOM_CAPSULE ? size[0] : 0.0);
        consider(c + half * r.col(2));
        consider(c - half * r.col(2));
        break;
      }
      case mjGEOM_BOX:
      case mjGEOM_ELLIPSOID: {
        int k = 0;
        for (int a = 1; a < 3; ++a) k = size[a] > size[k] ? a : k;
        consider(c + size[k] * r.col(k));
        consider(c - size[k] * r.col(k));
        break;
      }
      case mjGEOM_PLANE:
        break;  // infinite: no tip
      default:  // sphere, mesh, hfield...
        consider(c + m->geom_rbound[g] * dir);
        break;
    }
  }
  return best;
}

}  // namespace

MjcfRig load_mjcf(const std::string& path, const MjcfImportOptions& options) {
  route_mujoco_warnings_to_stderr();
  char error[1000] = "";
  mjModel* raw = mj_loadXML(path.c_str(), nullptr, error, sizeof(error));
  if (!raw) {
    std::string msg = error;
    std::replace(msg.begin(), msg.end(), '\n', ' ');
    throw_input_error(path, "", "", "MuJoCo cannot load it: " + msg);
  }
  MjModelPtr m(raw);
  return import_mjcf_model(m.get(), path, options);
}

namespace {

// the subtree that becomes the rig: a named body, or the largest top-level one; the other
// top-level bodies are reported as skipped
int choose_root(const mjModel* m, const std::string& source, const MjcfImportOptions& options,
                MjcfImportReport& rep) {
  std::vector<int> subtree_size(m->nbody, 1);
  for (int b = m->nbody - 1; b > 0; --b) subtree_size[m->body_parentid[b]] += subtree_size[b];
  int root = -1;
  if (!options.root_body.empty()) {
    root = mj_name2id(m, mjOBJ_BODY, options.root_body.c_str());
    if (root <= 0) {
      throw_input_error(source, "body '" + options.root_body + "'", "--body",
                        "no such body in the model");
    }
  } else {
    for (int b = 1; b < m->nbody; ++b) {
      if (m->body_parentid[b] == 0 && (root < 0 || subtree_size[b] > subtree_size[root])) root = b;
    }
  }
  for (int b = 1; b < m->nbody; ++b) {
    if (m->body_parentid[b] == 0 && b != root) rep.skipped_bodies.push_back(body_name(m, b));
  }
  return root;
}

// one pivot per body of the subtree at its rest origin, parents first (MuJoCo's body order is)
std::vector<PivotNode> subtree_pivots(const mjModel* m, const mjData* d, int root, MjcfRig& out) {
  std::vector<int> node_of(m->nbody, -1);
  std::vector<PivotNode> nodes;
  for (int b = root; b < m->nbody; ++b) {
    if (b != root && (m->body_parentid[b] <= 0 || node_of[m->body_parentid[b]] < 0)) continue;
    node_of[b] = static_cast<int>(nodes.size());
    PivotNode n;
    n.name = body_name(m, b);
    n.parent = b == root ? -1 : node_of[m->body_parentid[b]];
    n.rest_world = v3(d->xpos + 3 * b);
    nodes.push_back(n);
    out.node_body.push_back(b);
    out.node_rest_xquat.push_back(q4(d->xquat + 4 * b).normalized());
  }
  return nodes;
}

// pivots at their parent's own origin (no bone of their own)
std::vector<bool> zero_offsets(const std::vector<PivotNode>& nodes, double extent) {
  std::vector<bool> zero(nodes.size(), false);
  for (std::size_t i = 1; i < nodes.size(); ++i) {
    zero[i] = (nodes[i].rest_world - nodes[nodes[i].parent].rest_world).norm() <= 1e-9 * extent;
  }
  return zero;
}

// leaves get a tail from their geometry (a child at the body's own origin passes on whether it
// has children away), else a short stub along the direction from their nearest ancestor away
void add_leaf_tips(const mjModel* m, const mjData* d, const MjcfRig& out,
                   const std::vector<bool>& zero_offset, double extent,
                   std::vector<PivotNode>& nodes) {
  std::vector<bool> has_child_away(nodes.size(), false);
  for (std::size_t i = nodes.size() - 1; i >= 1; --i) {
    if (!zero_offset[i] || has_child_away[i]) has_child_away[nodes[i].parent] = true;
  }
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    if (has_child_away[i]) continue;
    const int b = out.node_body[i];
    Vec3 dir = Vec3::UnitZ();
    double offset_len = 0.0;
    for (int p = nodes[i].parent; p >= 0; p = nodes[p].parent) {
      const Vec3 off = nodes[i].rest_world - nodes[p].rest_world;
      if (off.norm() > 1e-9 * extent) {
        dir = off.normalized();
        offset_len = off.norm();
        break;
      }
    }
    Vec3 tip = leaf_tip(m, d, b, dir);
    if ((tip - nodes[i].rest_world).norm() <= 1e-6 * extent) {
      double rb = 0.0;
      for (int g = m->body_geomadr[b]; g >= 0 && g < m->body_geomadr[b] + m->body_geomnum[b]; ++g) {
        rb = std::max(rb, static_cast<double>(m->geom_rbound[g]));
      }
      tip = nodes[i].rest_world + std::max({rb, 0.1 * offset_len, 0.01}) * dir;
    }
    nodes[i].ends_world.push_back(tip);
  }
}

// the joints of one body, or of a chain of bodies
struct BodyJoints {
  std::vector<std::pair<Vec3, std::array<double, 3>>> hinges;  // world axis; lo, hi, limited
  std::vector<std::string> hinge_names;                        // (nhinge) MuJoCo's joint names
  std::vector<std::string> slides;  // "slide joint 'j' of body 'b'": dropped
  std::string ball_name;
  bool ball = false, ball_limited = false, free = false;
  double ball_range = 0.0;
};

std::string joint_name(const mjModel* m, int j) {
  const char* n = mj_id2name(m, mjOBJ_JOINT, j);
  return n && *n ? std::string(n) : "joint" + std::to_string(j);
}

std::vector<BodyJoints> body_joints(const mjModel* m, const mjData* d, const MjcfRig& out,
                                    std::size_t nnode, MjcfImportReport& rep) {
  std::vector<BodyJoints> bj(nnode);
  for (std::size_t i = 0; i < nnode; ++i) {
    const int b = out.node_body[i];
    const Mat3 xmat = m9(d->xmat + 9 * b);
    for (int j = m->body_jntadr[b]; j >= 0 && j < m->body_jntadr[b] + m->body_jntnum[b]; ++j) {
      const double lo = m->jnt_range[2 * j], hi = m->jnt_range[2 * j + 1];
      const bool limited = m->jnt_limited[j] != 0;
      switch (m->jnt_type[j]) {
        case mjJNT_FREE:
          bj[i].free = true;
          break;
        case mjJNT_BALL:
          bj[i].ball = true;
          bj[i].ball_limited = bj[i].ball_limited || limited;
          bj[i].ball_range = std::max(lo, hi);
          bj[i].ball_name = joint_name(m, j);
          break;
        case mjJNT_SLIDE:
          ++rep.slide_joints_dropped;
          bj[i].slides.push_back("slide joint '" + joint_name(m, j) + "' of body '" +
                                 body_name(m, b) + "'");
          break;
        case mjJNT_HINGE:
          bj[i].hinges.push_back(
              {(xmat * v3(m->jnt_axis + 3 * j)).normalized(), {lo, hi, limited ? 1.0 : 0.0}});
          bj[i].hinge_names.push_back(joint_name(m, j));
          break;
      }
    }
  }
  return bj;
}

// a bone's rotation relative to its parent bone is made by the joints of its own body and of
// the bodies between (zero-offset bodies have no bone of their own)
BodyJoints chain_joints(const PivotBones& bones, const std::vector<PivotNode>& nodes,
                        const std::vector<BodyJoints>& bj, int s) {
  BodyJoints all;
  const int stop = s == 0 ? -1 : bones.spec_node[bones.spec_parent[s]];
  for (int n = bones.spec_node[s]; n >= 0 && n != stop; n = nodes[n].parent) {
    const BodyJoints& j = bj[n];
    all.hinges.insert(all.hinges.begin(), j.hinges.begin(), j.hinges.end());
    all.hinge_names.insert(all.hinge_names.begin(), j.hinge_names.begin(), j.hinge_names.end());
    all.slides.insert(all.slides.begin(), j.slides.begin(), j.slides.end());
    if (!j.ball_name.empty()) all.ball_name = j.ball_name;
    all.ball = all.ball || j.ball;
    all.ball_limited = all.ball_limited || j.ball_limited;
    all.ball_range = std::max(all.ball_range, j.ball_range);
    all.free = all.free || j.free;
    if (s == 0) break;
  }
  return all;
}

const double kAlign = std::cos(deg2rad(20.0));  // a hinge within 20 deg of a bone axis maps to it

// a range bound clamped to +-180 deg, counted and named with the bone and the joint
double clamp_pi(double v, MjcfImportReport& rep, const std::string& bone,
                const std::string& joint) {
  if (v < -kPi || v > kPi) {
    ++rep.clamped_ranges;
    std::ostringstream s;
    s.precision(4);
    s << "bone '" << bone << "': joint '" << joint << "' range bound " << rad2deg(v)
      << " deg clamped to " << (v < 0 ? "-180" : "180") << " deg";
    rep.clamped.push_back(s.str());
  }
  return std::clamp(v, -kPi, kPi);
}

// the bone's roll: its local x is the first hinge axis not along the bone
void roll_to_first_hinge(const BodyJoints& j, BoneSpec& spec) {
  const Vec3 y = (spec.tail_world - spec.head_world).normalized();
  for (const auto& h : j.hinges) {
    const Vec3 perp = h.first - h.first.dot(y) * y;
    if (std::abs(h.first.dot(y)) < kAlign && perp.norm() > 1e-9) {
      const Vec3 x = perp.normalized();
      spec.rest_frame_world.col(0) = x;
      spec.rest_frame_world.col(1) = y;
      spec.rest_frame_world.col(2) = x.cross(y);
      return;
    }
  }
}

// joints -> per-axis limits (see the header's table)
void limits_from_joints(const BodyJoints& j, BoneSpec& spec, MjcfImportReport& rep) {
  for (AxisLimit& l : spec.limit) l = AxisLimit{};
  for (const std::string& slide : j.slides) {
    rep.dropped_slides.push_back("bone '" + spec.name + "': " + slide + " dropped");
  }
  if (j.free) return;
  if (j.ball) {
    if (j.ball_limited) {
      const double r = clamp_pi(j.ball_range, rep, spec.name, j.ball_name);
      for (AxisLimit& l : spec.limit) l = AxisLimit{true, -r, r};
    }
    return;
  }
  for (AxisLimit& l : spec.limit) l = AxisLimit{true, 0.0, 0.0};  // welded unless a hinge frees it
  std::string unaligned;
  for (std::size_t hi_index = 0; hi_index < j.hinges.size(); ++hi_index) {
    const auto& h = j.hinges[hi_index];
    const std::string& name = j.hinge_names[hi_index];
    const Vec3 local = spec.rest_frame_world.transpose() * h.first;
    int k = 0;
    for (int a = 1; a < 3; ++a) k = std::abs(local[a]) > std::abs(local[k]) ? a : k;
    if (std::abs(local[k]) < kAlign) {
      std::ostringstream s;
      s.precision(3);
      s << (unaligned.empty() ? "" : ", ") << "hinge '" << name << "' "
        << rad2deg(std::acos(std::min(1.0, std::abs(local[k])))) << " deg from every bone axis";
      unaligned += s.str();
      continue;
    }
    rep.max_hinge_misalignment_deg = std::max(
        rep.max_hinge_misalignment_deg, rad2deg(std::acos(std::min(1.0, std::abs(local[k])))));
    const double lo = h.second[0], hi = h.second[1];
    if (h.second[2] == 0.0) {
      spec.limit[k] = AxisLimit{};
    } else if (local[k] > 0) {
      spec.limit[k] =
          AxisLimit{true, clamp_pi(lo, rep, spec.name, name), clamp_pi(hi, rep, spec.name, name)};
    } else {
      spec.limit[k] =
          AxisLimit{true, clamp_pi(-hi, rep, spec.name, name), clamp_pi(-lo, rep, spec.name, name)};
    }
  }
  if (!unaligned.empty()) {
    ++rep.unaligned_hinges;
    rep.freed_bones.push_back(
        "bone '" + spec.name + "': " + unaligned +
        ": made free and unlimited (a hinge maps to a bone axis within 20 deg)");
    for (AxisLimit& l : spec.limit) l = AxisLimit{};
  }
}

// a body's joints are its first segment's: its other segments are welded to that one
// (pivot_bones), and a bone whose chain of bodies has no joint at all is welded to its parent
// (MuJoCo's jointless body); a welded bone has no limits of its own
void weld_jointless(const BodyJoints& j, int s, PivotBones& bones) {
  BoneSpec& spec = bones.specs[s];
  if (s > 0 && !j.free && !j.ball && j.hinges.empty() && spec.weld.empty()) {
    spec.weld = bones.specs[bones.spec_parent[s]].name;
  }
  if (!spec.weld.empty()) spec.limit = {};
}

// the root body's joint to the world: free, a hinge or ball (pinned at the root bone's head,
// limited as any bone), or none (fixed)
RootJoint root_joint_of(const BodyJoints& j, BoneSpec& root, MjcfImportReport& rep) {
  if (j.free) return RootJoint::kFree;
  if (j.ball || !j.hinges.empty()) {
    rep.root_joint = "pinned";
    return RootJoint::kPinned;
  }
  root.limit = {};
  rep.root_joint = "fixed";
  return RootJoint::kFixed;
}

// the bones that carry body i's mass: its own, else those of its zero-offset descendants, else
// the bone ending at its origin
std::vector<int> mass_carriers(std::size_t i, const std::vector<std::vector<int>>& followers,
                               const std::vector<PivotNode>& nodes,
                               const std::vector<bool>& zero_offset, const PivotBones& bones) {
  std::vector<int> f = followers[i];
  for (std::size_t j = i + 1; j < nodes.size() && f.empty(); ++j) {
    int n = static_cast<int>(j);
    while (n > static_cast<int>(i) && zero_offset[n]) n = nodes[n].parent;
    if (n == static_cast<int>(i)) f = followers[j];
  }
  if (f.empty()) f = {std::max(0, bones.node_incoming[i])};
  return f;
}

// each body's mass and inertia shared by the bones that carry it; inertia carried to each bone's
// midpoint with the parallel-axis (Steiner) term, world axes
void share_body_masses(const mjModel* m, const mjData* d, const MjcfRig& out,
                       const std::vector<PivotNode>& nodes, const std::vector<bool>& zero_offset,
                       const PivotBones& bones, std::vector<double>& mass,
                       std::vector<Mat3>& inertia, MjcfImportReport& rep) {
  const int nspec = static_cast<int>(bones.specs.size());
  mass.assign(nspec, 0.0);
  inertia.assign(nspec, Mat3::Zero());
  std::vector<std::vector<int>> followers(nodes.size());
  for (int s = 0; s < nspec; ++s) followers[bones.spec_node[s]].push_back(s);
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const int b = out.node_body[i];
    rep.model_mass += m->body_mass[b];
    const std::vector<int> f = mass_carriers(i, followers, nodes, zero_offset, bones);
    const Mat3 ri = m9(d->ximat + 9 * b);
    const Mat3 iw = ri * v3(m->body_inertia + 3 * b).asDiagonal() * ri.transpose();
    const Vec3 com = v3(d->xipos + 3 * b);
    const double share = m->body_mass[b] / static_cast<double>(f.size());
    Vec3 mid = Vec3::Zero();
    for (int s : f) {
      const Vec3 bone_mid = 0.5 * (bones.specs[s].head_world + bones.specs[s].tail_world);
      const Vec3 r = bone_mid - com;
      mass[s] += share;
      inertia[s] += iw / static_cast<double>(f.size()) +
                    share * (r.squaredNorm() * Mat3::Identity() - r * r.transpose());
      mid += bone_mid / static_cast<double>(f.size());
    }
    if (m->body_mass[b] > 0) {
      rep.max_com_shift = std::max(rep.max_com_shift, (mid - v3(d->xipos + 3 * b)).norm());
    }
  }
}

// masses (with a floor for massless bones) and the diagonal of each inertia in the bone's frame
// into the specs; a diagonal no real body has falls back to the cylinder
void set_spec_masses(const std::vector<double>& mass_in, const std::vector<Mat3>& inertia,
                     PivotBones& bones, MjcfImportReport& rep) {
  const int nspec = static_cast<int>(bones.specs.size());
  std::vector<double> mass = mass_in;
  double mean = 0.0;
  for (double v : mass) mean += v / nspec;
  const double floor_mass = mean > 0.0 ? 1e-3 * mean : 1e-3;
  for (int s = 0; s < nspec; ++s) {
    BoneSpec& spec = bones.specs[s];
    if (!(mass[s] > 0.0)) {
      ++rep.mass_floor_bones;
      mass[s] = floor_mass;
    }
    spec.mass = mass[s];
    const Mat3 local = spec.rest_frame_world.transpose() * inertia[s] * spec.rest_frame_world;
    const Vec3 diag = local.diagonal();
    const bool triangle = diag.x() + diag.y() >= diag.z() * (1 - 1e-9) &&
                          diag.y() + diag.z() >= diag.x() * (1 - 1e-9) &&
                          diag.z() + diag.x() >= diag.y() * (1 - 1e-9);
    if (diag.allFinite() && diag.minCoeff() > 0.0 && triangle) {
      spec.inertia_local = diag;
      Mat3 off = local;
      off.diagonal().setZero();
      rep.max_offdiag_inertia =
          std::max(rep.max_offdiag_inertia, off.cwiseAbs().maxCoeff() / diag.maxCoeff());
    } else {
      spec.inertia_local.setZero();  // the cylinder of the bone's radius
      ++rep.cylinder_inertia_bones;
    }
    rep.rig_mass += spec.mass;
  }
}

// the radius (size[0]) of body b's capsule geom best aligned with `axis_world`, if it is better
// aligned than `best_alignment` (|cos| of the angle, updated); 0 when none is
double aligned_capsule_radius(const mjModel* m, const mjData* d, int b, const Vec3& axis_world,
                              double& best_alignment) {
  double radius = 0.0;
  for (int g = m->body_geomadr[b]; g >= 0 && g < m->body_geomadr[b] + m->body_geomnum[b]; ++g) {
    if (m->geom_type[g] != mjGEOM_CAPSULE) continue;
    const double alignment = std::abs(m9(d->geom_xmat + 9 * g).col(2).dot(axis_world));
    if (alignment > best_alignment) {
      best_alignment = alignment;
      radius = m->geom_size[3 * g];
    }
  }
  return radius;
}

// the radius (size[0]) of body b's largest sphere geom; 0 when it has none
double largest_sphere_radius(const mjModel* m, int b) {
  double radius = 0.0;
  for (int g = m->body_geomadr[b]; g >= 0 && g < m->body_geomadr[b] + m->body_geomnum[b]; ++g) {
    if (m->geom_type[g] == mjGEOM_SPHERE)
      radius = std::max(radius, static_cast<double>(m->geom_size[3 * g]));
  }
  return radius;
}

// bone radii from the capsule geoms of the body each bone follows and of the bodies at its origin
// (zero-offset ancestors: a shin whose twist body carries the bone): the capsule whose axis (geom
// z) is best aligned with the bone, first on ties. Its size[0] is the radius in the model's length
// unit, which is the rig's. A bone with no capsule there takes the largest sphere geom of those
// bodies (a head, a hand: the sphere is the body's thickness in every direction); a bone with
// neither gets the radius fitted to its length (rig_sizing.h), and is listed in the report. A
// --radius replaces them all.
void set_geom_radii(const mjModel* m, const mjData* d, const MjcfRig& out,
                    const std::vector<PivotNode>& nodes, const std::vector<bool>& zero_offset,
                    const SizingOptions& sizing, PivotBones& bones, MjcfImportReport& rep) {
  for (std::size_t s = 0; s < bones.specs.size(); ++s) {
    BoneSpec& spec = bones.specs[s];
    const Vec3 axis = (spec.tail_world - spec.head_world).normalized();
    double best_alignment = -1.0, radius = 0.0, sphere = 0.0;
    for (int n = bones.spec_node[s]; n >= 0; n = zero_offset[n] ? nodes[n].parent : -1) {
      const double r = aligned_capsule_radius(m, d, out.node_body[n], axis, best_alignment);
      if (r > 0.0) radius = r;
      sphere = std::max(sphere, largest_sphere_radius(m, out.node_body[n]));
    }
    if (radius <= 0.0) radius = sphere;
    if (radius <= 0.0) {
      rep.bones_fitted_radius.push_back(spec.name);
      radius = fitted_radius(sizing, (spec.tail_world - spec.head_world).norm());
    }
    if (sizing.radius > 0.0) radius = sizing.radius;
    spec.collision_radius = radius;
    spec.radius = radius;
  }
}

// one note: a heading and its list ("" when the list is empty)
void add_note(const std::string& heading, const std::vector<std::string>& items,
              std::vector<std::string>& notes) {
  if (items.empty()) return;
  std::string s = heading + " (" + std::to_string(items.size()) + "): ";
  for (std::size_t i = 0; i < items.size(); ++i) s += (i ? "; " : "") + items[i];
  notes.push_back(s);
}

// the rig's source notes and units: where it came from and every change to the model's joints
void write_mjcf_notes(const std::string& source, const MjcfImportOptions& options,
                      const MjcfImportReport& rep, Rig& rig) {
  std::ostringstream s;
  s.precision(6);
  s << "rig from-mjcf " << source << ": " << rig.nbone << " bones from " << rep.nbody_used << " of "
    << rep.nbody_model << " bodies; mass " << rep.rig_mass << " kg (model " << rep.model_mass
    << " kg)";
  const SizingOptions& z = options.sizing;
  if (z.radius > 0.0) s << "; --radius " << z.radius;
  if (z.mass_per_length > 0.0) s << "; --mass-per-length " << z.mass_per_length;
  if (z.total_mass > 0.0) s << "; --total-mass " << z.total_mass;
  rig.source.push_back(s.str());
  add_note("slide joints dropped", rep.dropped_slides, rig.source);
  add_note("bones freed by unaligned hinges", rep.freed_bones, rig.source);
  add_note("ranges clamped to +-180 deg", rep.clamped, rig.source);
  std::ostringstream t;
  t << "limits widened so that the rest angle is at the edge of the torsion band (tolerance "
    << rep.fitted_tolerance << ")";
  add_note(t.str(), rep.widened_limits, rig.source);
  add_note("collision_exclude: bone pairs whose capsules overlap at rest", rep.rest_overlaps,
           rig.source);
  std::ostringstream r;
  r << "radius " << kRadiusPerLength << " x length (no capsule or sphere geom)";
  if (z.radius <= 0.0) add_note(r.str(), rep.bones_fitted_radius, rig.source);
  rig.units = "the model's (lengths read as metres), kg";
}

}  // namespace

namespace {

// the model's data, or an InputError naming the file where MuJoCo cannot allocate it
MjDataPtr import_data(const mjModel* m, const std::string& source) {
  try {
    return make_mjdata(m);
  } catch (const MjcfAllocationError& e) {
    throw_input_error(source, "", "size", e.what());
  }
}

}  // namespace

MjcfRig import_mjcf_model(const mjModel* m, const std::string& source,
                          const MjcfImportOptions& options) {
  MjcfRig out;
  MjcfImportReport& rep = out.report;
  rep.nbody_model = m->nbody - 1;
  if (m->nbody < 2) throw_input_error(source, "", "worldbody", "the model has no body");
  const MjDataPtr data = import_data(m, source);
  mjData* d = data.get();
  mj_resetData(m, d);  // qpos = qpos0
  mj_kinematics(m, d);

  // the kinematic tree: pivots, leaf tips, bones
  const int root = choose_root(m, source, options, rep);
  std::vector<PivotNode> nodes = subtree_pivots(m, d, root, out);
  rep.nbody_used = static_cast<int>(nodes.size());
  double extent = 1.0;
  for (const PivotNode& n : nodes) extent = std::max(extent, n.rest_world.cwiseAbs().maxCoeff());
  const std::vector<bool> zero_offset = zero_offsets(nodes, extent);
  add_leaf_tips(m, d, out, zero_offset, extent, nodes);
  PivotBones bones = pivot_bones(nodes, source);

  // frames (roll to the first hinge) and limits per bone, the root's joint to the world; limits
  // whose band holds the rest angle widened to it (rest_limits.h)
  const std::vector<BodyJoints> bj = body_joints(m, d, out, nodes.size(), rep);
  for (int s = 0; s < static_cast<int>(bones.specs.size()); ++s) {
    const BodyJoints j = chain_joints(bones, nodes, bj, s);
    roll_to_first_hinge(j, bones.specs[s]);
    limits_from_joints(j, bones.specs[s], rep);
    weld_jointless(j, s, bones);
  }
  bones.root_joint = root_joint_of(chain_joints(bones, nodes, bj, 0), bones.specs[0], rep);
  rep.fitted_tolerance = preset_params("robust").torsion_tolerance;
  for (const RestBandProblem& p : fit_limits_to_rest(bones.specs, rep.fitted_tolerance)) {
    rep.widened_limits.push_back(describe(p, bones.specs[p.bone].name));
  }

  // mass and inertia: each body shared by the bones that follow it; radii from the geoms
  check_sizing_options(options.sizing);
  std::vector<double> mass;
  std::vector<Mat3> inertia;
  share_body_masses(m, d, out, nodes, zero_offset, bones, mass, inertia, rep);
  set_spec_masses(mass, inertia, bones, rep);
  set_geom_radii(m, d, out, nodes, zero_offset, options.sizing, bones, rep);
  fit_masses(bones.specs, options.sizing, std::vector<bool>(bones.specs.size(), true));
  if (options.sizing.mass_per_length > 0.0 || options.sizing.total_mass > 0.0) {
    rep.rig_mass = 0.0;
    for (const BoneSpec& b : bones.specs) rep.rig_mass += b.mass;
  }

  const char* model_name = m->nnames > 0 ? m->names : "";  // the model name comes first
  out.pivots = finish_pivot_rig(nodes, bones, source, model_name);
  // the pairs of capsules that overlap at rest never collide
  Rig& rig = out.pivots.rig;
  for (const BoneOverlap& o : exclude_rest_overlaps(rig)) {
    rep.rest_overlaps.push_back(rig.bone_name[o.a] + "/" + rig.bone_name[o.b]);
  }
  write_mjcf_notes(source, options, rep, rig);
  return out;
}

Pose pose_from_mujoco(const MjcfRig& mr, const mjData* d) {
  const std::size_t n = mr.node_body.size();
  std::vector<Quat> rot(n);
  for (std::size_t i = 0; i < n; ++i) {
    const int b = mr.node_body[i];
    rot[i] = (q4(d->xquat + 4 * b).normalized() * mr.node_rest_xquat[i].conjugate()).normalized();
  }
  BoneFrames scratch;
  Pose pose;
  pivot_pose(mr.pivots, rot, v3(d->xpos + 3 * mr.node_body[0]), scratch, pose);
  return pose;
}

}  // namespace physik
