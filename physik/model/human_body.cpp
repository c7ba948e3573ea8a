// The human template fitted to a converted skeleton (human_body.h).
#include "physik/model/human_body.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>

#include "physik/model/kinematics.h"
#include "physik/model/message_number.h"
#include "physik/model/rest_limits.h"

namespace physik {

namespace {

const std::vector<TemplateSegment>& segs() {
  return human_segments();
}

// columns x0, d0, x0 x d0 in body coordinates (F, L, U)
Mat3 template_frame(const TemplateSegment& t) {
  Mat3 T;
  T.col(0) = t.x0;
  T.col(1) = t.d0;
  T.col(2) = t.x0.cross(t.d0);
  return T;
}

// the body's basis in the rig's world: columns F, L, U
Mat3 body_basis(const BodyAxes& a) {
  Mat3 B;
  B.col(0) = a.forward;
  B.col(1) = a.left;
  B.col(2) = a.up;
  return B;
}

// the segment's chain: a bone carries its parent's frame within one chain (human_body.h)
int chain_of(const TemplateSegment& t) {
  const std::string base = t.name.substr(0, t.name.find('.'));
  int chain = 0;
  if (base == "lumbar" || base == "thorax" || base == "neck" || base == "head") chain = 1;
  if (base == "clavicle") chain = 2;
  if (base == "upper_arm" || base == "forearm" || base == "hand" || base == "fingers") chain = 3;
  if (base == "thigh" || base == "shank" || base == "foot" || base == "toes") chain = 4;
  return chain * 3 + t.side + 1;
}

// the shortest rotation taking unit `from` onto unit `to` (half a turn about `across`, a unit
// vector across `from`, when they are opposite)
Quat swing(const Vec3& from, const Vec3& to, const Vec3& across) {
  if (from.dot(to) < -1.0 + 1e-12) return Quat(Eigen::AngleAxisd(kPi, across));
  return Quat::FromTwoVectors(from, to);
}

int first_node_of(const std::vector<int>& node_segment, const char* name) {
  const int s = human_segment_index(name);
  for (std::size_t j = 0; j < node_segment.size(); ++j) {
    if (node_segment[j] == s) return static_cast<int>(j);
  }
  return -1;
}

// the top of the trunk: the first neck (else head) pivot, else the spine pivot farthest from
// `from`
Vec3 trunk_top(const std::vector<PivotNode>& nodes, const std::vector<int>& node_segment,
               const Vec3& from) {
  for (const char* name : {"neck", "head"}) {
    const int j = first_node_of(node_segment, name);
    if (j >= 0) return nodes[j].rest_world;
  }
  Vec3 top = from;
  const int lumbar = human_segment_index("lumbar"), thorax = human_segment_index("thorax");
  for (std::size_t j = 0; j < nodes.size(); ++j) {
    if (node_segment[j] != lumbar && node_segment[j] != thorax) continue;
    for (const Vec3& p : nodes[j].ends_world) {
      if ((p - from).norm() > (top - from).norm()) top = p;
    }
    const Vec3& p = nodes[j].rest_world;
    if ((p - from).norm() > (top - from).norm()) top = p;
  }
  return top;
}

double extent_along(const std::vector<PivotNode>& nodes, const Vec3& axis) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const PivotNode& n : nodes) {
    lo = std::min(lo, n.rest_world.dot(axis));
    hi = std::max(hi, n.rest_world.dot(axis));
    for (const Vec3& e : n.ends_world) {
      lo = std::min(lo, e.dot(axis));
      hi = std::max(hi, e.dot(axis));
    }
  }
  return nodes.empty() ? 0.0 : hi - lo;
}

// stage 1: each bone's anatomical rest frame, segment and forward axis; the rest's turn from the
// anatomical direction (rad, rotation vector in the bone's frame)
std::vector<Vec3> set_frames(const BodyAxes& axes, const std::vector<int>& seg, PivotBones& bones) {
  const Mat3 B = body_basis(axes);
  const std::size_t n = bones.specs.size();
  std::vector<Mat3> S(n);
  std::vector<Vec3> rest_turn(n, Vec3::Zero());
  for (std::size_t s = 0; s < n; ++s) {
    BoneSpec& b = bones.specs[s];
    const TemplateSegment& t = segs()[seg[s]];
    const Mat3 T = template_frame(t);
    const int p = bones.spec_parent[s];
    Mat3 P = B * T;
    if (p >= 0 && chain_of(segs()[seg[p]]) == chain_of(t)) {
      P = S[p] * template_frame(segs()[seg[p]]).transpose() * T;
    }
    const Vec3 dir = (b.tail_world - b.head_world).normalized();
    const Quat w = swing(P.col(1), dir, P.col(0));
    S[s] = w.toRotationMatrix() * P;
    rest_turn[s] = P.transpose() * rotation_vector(w);
    b.rest_frame_world = S[s];
    b.segment = t.name;
    b.forward_local = T.transpose() * Vec3::UnitX();
  }
  return rest_turn;
}

