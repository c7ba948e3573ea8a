#include "physik/model/rig.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <unordered_map>

#include "physik/model/errors.h"
#include "physik/model/human_template.h"
#include "physik/model/joint_coordinates.h"
#include "physik/model/names.h"

namespace physik {

namespace {

std::string bone_element(const BoneSpec& b, std::size_t index) {
  std::ostringstream s;
  s << "bones[" << index << "] '" << b.name << "'";
  return s.str();
}

// the specs' names in file order (the did-you-mean of an unknown parent or weld)
std::vector<std::string> spec_names(const std::vector<BoneSpec>& specs) {
  std::vector<std::string> names;
  names.reserve(specs.size());
  for (const BoneSpec& b : specs) names.push_back(b.name);
  return names;
}

std::string fmt(double v) {
  std::ostringstream s;
  s.precision(6);
  s << v;
  return s.str();
}

}  // namespace

Vec3 cylinder_inertia(double mass, double radius, double length) {
  const double axial = 0.5 * mass * radius * radius;
  const double transverse = mass * (3.0 * radius * radius + length * length) / 12.0;
  return Vec3(transverse, axial, transverse);
}

Mat3 rest_frame_from_roll(const Vec3& head_world, const Vec3& tail_world, double roll) {
  const Vec3 dir = (tail_world - head_world).normalized();
  const Vec3 y(0, 1, 0);
  Mat3 align;
  if (dir.dot(y) < -1.0 + 1e-12) {
    // antiparallel: Blender turns 180 deg about Z
    align = Eigen::AngleAxisd(kPi, Vec3::UnitZ()).toRotationMatrix();
  } else {
    align = Quat::FromTwoVectors(y, dir).toRotationMatrix();
  }
  return align * Eigen::AngleAxisd(roll, y).toRotationMatrix();
}

int Rig::find_bone(const std::string& n) const {
  auto it = std::find(bone_name.begin(), bone_name.end(), n);
  return it == bone_name.end() ? -1 : static_cast<int>(it - bone_name.begin());
}

double Rig::total_mass() const {
  double m = 0.0;
  for (double b : bone_mass) m += b;
  return m;
}

int Rig::max_bones_per_joint() const {
  int best = 0;
  for (const Joint& j : joints) best = std::max(best, j.nbone());
  return best;
}

const char* to_string(RootJoint root) {
  switch (root) {
    case RootJoint::kFree:
      return "free";
    case RootJoint::kPinned:
      return "pinned";
    case RootJoint::kFixed:
      return "fixed";
  }
  return "?";
}

const char* to_string(JointType type) {
  switch (type) {
    case JointType::kFree:
      return "free";
    case JointType::kBall:
      return "ball";
    case JointType::kHinge:
      return "hinge";
    case JointType::kUniversal:
      return "universal";
    case JointType::kWeld:
      return "weld";
  }
  return "?";
}

bool Rig::has_locked_joints() const {
  for (int i = 0; i < nbone; ++i) {
    const JointType t = bone_joint_type[i];
    if (t == JointType::kHinge || t == JointType::kUniversal) return true;
    if (t == JointType::kWeld && bone_weld[i] < 0 && !(i == 0 && root_joint == RootJoint::kFixed)) {
      return true;
    }
  }
  return false;
}

bool Rig::has_welds() const {
  return std::any_of(bone_weld.begin(), bone_weld.end(), [](int w) { return w >= 0; });
}

int Rig::bone_dof(int bone) const {
  if (bone_joint_type[bone] == JointType::kWeld) return 0;
  int dof = 3;
  for (const AxisLimit& a : bone_limit[bone]) dof -= a.locked() ? 1 : 0;
  return dof;
}

double Rig::height() const {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (int i = 0; i < nbone; ++i) {
    for (const Vec3* p : {&bone_rest_head_world[i], &bone_rest_tail_world[i]}) {
      lo = std::min(lo, p->z());
      hi = std::max(hi, p->z());
    }
  }
  return nbone ? hi - lo : 0.0;
}

double Rig::length_scale() const {
  double sum = 0.0;
  for (double l : bone_length) sum += l;
  return nbone ? sum / nbone : 0.0;
}

double Rig::reference_length() const {
  return std::max(height(), length_scale());
}

double Rig::chain_length(int bone, double alpha) const {
  double r = alpha * bone_length[bone];
  for (int b = bone_parent[bone]; b >= 0; b = bone_parent[b]) r += bone_length[b];
  return r;
}

bool Rig::bones_share_joint(int a, int b) const {
  const int pa = bone_parent[a], pb = bone_parent[b];
  return pa == b || pb == a || (pa >= 0 && pa == pb) || bone_body[a] == bone_body[b];
}

bool Rig::collision_excluded(int a, int b) const {
  const std::pair<int, int> key{std::min(a, b), std::max(a, b)};
  return std::binary_search(collision_exclude.begin(), collision_exclude.end(), key);
}

void set_collision_exclude(Rig& rig, const std::vector<std::pair<std::string, std::string>>& pairs,
                           const std::string& source) {
  std::unordered_map<std::string, int> index_of;
  index_of.reserve(rig.nbone);
  for (int b = 0; b < rig.nbone; ++b) index_of.emplace(rig.bone_name[b], b);
  std::vector<std::pair<int, int>> out;
  out.reserve(pairs.size());
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    const std::string field = "collision_exclude[" + std::to_string(i) + "]";
    int b[2];
    for (int k = 0; k < 2; ++k) {
      const std::string& name = k == 0 ? pairs[i].first : pairs[i].second;
      auto it = index_of.find(name);
      if (it == index_of.end()) throw_input_error(source, "", field, unknown_bone(name, rig));
      b[k] = it->second;
    }
    if (b[0] == b[1]) {
      throw_input_error(source, "", field,
                        "bone '" + pairs[i].first +
                            "' is paired with itself (an exclusion names two different bones)");
    }
    out.emplace_back(std::min(b[0], b[1]), std::max(b[0], b[1]));
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  rig.collision_exclude = std::move(out);
}

namespace {

// stage 1: names are non-empty, printable UTF-8 and unique; returns name -> index in `specs`
std::unordered_map<std::string, std::size_t> index_names(const std::vector<BoneSpec>& specs,
                                                         const std::string& source) {
  std::unordered_map<std::string, std::size_t> index_of;
  index_of.reserve(specs.size());
  for (std::size_t i = 0; i < specs.size(); ++i) {
    const BoneSpec& b = specs[i];
    if (b.name.empty()) throw_input_error(source, bone_element(b, i), "name", "empty bone name");
    const std::string bad = name_problem(b.name);
    // the element leaves the name out: it would carry the bad bytes into the message
    if (!bad.empty()) {
      throw_input_error(source, "bones[" + std::to_string(i) + "]", "name", bad);
    }
    if (!index_of.emplace(b.name, i).second) {
      throw_input_error(
          source, bone_element(b, i), "name",
          "duplicate bone name (first used by bones[" + std::to_string(index_of[b.name]) + "])");
    }
  }
  return index_of;
}

// stage 2: parents are known bones and exactly one bone is the root; fills each bone's children
// (in file order) and returns the root's index in `specs`
std::size_t link_parents(const std::vector<BoneSpec>& specs,
                         const std::unordered_map<std::string, std::size_t>& index_of,
                         const std::string& source,
                         std::vector<std::vector<std::size_t>>& children) {
  children.assign(specs.size(), {});
  std::size_t root = specs.size();
  for (std::size_t i = 0; i < specs.size(); ++i) {
    const BoneSpec& b = specs[i];
    if (b.parent.empty()) {
      if (root != specs.size()) {
        throw_input_error(source, bone_element(b, i), "parent",
                          "a second root (bone '" + specs[root].name +
                              "' is already the root; a rig has exactly one)");
      }
      root = i;
      continue;
    }
    if (b.parent == b.name) {
      throw_input_error(source, bone_element(b, i), "parent", "a bone cannot be its own parent");
    }
    auto it = index_of.find(b.parent);
    if (it == index_of.end()) {
      throw_input_error(source, bone_element(b, i), "parent",
                        unknown_bone(b.parent, spec_names(specs)));
    }
    children[it->second].push_back(i);
  }
  if (root == specs.size()) {
    throw_input_error(source, "", "parent",
                      "no root bone (every bone has a parent, so the parents form a cycle)");
  }
  return root;
}

// stage 2b: welds name the bone's parent or a sibling listed before it (the group's first bone
// then comes first in DFS order), form no cycle, and sit on bones without limits below the root
void check_welds(const std::vector<BoneSpec>& specs,
                 const std::unordered_map<std::string, std::size_t>& index_of,
                 const std::vector<std::vector<std::size_t>>& children, const std::string& source) {
  const std::size_t n = specs.size();
  std::vector<std::size_t> target(n, n);
  for (std::size_t i = 0; i < n; ++i) {
    const BoneSpec& b = specs[i];
    if (b.weld.empty()) continue;
    const std::string el = bone_element(b, i);
    if (b.parent.empty()) {
      throw_input_error(source, el, "weld",
                        "the root has no parent to weld to (a root held to the world is the "
                        "rig's \"root\": \"fixed\")");
    }
    if (b.weld == b.name) throw_input_error(source, el, "weld", "a bone cannot weld to itself");
    auto it = index_of.find(b.weld);
    if (it == index_of.end()) {
      throw_input_error(source, el, "weld", unknown_bone(b.weld, spec_names(specs)));
    }
    const BoneSpec& w = specs[it->second];
    if (b.weld != b.parent && w.parent != b.parent) {
      throw_input_error(source, el, "weld",
                        "'" + b.weld + "' is neither this bone's parent '" + b.parent +
                            "' nor a sibling of it (a bone welds to its parent, or to a bone "
                            "with the same parent)");
    }
    for (int a = 0; a < 3; ++a) {
      if (b.limit[a].limited) {
        throw_input_error(
            source, el, "limits_deg",
            "a welded bone has no degree of freedom to limit (welded to '" + b.weld + "')");
      }
    }
    target[i] = it->second;
  }
  // sibling welds: a chain never returns to where it started, and ends on an earlier sibling
  for (std::size_t i = 0; i < n; ++i) {
    std::string path = specs[i].name;
    std::size_t k = i, steps = 0;
    while (target[k] != n && specs[k].weld != specs[k].parent) {
      k = target[k];
      path += " -> " + specs[k].name;
      if (k == i || ++steps > n) {
        throw_input_error(source, bone_element(specs[i], i), "weld", "weld cycle " + path);
      }
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (target[i] == n || specs[i].weld == specs[i].parent) continue;
    const std::vector<std::size_t>& kids = children[index_of.at(specs[i].parent)];
    const auto pos = [&](std::size_t x) { return std::find(kids.begin(), kids.end(), x); };
    if (pos(target[i]) > pos(i)) {
      throw_input_error(source, bone_element(specs[i], i), "weld",
                        "the sibling '" + specs[i].weld +
                            "' it welds to must come before it among the children of '" +
                            specs[i].parent + "'");
    }
  }
}

// stage 3: depth-first order from the root (children in file order); a bone the walk never
// reaches sits on a parent cycle
std::vector<std::size_t> dfs_order(const std::vector<BoneSpec>& specs,
                                   const std::vector<std::vector<std::size_t>>& children,
                                   std::size_t root, const std::string& source) {
  // an explicit stack (children pushed in reverse): the depth of the tree is the input's, so
  // no recursion may follow it
  std::vector<std::size_t> order;
  order.reserve(specs.size());
  std::vector<std::size_t> stack{root};
  while (!stack.empty()) {
    const std::size_t i = stack.back();
    stack.pop_back();
    order.push_back(i);
    for (auto it = children[i].rbegin(); it != children[i].rend(); ++it) stack.push_back(*it);
  }
  if (order.size() != specs.size()) {
    std::vector<bool> seen(specs.size(), false);
    for (std::size_t i : order) seen[i] = true;
    for (std::size_t i = 0; i < specs.size(); ++i) {
      if (!seen[i]) {
        throw_input_error(
            source, bone_element(specs[i], i), "parent",
            "parent cycle: this bone's ancestors never reach the root '" + specs[root].name + "'");
      }
    }
  }
  return order;
}

// stage 4a: head, tail and rest frame of one bone
void check_geometry(const BoneSpec& b, const std::string& source, const std::string& el) {
  if (!b.head_world.allFinite()) throw_input_error(source, el, "head", "non-finite coordinate");
  if (!b.tail_world.allFinite()) throw_input_error(source, el, "tail", "non-finite coordinate");
  for (const auto& [field, p] :
       {std::pair<const char*, const Vec3*>{"head", &b.head_world}, {"tail", &b.tail_world}}) {
    if (p->cwiseAbs().maxCoeff() > kMaxCoordinate) {
      throw_input_error(source, el, field,
                        "coordinate " + fmt(p->cwiseAbs().maxCoeff()) + " is beyond +-" +
                            fmt(kMaxCoordinate) + " rig units (rig.h kMaxCoordinate)");
    }
  }
  const double len = (b.tail_world - b.head_world).norm();
  if (!(len > 1e-9)) {
    throw_input_error(source, el, "tail", "zero-length bone (head and tail coincide)");
  }
  const Mat3& f = b.rest_frame_world;
  if (!f.allFinite() || (f.transpose() * f - Mat3::Identity()).norm() > 1e-3 ||
      f.determinant() < 0.0) {
    throw_input_error(source, el, "rest_frame", "not a right-handed orthonormal frame");
  }
  const Vec3 dir = (b.tail_world - b.head_world) / len;
  if (f.col(1).dot(dir) < 1.0 - 1e-3) {
    throw_input_error(source, el, "rest_frame",
                      "the frame's y axis does not run from head to tail");
  }
}

// stage 4b: per-axis limits of one bone
void check_limits(const BoneSpec& b, const std::string& source, const std::string& el) {
  static const char* kAxis[3] = {"x", "y", "z"};
  for (int a = 0; a < 3; ++a) {
    const AxisLimit& l = b.limit[a];
    if (!l.limited) continue;
    const std::string field = std::string("limits_deg.") + kAxis[a];
    if (!std::isfinite(l.min) || !std::isfinite(l.max)) {
      throw_input_error(source, el, field, "non-finite limit");
    }
    if (l.min > l.max) {
      throw_input_error(source, el, field,
                        "min " + fmt(rad2deg(l.min)) + " deg is greater than max " +
                            fmt(rad2deg(l.max)) + " deg");
    }
    if (l.min < -kPi - 1e-9 || l.max > kPi + 1e-9) {
      throw_input_error(source, el, field, "limits must lie within [-180, 180] deg");
    }
  }
}

// stage 4c: mass, radius and explicit inertia of one bone
void check_mass(const BoneSpec& b, const std::string& source, const std::string& el) {
  if (!std::isfinite(b.mass) || !(b.mass > 0.0)) {
    throw_input_error(source, el, "mass", "mass must be a positive finite number");
  }
  if (!std::isfinite(b.radius) || !(b.radius > 0.0)) {
    throw_input_error(source, el, "radius", "radius must be a positive finite number");
  }
  // outside these the inertia m (3 r^2 + L^2) / 12, its inverse or a kinetic energy overflows
  const std::string range = " (rig.h: [" + fmt(kMinScale) + ", " + fmt(kMaxScale) + "])";
  if (b.mass < kMinScale || b.mass > kMaxScale) {
    throw_input_error(source, el, "mass", "mass " + fmt(b.mass) + " kg is out of range" + range);
  }
  if (b.radius < kMinScale || b.radius > kMaxScale) {
    throw_input_error(source, el, "radius",
                      "radius " + fmt(b.radius) + " rig units is out of range" + range);
  }
  // collision_radius 0 is the default (a fraction of the length), else within the radius' range
  if (!std::isfinite(b.collision_radius) || b.collision_radius < 0.0 ||
      (b.collision_radius > 0.0 &&
       (b.collision_radius < kMinScale || b.collision_radius > kMaxScale))) {
    throw_input_error(source, el, "collision_radius",
                      "collision radius " + fmt(b.collision_radius) +
                          " rig units must be positive and finite" + range);
  }
  if (b.inertia_local.isZero()) return;
  const Vec3& in = b.inertia_local;
  if (!in.allFinite() || !(in.minCoeff() > 0.0)) {
    throw_input_error(source, el, "inertia_local", "moments must be positive finite numbers");
  }
  const double lo = kMinScale * kMinScale * kMinScale, hi = kMaxScale * kMaxScale * kMaxScale;
  if (in.minCoeff() < lo || in.maxCoeff() > hi) {
    throw_input_error(source, el, "inertia_local",
                      "moments must lie in [" + fmt(lo) + ", " + fmt(hi) + "] kg m^2");
  }
  // principal moments of a real body obey the triangle inequality
  if (in.x() + in.y() < in.z() * (1 - 1e-9) || in.y() + in.z() < in.x() * (1 - 1e-9) ||
      in.z() + in.x() < in.y() * (1 - 1e-9)) {
    throw_input_error(source, el, "inertia_local",
                      "moments break the triangle inequality (no real body has them)");
  }
}

// stage 4d: a bone's place in the human template: a known segment, a finite nonzero forward axis
void check_body(const BoneSpec& b, const std::string& source, const std::string& el) {
  if (!b.segment.empty() && human_segment_index(b.segment) < 0) {
    throw_input_error(source, el, "segment",
                      "unknown segment '" + b.segment + "'" +
                          did_you_mean(b.segment, human_segment_names()) +
                          " (human_template.h: pelvis, lumbar, thorax, neck, head, and clavicle, "
                          "upper_arm, forearm, hand, fingers, thigh, shank, foot, toes with .L "
                          "or .R)");
  }
  if (!b.forward_local.allFinite() ||
      (!b.forward_local.isZero() && !(b.forward_local.stableNorm() > 1e-9))) {
    throw_input_error(source, el, "forward", "must be a finite nonzero vector");
  }
}

// stage 5: the per-bone arrays in DFS order; a child's head must meet its parent's tail (within
// 1e-3 of the parent's length) and is snapped onto it to remove the file's rounding
void fill_bones(const std::vector<BoneSpec>& specs, const std::vector<std::size_t>& order,
                const std::unordered_map<std::string, std::size_t>& index_of,
                const std::string& source, Rig& rig) {
  std::vector<int> new_index(specs.size());
  for (std::size_t k = 0; k < order.size(); ++k) new_index[order[k]] = static_cast<int>(k);
  for (std::size_t k = 0; k < order.size(); ++k) {
    const BoneSpec& b = specs[order[k]];
    const int parent = b.parent.empty() ? -1 : new_index[index_of.at(b.parent)];
    Vec3 head = b.head_world;
    if (parent >= 0) {
      const Vec3& parent_tail = rig.bone_rest_tail_world[parent];
      const double gap = (head - parent_tail).norm();
      if (gap > 1e-3 * rig.bone_length[parent]) {
        throw_input_error(source, bone_element(b, order[k]), "head",
                          "does not meet the tail of its parent '" + b.parent + "' (gap " +
                              fmt(gap) + "); a joint is a parent's tail with its children's heads");
      }
      head = parent_tail;
    }
    rig.bone_name.push_back(b.name);
    rig.bone_parent.push_back(parent);
    rig.bone_rest_head_world.push_back(head);
    rig.bone_rest_tail_world.push_back(b.tail_world);
    // re-orthonormalise the file's frame (files carry 4 decimals)
    Quat q(b.rest_frame_world);
    q.normalize();
    rig.bone_rest_orient_world.push_back(q);
    const double len = (b.tail_world - head).norm();
    rig.bone_length.push_back(len);
    rig.bone_mass.push_back(b.mass);
    rig.bone_radius.push_back(b.radius);
    rig.bone_collision_radius.push_back(b.collision_radius > 0.0 ? b.collision_radius
                                                                 : kCollisionRadiusPerLength * len);
    rig.bone_inertia_local.push_back(
        b.inertia_local.isZero() ? cylinder_inertia(b.mass, b.radius, len) : b.inertia_local);
    rig.bone_limit.push_back(b.limit);
    rig.bone_segment.push_back(b.segment);
    rig.bone_forward_local.push_back(b.forward_local.isZero() ? b.forward_local
                                                              : b.forward_local.stableNormalized());
    rig.bone_weld.push_back(b.weld.empty() ? -1 : new_index[index_of.at(b.weld)]);
  }
}

// stage 6: rest frames exact and relative to the parent. The frame's y axis must be exactly the
// bone direction: the file's rounding is folded into the frame by the minimal rotation that
// aligns them. Then each bone's rest frame and head in its parent's frame.
void derive_rest_frames(Rig& rig) {
  for (int i = 0; i < rig.nbone; ++i) {
    const Vec3 dir = (rig.bone_rest_tail_world[i] - rig.bone_rest_head_world[i]).normalized();
    const Vec3 y = rig.bone_rest_orient_world[i] * Vec3::UnitY();
    rig.bone_rest_orient_world[i] =
        (Quat::FromTwoVectors(y, dir) * rig.bone_rest_orient_world[i]).normalized();
  }
  rig.bone_children.assign(rig.nbone, {});
  rig.bone_rest_orient_parent.resize(rig.nbone);
  rig.bone_head_in_parent.resize(rig.nbone);
  for (int i = 0; i < rig.nbone; ++i) {
    const int p = rig.bone_parent[i];
    if (p < 0) {
      rig.bone_rest_orient_parent[i] = rig.bone_rest_orient_world[i];
      rig.bone_head_in_parent[i].setZero();
      continue;
    }
    rig.bone_children[p].push_back(i);
    rig.bone_rest_orient_parent[i] =
        (rig.bone_rest_orient_world[p].conjugate() * rig.bone_rest_orient_world[i]).normalized();
    rig.bone_head_in_parent[i] = rig.bone_rest_orient_world[p].conjugate() *
                                 (rig.bone_rest_head_world[i] - rig.bone_rest_head_world[p]);
  }
}

// the lock rotation L = exp(sum over locked axes of min e_k) (rig.h "Locked axes")
Quat lock_rotation(const std::array<AxisLimit, 3>& limit) {
  Vec3 v = Vec3::Zero();
  for (int k = 0; k < 3; ++k) {
    if (limit[k].locked()) v[k] = limit[k].min;
  }
  const double angle = v.norm();
  return angle > 0.0 ? Quat(Eigen::AngleAxisd(angle, v / angle)) : Quat::Identity();
}

// a joint's type by its locked axes, its free axes in x, y, z order into `axes`
JointType type_by_locks(const std::array<AxisLimit, 3>& limit, std::array<int, 2>& axes) {
  int nfree = 0;
  axes = {-1, -1};
  for (int k = 0; k < 3; ++k) {
    if (limit[k].locked()) continue;
    if (nfree < 2) axes[nfree] = k;
    ++nfree;
  }
  if (nfree == 3) axes = {-1, -1};
  switch (nfree) {
    case 0:
      return JointType::kWeld;
    case 1:
      return JointType::kHinge;
    case 2:
      return JointType::kUniversal;
    default:
      return JointType::kBall;
  }
}

int coordinates(JointType type) {
  return type == JointType::kFree ? 6 : rotational_coordinates(type);
}

// stage 6b: the joint model: each bone's joint type (its locked axes removed: rig.h "Locked
// axes"), joint parent and velocity coordinates, its rest frame in the frame of the bone it is
// welded to, and its rigid body; and the coordinates of the gauss-seidel scheme's balls
void derive_joint_model(Rig& rig, RootJoint root) {
  const int n = rig.nbone;
  rig.root_joint = root;
  rig.bone_joint_type.assign(n, JointType::kBall);
  rig.bone_joint_parent.assign(n, -1);
  rig.bone_dofadr.assign(n, 0);
  rig.bone_dofadr_springs.assign(n, 0);
  rig.bone_joint_axes.assign(n, {-1, -1});
  rig.bone_joint_lock.assign(n, Quat::Identity());
  rig.bone_rest_orient_weld.assign(n, Quat::Identity());
  rig.bone_body.assign(n, 0);
  rig.body_nbone.assign(n, 0);
  int nv = 0, nv_springs = 0;
  for (int i = 0; i < n; ++i) {
    const int w = rig.bone_weld[i];
    JointType& type = rig.bone_joint_type[i];
    if (i == 0 && root != RootJoint::kPinned) {
      type = root == RootJoint::kFree ? JointType::kFree : JointType::kWeld;
    } else if (w >= 0) {
      type = JointType::kWeld;
    } else {
      type = type_by_locks(rig.bone_limit[i], rig.bone_joint_axes[i]);
      if (type != JointType::kBall) rig.bone_joint_lock[i] = lock_rotation(rig.bone_limit[i]);
    }
    rig.bone_joint_parent[i] = w >= 0 ? w : rig.bone_parent[i];
    rig.bone_dofadr[i] = nv;
    nv += coordinates(type);
    rig.bone_dofadr_springs[i] = nv_springs;
    nv_springs += coordinates(rig.joint_type(i, LockedAxes::kSprings));
    if (w >= 0) {
      rig.bone_rest_orient_weld[i] =
          (rig.bone_rest_orient_world[w].conjugate() * rig.bone_rest_orient_world[i]).normalized();
    }
    rig.bone_body[i] = w >= 0 ? rig.bone_body[w] : i;
    ++rig.body_nbone[rig.bone_body[i]];
  }
  rig.nv = nv;
  rig.nv_springs = nv_springs;
}

// stage 7: one joint per bone with children, and the members flattened for the joint solve
void derive_joints(Rig& rig) {
  rig.bone_joint_at_tail.assign(rig.nbone, -1);
  rig.bone_joint_at_head.assign(rig.nbone, -1);
  if (rig.root_joint == RootJoint::kPinned) {
    // the world holds the root's head
    Joint j;
    j.children = {0};
    j.anchored = true;
    rig.bone_joint_at_head[0] = 0;
    rig.joints.push_back(j);
  }
  for (int i = 0; i < rig.nbone; ++i) {
    if (rig.bone_children[i].empty()) continue;
    Joint j;
    j.parent = i;
    j.children = rig.bone_children[i];
    j.anchored = i == 0 && rig.root_joint == RootJoint::kFixed;
    rig.bone_joint_at_tail[i] = static_cast<int>(rig.joints.size());
    for (int c : j.children) rig.bone_joint_at_head[c] = static_cast<int>(rig.joints.size());
    rig.joints.push_back(j);
  }
  // the members: one per rigid body at the joint (welded bones are one body: rig.h "Welds"),
  // named by its first bone there; a joint inside one body holds nothing and is left out
  std::vector<Joint> kept;
  for (const Joint& j : rig.joints) {
    const int first = static_cast<int>(rig.joint_member_bone.size());
    std::vector<int> bodies;
    const auto add = [&](int bone, int at_tail) {
      const int body = rig.bone_body[bone];
      if (std::find(bodies.begin(), bodies.end(), body) != bodies.end()) return;
      bodies.push_back(body);
      rig.joint_member_bone.push_back(bone);
      rig.joint_member_body.push_back(body);
      rig.joint_member_at_tail.push_back(at_tail);
    };
    if (j.parent >= 0) add(j.parent, 1);
    for (int c : j.children) add(c, 0);
    if (bodies.size() < 2 && !j.anchored) {
      rig.joint_member_bone.resize(first);
      rig.joint_member_body.resize(first);
      rig.joint_member_at_tail.resize(first);
      continue;
    }
    rig.joint_first_member.push_back(first);
    rig.joint_anchored.push_back(j.anchored ? 1 : 0);
    kept.push_back(j);
  }
  rig.joint_first_member.push_back(static_cast<int>(rig.joint_member_bone.size()));
  if (kept.size() != rig.joints.size()) {
    rig.joints = kept;
    rig.bone_joint_at_tail.assign(rig.nbone, -1);
    rig.bone_joint_at_head.assign(rig.nbone, -1);
    for (std::size_t k = 0; k < kept.size(); ++k) {
      const int index = static_cast<int>(k);
      if (kept[k].parent >= 0) rig.bone_joint_at_tail[kept[k].parent] = index;
      for (int c : kept[k].children) rig.bone_joint_at_head[c] = index;
    }
  }
}

}  // namespace

Rig build_rig(const std::vector<BoneSpec>& specs, const std::string& source,
              const std::string& name, RootJoint root_joint) {
  if (specs.empty()) throw_input_error(source, "", "bones", "the rig has no bones");
  if (specs.size() > static_cast<std::size_t>(kMaxBones)) {
    throw_input_error(source, "", "bones",
                      std::to_string(specs.size()) + " bones, more than the " +
                          std::to_string(kMaxBones) + " a rig may have (rig.h kMaxBones)");
  }
  const std::string bad_name = name_problem(name);
  if (!bad_name.empty()) throw_input_error(source, "", "name", "the rig's name: " + bad_name);
  const auto index_of = index_names(specs, source);
  std::vector<std::vector<std::size_t>> children;
  const std::size_t root = link_parents(specs, index_of, source, children);
  const std::vector<std::size_t> order = dfs_order(specs, children, root, source);
  check_welds(specs, index_of, children, source);
  if (root_joint != RootJoint::kPinned) {
    for (int a = 0; a < 3; ++a) {
      if (specs[root].limit[a].limited) {
        throw_input_error(source, bone_element(specs[root], root), "limits_deg",
                          root_joint == RootJoint::kFree
                              ? "a free root has nothing to limit its turn against (limits on "
                                "the root need the rig's \"root\": \"pinned\")"
                              : "a fixed root does not turn: it has nothing to limit");
      }
    }
  }
  for (std::size_t i = 0; i < specs.size(); ++i) {
    const std::string el = bone_element(specs[i], i);
    check_geometry(specs[i], source, el);
    check_limits(specs[i], source, el);
    check_mass(specs[i], source, el);
    check_body(specs[i], source, el);
  }
  Rig rig;
  rig.name = name;
  rig.nbone = static_cast<int>(specs.size());
  fill_bones(specs, order, index_of, source, rig);
  derive_rest_frames(rig);
  derive_joint_model(rig, root_joint);
  derive_joints(rig);
  return rig;
}

void refresh_joint_model(Rig& rig) {
  derive_joint_model(rig, rig.root_joint);
}

std::string unknown_bone(const std::string& name, const Rig& rig) {
  const std::vector<SourceJoint>& joints = rig.source_skeleton.joints;
  int j = -1;
  for (int k = 0; k < static_cast<int>(joints.size()); ++k) {
    if (joints[k].name == name && joints[k].bones.empty()) j = k;
  }
  if (j < 0) return unknown_bone(name, rig.bone_name);
  // the bone that ends at the joint: one of its nearest ancestor's with bones, along its offset
  const Quat axes = source_axes_to_rig(rig.source_skeleton.axes);
  Vec3 reach = Vec3::Zero();  // rig units, from that ancestor's origin
  int a = j;
  std::string ends;
  while (a >= 0 && (a == j || joints[a].bones.empty())) {
    reach += rig.source_skeleton.scale * (axes * joints[a].offset);
    a = joints[a].parent;
  }
  if (a >= 0) {
    for (int b : joints[a].bones) {
      const Vec3 d = rig.bone_rest_tail_world[b] - rig.bone_rest_head_world[b];
      if ((d - reach).norm() <= 1e-9 * std::max(1.0, reach.norm())) ends = rig.bone_name[b];
    }
  }
  std::string starts;
  for (const SourceJoint& c : joints) {
    if (c.parent != j || c.bones.empty()) continue;
    starts += (starts.empty() ? "'" : ", '") + rig.bone_name[c.bones.front()] + "'";
  }
  std::string s = "unknown bone '" + name +
                  "': a joint of the rig's source skeleton without a bone of its own (its "
                  "children sit at its origin)";
  if (!ends.empty()) s += "; its point is bone '" + ends + "' at alpha 1";
  if (!starts.empty()) s += "; the bones that start there: " + starts;
  return s;
}

}  // namespace physik