// one rigid segment: the pelvis, a clavicle, the long bones of a limb, a hand's palm, a foot (a
// second bone of one of these is a twist or deform helper of the same bone, MakeHuman's
// upperarm02.L, DAZ's lThighTwist); the spine, the neck, the fingers and the toes have joints
bool rigid_segment(const TemplateSegment& t) {
  const std::string base = t.name.substr(0, t.name.find('.'));
  return base == "pelvis" || base == "clavicle" || base == "upper_arm" || base == "forearm" ||
         base == "hand" || base == "thigh" || base == "shank" || base == "foot";
}

// stage 2: a bone of a rigid segment below a bone of the same segment is welded to it
void weld_rigid_segments(const std::vector<int>& seg, PivotBones& bones, HumanBodyFit& fit) {
  for (std::size_t s = 1; s < bones.specs.size(); ++s) {
    const int p = bones.spec_parent[s];
    BoneSpec& b = bones.specs[s];
    if (p < 0 || seg[s] != seg[p] || !rigid_segment(segs()[seg[s]]) || !b.weld.empty()) continue;
    b.weld = bones.specs[p].name;
    fit.welded.push_back(b.name + " to " + b.weld);
  }
}

// one axis's limit: the template's range over `share` bones, offset by the rest's turn (deg)
AxisLimit axis_limit(const std::array<double, 2>& range, double share, double offset_deg) {
  if (range[0] == range[1]) return AxisLimit{true, 0.0, 0.0};
  const double lo = std::max(-180.0, range[0] / share - offset_deg);
  const double hi = std::min(180.0, range[1] / share - offset_deg);
  return AxisLimit{true, deg2rad(lo), deg2rad(hi)};
}

// stage 3: limits from the template's ranges (human_body.h); welded bones and the root have none
void set_limits(const std::vector<int>& seg, const std::vector<Vec3>& rest_turn,
                PivotBones& bones) {
  std::map<std::string, int> region_bones;
  const std::size_t n = bones.specs.size();
  for (std::size_t s = 1; s < n; ++s) {
    if (bones.specs[s].weld.empty()) ++region_bones[segs()[seg[s]].shared_region];
  }
  for (std::size_t s = 0; s < n; ++s) {
    BoneSpec& b = bones.specs[s];
    b.limit = {};
    const TemplateSegment& t = segs()[seg[s]];
    if (s == 0 || !b.weld.empty() || t.kind == JointKind::kRoot) continue;
    const double share = t.shared_region.empty() ? 1.0 : region_bones[t.shared_region];
    for (int a = 0; a < 3; ++a) {
      const double offset = t.offset_by_rest ? rad2deg(rest_turn[s][a]) : 0.0;
      b.limit[a] = axis_limit(t.range_deg[a], share, offset);
    }
  }
}

// a de Leva row on one side (trunk and head rows: side 0)
struct MassKey {
  LevaSegment row;
  int side;
  bool operator<(const MassKey& o) const { return row != o.row ? row < o.row : side < o.side; }
};

bool limb_row(LevaSegment r) {
  return r >= LevaSegment::kUpperArm;
}

MassKey key_of(const TemplateSegment& t) {
  return {t.leva, limb_row(t.leva) ? t.side : 0};
}

// the row a row with no bone passes its mass to (human_body.h "Masses"); itself for the end
MassKey next_up(const MassKey& k) {
  using L = LevaSegment;
  switch (k.row) {
    case L::kHand:
      return {L::kForearm, k.side};
    case L::kForearm:
      return {L::kUpperArm, k.side};
    case L::kUpperArm:
      return {L::kUpperTrunk, 0};
    case L::kFoot:
      return {L::kShank, k.side};
    case L::kShank:
      return {L::kThigh, k.side};
    case L::kThigh:
      return {L::kLowerTrunk, 0};
    case L::kHead:
      return {L::kUpperTrunk, 0};
    case L::kUpperTrunk:
      return {L::kMiddleTrunk, 0};
    default:
      return {L::kLowerTrunk, 0};
  }
}

std::string row_name(const MassKey& k) {
  std::string name = leva_row(k.row).name;
  if (k.side != 0) name += k.side > 0 ? ".L" : ".R";
  return name;
}

// every row's mass (kg) on the rows that have bones, the others passed toward the root (each
// step moves down a limb or the trunk; the lower trunk, the root's, always has a bone)
std::map<MassKey, double> row_masses(const std::map<MassKey, double>& volume, double total,
                                     std::vector<HumanMassRow>& rows) {
  std::map<MassKey, double> mass;
  for (int r = 0; r < static_cast<int>(LevaSegment::kCount); ++r) {
    const LevaSegment row = static_cast<LevaSegment>(r);
    for (int side : limb_row(row) ? std::vector<int>{1, -1} : std::vector<int>{0}) {
      MassKey k{row, side};
      HumanMassRow out;
      out.segment = row_name(k);
      out.table_share = leva_row(row).mass_share;
      out.table_com = leva_row(row).com;
      while (!volume.count(k) && k.row != LevaSegment::kLowerTrunk) k = next_up(k);
      if (!(k.row == row && k.side == side)) out.passed_to = row_name(k);
      mass[k] += out.table_share * total;
      rows.push_back(out);
    }
  }
  return mass;
}

// stage 4: masses and inertias (human_body.h "Masses")
void set_masses(const std::vector<int>& seg, double total, PivotBones& bones, HumanBodyFit& fit) {
  std::map<MassKey, double> volume;
  const std::size_t n = bones.specs.size();
  std::vector<double> vol(n);
  for (std::size_t s = 0; s < n; ++s) {
    const BoneSpec& b = bones.specs[s];
    vol[s] = std::pow((b.tail_world - b.head_world).norm(), 3);
    volume[key_of(segs()[seg[s]])] += vol[s];
  }
  std::map<MassKey, double> mass = row_masses(volume, total, fit.masses);
  // a root mapped off the pelvis leaves the lower trunk without bones: its mass goes to the root's
  const MassKey root_key = key_of(segs()[seg[0]]);
  for (auto it = mass.begin(); it != mass.end();) {
    if (volume.count(it->first)) {
      ++it;
      continue;
    }
    mass[root_key] += it->second;
    it = mass.erase(it);
  }
  for (std::size_t s = 0; s < n; ++s) {
    BoneSpec& b = bones.specs[s];
    const TemplateSegment& t = segs()[seg[s]];
    const MassKey k = key_of(t);
    const double m = mass[k] * vol[s] / volume.at(k);
    b.mass = std::min(kMaxScale, std::max(1e3 * kMinScale, m));
    const LevaRow& r = leva_row(t.leva);
    const double L = (b.tail_world - b.head_world).norm();
    b.inertia_local =
        b.mass * L * L *
        Vec3(r.r_transverse * r.r_transverse, r.r_long * r.r_long, r.r_sagittal * r.r_sagittal);
    // within rig.h's bounds, all three by one factor (the triangle inequality holds)
    const double hi = kMaxScale * kMaxScale * kMaxScale, lo = kMinScale * kMinScale * kMinScale;
    if (b.inertia_local.maxCoeff() > hi) b.inertia_local *= hi / b.inertia_local.maxCoeff();
    if (b.inertia_local.minCoeff() < lo) b.inertia_local *= lo / b.inertia_local.minCoeff();
  }
  double sum = 0.0;
  for (const BoneSpec& b : bones.specs) sum += b.mass;
  for (HumanMassRow& row : fit.masses) {
    for (std::size_t s = 0; s < n; ++s) {
      if (row_name(key_of(segs()[seg[s]])) != row.segment) continue;
      row.rig_share += bones.specs[s].mass / sum;
      ++row.nbone;
    }
  }
}

}  // namespace

std::vector<int> inherit_segments(const std::vector<PivotNode>& nodes,
                                  const std::vector<int>& node_segment) {
  std::vector<int> out(nodes.size(), -1);
  for (std::size_t j = 0; j < nodes.size(); ++j) {
    out[j] = node_segment[j];
    if (out[j] >= 0) continue;
    out[j] = nodes[j].parent >= 0 ? out[nodes[j].parent] : human_segment_index("pelvis");
  }
  return out;
}

BodyAxes human_body_axes(const std::vector<PivotNode>& nodes,
                         const std::vector<int>& node_segment) {
  BodyAxes a;
  const int hl = first_node_of(node_segment, "thigh.L");
  const int hr = first_node_of(node_segment, "thigh.R");
  if (hl < 0 || hr < 0) return a;
  const Vec3 right = nodes[hr].rest_world - nodes[hl].rest_world;
  const Vec3 mid = 0.5 * (nodes[hr].rest_world + nodes[hl].rest_world);
  Vec3 up = trunk_top(nodes, node_segment, mid) - mid;
  const double scale = std::max(right.norm(), up.norm());
  if (!(right.norm() > 1e-9 * scale) || !(scale > 0.0)) return a;
  const Vec3 r = right.normalized();
  up -= r * r.dot(up);
  if (!(up.norm() > 1e-6 * scale)) return a;
  a.ok = true;
  a.up = up.normalized();
  a.left = -r;
  a.forward = a.left.cross(a.up);
  a.height = extent_along(nodes, a.up);
  return a;
}

namespace {

// the summed length of the bones of `names` (rig units)
double chain_length(const std::vector<int>& seg, const PivotBones& bones,
                    std::initializer_list<const char*> names) {
  double sum = 0.0;
  for (const char* name : names) {
    const int k = human_segment_index(name);
    for (std::size_t s = 0; s < bones.specs.size(); ++s) {
      if (seg[s] == k) sum += (bones.specs[s].tail_world - bones.specs[s].head_world).norm();
    }
  }
  return sum;
}

// stage 5: proportions a human of this height cannot have, feet pointing backward
void check_proportions(const std::vector<int>& seg, const PivotBones& bones, const BodyAxes& axes,
                       HumanBodyFit& fit) {
  if (!(fit.height > 0.0)) return;
  struct Limb {
    const char* what;
    std::initializer_list<const char*> segments;
    double share;
  };
  const Limb limbs[] = {
      {"left leg (thigh and shank)", {"thigh.L", "shank.L"}, kLegShare},
      {"right leg (thigh and shank)", {"thigh.R", "shank.R"}, kLegShare},
      {"left arm (upper arm and forearm)", {"upper_arm.L", "forearm.L"}, kArmShare},
      {"right arm (upper arm and forearm)", {"upper_arm.R", "forearm.R"}, kArmShare}};
  for (const Limb& l : limbs) {
    const double ratio = chain_length(seg, bones, l.segments) / fit.height;
    if (ratio >= 0.5 * l.share && ratio <= 1.5 * l.share) continue;
    fit.warnings.push_back(std::string("the ") + l.what + " is " + message_number(ratio) +
                           " of the figure's height " + message_number(fit.height) +
                           " rig units; a human's is about " + message_number(l.share) +
                           " (Drillis & Contini): check the joint names and the skeleton");
  }
  for (std::size_t s = 0; s < bones.specs.size(); ++s) {
    const std::string& name = segs()[seg[s]].name;
    if (name != "foot.L" && name != "foot.R") continue;
    const Vec3 dir = bones.specs[s].tail_world - bones.specs[s].head_world;
    if (dir.dot(axes.forward) < -0.5 * dir.norm()) {
      fit.warnings.push_back("the foot '" + bones.specs[s].name +
                             "' points backward: are the left and right names swapped?");
    }
  }
}

}  // namespace

HumanBodyFit fit_human_body(const std::vector<PivotNode>& nodes,
                            const std::vector<int>& node_segment, PivotBones& bones,
                            const HumanBodyOptions& options) {
  HumanBodyFit fit;
  BodyAxes axes = human_body_axes(nodes, node_segment);
  if (!axes.ok) {
    fit.warnings.push_back(
        "the hips and the top of the trunk give no body axes (a thigh is missing, or they meet "
        "at one point): the rig's own axes stand in for forward, left and up");
    axes = BodyAxes{};
  }
  fit.forward_world = axes.forward;
  fit.left_world = axes.left;
  fit.up_world = axes.up;
  fit.height = axes.height;
  fit.up_tilt = std::acos(std::clamp(axes.up.z(), -1.0, 1.0));
  fit.total_mass = options.total_mass > 0.0 ? options.total_mass : kReferenceMass;
  const std::size_t n = bones.specs.size();
  fit.spec_segment.resize(n);
  for (std::size_t s = 0; s < n; ++s) fit.spec_segment[s] = node_segment[bones.spec_node[s]];
  const std::vector<int>& seg = fit.spec_segment;
  const std::vector<Vec3> rest_turn = set_frames(axes, seg, bones);
  weld_rigid_segments(seg, bones, fit);
  set_limits(seg, rest_turn, bones);
  for (const RestBandProblem& p : fit_limits_to_rest(bones.specs, options.torsion_tolerance)) {
    fit.widened.push_back(describe(p, bones.specs[p.bone].name));
  }
  set_masses(seg, fit.total_mass, bones, fit);
  check_proportions(seg, bones, axes, fit);
  return fit;
}

}  // namespace physik
