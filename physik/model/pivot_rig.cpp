// Pivot tree -> rig; see pivot_rig.h for the mapping. Every stage is linear (or n log n) in the
// number of pivots: 20,000 siblings or a 20,000-deep chain must not cost n^2.
#include "physik/model/pivot_rig.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>

#include "physik/model/errors.h"
#include "physik/model/unique_names.h"

namespace physik {

namespace {

struct Segment {
  int node = -1;
  Vec3 tail = Vec3::Zero();
  int tail_node = -1;  // first child pivot in the group
  int tail_end = -1;   // or the end point
  int parent = -1;     // parent segment, -1 = root level
  std::string name;
};

// stage 0: parents before children, finite positions; returns the grouping tolerance (offsets
// shorter than it are zero)
double check_nodes(const std::vector<PivotNode>& nodes, const std::string& source) {
  const int n = static_cast<int>(nodes.size());
  if (n == 0) throw_input_error(source, "", "", "no joints to make bones from");
  if (nodes[0].parent != -1) {
    throw_input_error(source, nodes[0].name, "parent", "the first joint must be the root");
  }
  double extent = 1.0;
  for (int i = 0; i < n; ++i) {
    if (i > 0 && (nodes[i].parent < 0 || nodes[i].parent >= i)) {
      throw_input_error(source, nodes[i].name, "parent", "parents must come before children");
    }
    if (!nodes[i].rest_world.allFinite()) {
      throw_input_error(source, nodes[i].name, "position", "not finite");
    }
    for (const Vec3& e : nodes[i].ends_world) {
      if (!e.allFinite()) throw_input_error(source, nodes[i].name, "end point", "not finite");
    }
    extent = std::max(extent, nodes[i].rest_world.cwiseAbs().maxCoeff());
  }
  return 1e-9 * extent;
}

// Groups a pivot's tail points by position: a point joins the first (lowest-index) segment of the
// same pivot within tol, found through a grid of cell size tol (a match lies in one of the 27
// cells around the point), so n siblings cost O(n) instead of O(n^2).
class SegmentGrid {
 public:
  explicit SegmentGrid(double tol) : tol_(tol) {}

  int find(int node, const Vec3& p, const std::vector<Segment>& segs) const {
    const Cell c = cell(p);
    int best = -1;
    for (std::int64_t dx = -1; dx <= 1; ++dx) {
      for (std::int64_t dy = -1; dy <= 1; ++dy) {
        for (std::int64_t dz = -1; dz <= 1; ++dz) {
          auto it = grid_.find(Key{node, c.x + dx, c.y + dy, c.z + dz});
          if (it == grid_.end()) continue;
          for (int s : it->second) {
            if ((segs[s].tail - p).norm() <= tol_ && (best < 0 || s < best)) best = s;
          }
        }
      }
    }
    return best;
  }

  void add(int node, int seg, const Vec3& p) {
    const Cell c = cell(p);
    grid_[Key{node, c.x, c.y, c.z}].push_back(seg);
  }

 private:
  struct Cell {
    std::int64_t x, y, z;
  };
  struct Key {
    int node;
    std::int64_t x, y, z;
    bool operator==(const Key& o) const {
      return node == o.node && x == o.x && y == o.y && z == o.z;
    }
  };
  struct KeyHash {
    std::size_t operator()(const Key& k) const {
      std::size_t h = std::hash<std::int64_t>()(k.x);
      for (std::int64_t v : {k.y, k.z, static_cast<std::int64_t>(k.node)}) {
        h ^= std::hash<std::int64_t>()(v) + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
      }
      return h;
    }
  };
  Cell cell(const Vec3& p) const {
    // |p| / tol <= 1e9 (tol = 1e-9 of the extent): the cell indices fit an int64
    return {static_cast<std::int64_t>(std::floor(p.x() / tol_)),
            static_cast<std::int64_t>(std::floor(p.y() / tol_)),
            static_cast<std::int64_t>(std::floor(p.z() / tol_))};
  }
  double tol_;
  std::unordered_map<Key, std::vector<int>, KeyHash> grid_;
};

// stage 1: segments per pivot: children and end points grouped by offset; child_seg[c] is the
// segment of c's parent that ends at c (-1 if c sits on its parent)
void make_segments(const std::vector<PivotNode>& nodes, double tol, std::vector<Segment>& segs,
                   std::vector<std::vector<int>>& node_segs, std::vector<int>& child_seg) {
  const int n = static_cast<int>(nodes.size());
  std::vector<std::vector<int>> children(n);
  for (int i = 1; i < n; ++i) children[nodes[i].parent].push_back(i);
  node_segs.assign(n, {});
  child_seg.assign(n, -1);
  SegmentGrid grid(tol);
  auto add_segment = [&](int j, const Vec3& p, int tail_node, int tail_end) {
    Segment seg;
    seg.node = j;
    seg.tail = p;
    seg.tail_node = tail_node;
    seg.tail_end = tail_end;
    const int s = static_cast<int>(segs.size());
    segs.push_back(seg);
    node_segs[j].push_back(s);
    grid.add(j, s, p);
    return s;
  };
  for (int j = 0; j < n; ++j) {
    for (int c : children[j]) {
      const Vec3& p = nodes[c].rest_world;
      if ((p - nodes[j].rest_world).norm() <= tol) continue;
      const int s = grid.find(j, p, segs);
      child_seg[c] = s >= 0 ? s : add_segment(j, p, c, -1);
    }
    for (std::size_t e = 0; e < nodes[j].ends_world.size(); ++e) {
      const Vec3& p = nodes[j].ends_world[e];
      if ((p - nodes[j].rest_world).norm() <= tol) continue;
      if (grid.find(j, p, segs) < 0) add_segment(j, p, -1, static_cast<int>(e));
    }
  }
}

// stage 2: the segment whose tail is at each pivot (through zero offsets), every segment's
// parent, and the number and mean length of the segments at the root level
std::vector<int> link_segments(const std::vector<PivotNode>& nodes,
                               const std::vector<int>& child_seg, std::vector<Segment>& segs,
                               int& root_level, double& root_len) {
  const int n = static_cast<int>(nodes.size());
  std::vector<int> incoming(n, -1);
  for (int c = 1; c < n; ++c) {
    incoming[c] = child_seg[c] >= 0 ? child_seg[c] : incoming[nodes[c].parent];
  }
  root_level = 0;
  root_len = 0.0;
  for (Segment& s : segs) {
    s.parent = incoming[s.node];
    if (s.parent < 0) {
      ++root_level;
      root_len += (s.tail - nodes[s.node].rest_world).norm();
    }
  }
  return incoming;
}

// stage 3: names (pivot_rig.h, 4.)
void name_segments(const std::vector<PivotNode>& nodes,
                   const std::vector<std::vector<int>>& node_segs, std::vector<Segment>& segs,
                   UniqueNames& used) {
  for (std::size_t j = 0; j < nodes.size(); ++j) {
    int nend = 0;
    for (int s : node_segs[j]) {
      Segment& seg = segs[s];
      std::string base = nodes[j].name;
      if (node_segs[j].size() > 1) {
        if (seg.tail_node >= 0) {
          base += ">" + nodes[seg.tail_node].name;
        } else {
          ++nend;
          base += nend == 1 ? ">end" : ">end" + std::to_string(nend);
        }
      }
      seg.name = used.make(base);
    }
  }
}

// stage 4: specs, the synthetic root first if any, then the segments in DFS order of the segment
// tree (children in pivot order; an explicit stack); returns each segment's spec index
std::vector<int> emit_specs(const std::vector<PivotNode>& nodes, const std::vector<Segment>& segs,
                            double mass_per_length, double radius, int root_level, double root_len,
                            UniqueNames& used, PivotBones& out) {
  auto add_spec = [&](const std::string& name, const std::string& parent, const Vec3& head,
                      const Vec3& tail, int node, int tail_node, int tail_end, int parent_spec) {
    BoneSpec b;
    b.name = name;
    b.parent = parent;
    b.head_world = head;
    b.tail_world = tail;
    b.rest_frame_world = rest_frame_from_roll(head, tail, 0.0);
    b.mass = mass_per_length * (tail - head).norm();
    b.radius = radius;
    out.specs.push_back(b);
    out.spec_node.push_back(node);
    out.spec_parent.push_back(parent_spec);
    out.spec_tail_node.push_back(tail_node);
    out.spec_tail_end.push_back(tail_end);
  };
  out.synthetic_root = root_level != 1;
  std::string synthetic_name;
  if (out.synthetic_root) {
    // a handle bone ending at the root pivot (pivot_rig.h, 3.)
    const double len = root_level > 0 ? root_len / root_level : 1.0;
    synthetic_name =
        used.taken(nodes[0].name) ? used.make(nodes[0].name + "_root") : used.make(nodes[0].name);
    add_spec(synthetic_name, "", nodes[0].rest_world - Vec3(0, 0, len), nodes[0].rest_world, 0, -1,
             -1, -1);
  }
  std::vector<std::vector<int>> seg_children(segs.size());
  std::vector<int> roots;
  for (std::size_t s = 0; s < segs.size(); ++s) {
    if (segs[s].parent < 0) {
      roots.push_back(static_cast<int>(s));
    } else {
      seg_children[segs[s].parent].push_back(static_cast<int>(s));
    }
  }
  std::vector<int> spec_of_seg(segs.size(), -1);
  std::vector<int> stack(roots.rbegin(), roots.rend());
  while (!stack.empty()) {
    const int s = stack.back();
    stack.pop_back();
    const Segment& seg = segs[s];
    const std::string parent =
        seg.parent >= 0 ? segs[seg.parent].name : (out.synthetic_root ? synthetic_name : "");
    spec_of_seg[s] = static_cast<int>(out.specs.size());
    add_spec(seg.name, parent, nodes[seg.node].rest_world, seg.tail, seg.node, seg.tail_node,
             seg.tail_end,
             seg.parent >= 0 ? spec_of_seg[seg.parent] : (out.synthetic_root ? 0 : -1));
    for (auto it = seg_children[s].rbegin(); it != seg_children[s].rend(); ++it) {
      stack.push_back(*it);
    }
  }
  return spec_of_seg;
}

}  // namespace

PivotBones pivot_bones(const std::vector<PivotNode>& nodes, const std::string& source,
                       double mass_per_length, double radius) {
  const double tol = check_nodes(nodes, source);
  std::vector<Segment> segs;
  std::vector<std::vector<int>> node_segs;
  std::vector<int> child_seg;
  make_segments(nodes, tol, segs, node_segs, child_seg);
  int root_level = 0;
  double root_len = 0.0;
  const std::vector<int> incoming = link_segments(nodes, child_seg, segs, root_level, root_len);
  UniqueNames used;
  name_segments(nodes, node_segs, segs, used);

  PivotBones out;
  const std::vector<int> spec_of_seg =
      emit_specs(nodes, segs, mass_per_length, radius, root_level, root_len, used, out);
  const int n = static_cast<int>(nodes.size());
  out.node_specs.assign(n, {});
  out.node_incoming.assign(n, -1);
  for (int j = 0; j < n; ++j) {
    for (int s : node_segs[j]) out.node_specs[j].push_back(spec_of_seg[s]);
    out.node_incoming[j] =
        incoming[j] >= 0 ? spec_of_seg[incoming[j]] : (out.synthetic_root ? 0 : -1);
  }
  // welds (pivot_rig.h, 3b.): a pivot's segments are one body; the first one (emitted first
  // among its siblings) carries the joint
  for (int j = 0; j < n; ++j) {
    const std::vector<int>& own = out.node_specs[j];
    if (j == 0 && out.synthetic_root) {
      for (int s : own) out.specs[s].weld = out.specs[0].name;
      continue;
    }
    for (std::size_t k = 1; k < own.size(); ++k) out.specs[own[k]].weld = out.specs[own[0]].name;
  }
  return out;
}

void pin_root_pivot(PivotBones& bones) {
  if (!bones.synthetic_root) {
    bones.root_joint = RootJoint::kPinned;
    return;
  }
  // the handle stays; the root pivot's segments turn on a ball at its tail (pivot_rig.h, 3c.)
  bones.root_joint = RootJoint::kFixed;
  bones.spec_node[0] = -1;
  const std::vector<int>& own = bones.node_specs.at(0);
  for (std::size_t k = 0; k < own.size(); ++k) {
    bones.specs[own[k]].weld = k == 0 ? std::string() : bones.specs[own[0]].name;
  }
}

PivotRig finish_pivot_rig(const std::vector<PivotNode>& nodes, const PivotBones& bones,
                          const std::string& source, const std::string& name) {
  PivotRig pr;
  pr.rig = build_rig(bones.specs, source, name, bones.root_joint);
  pr.nodes = nodes;
  pr.synthetic_root = bones.synthetic_root;
  pr.bone_node.assign(pr.rig.nbone, -1);
  pr.bone_tail_node.assign(pr.rig.nbone, -1);
  pr.bone_tail_end.assign(pr.rig.nbone, -1);
  // one name index, not a linear find_bone per spec
  std::unordered_map<std::string, int> bone_of;
  bone_of.reserve(pr.rig.nbone);
  for (int b = 0; b < pr.rig.nbone; ++b) bone_of.emplace(pr.rig.bone_name[b], b);
  for (std::size_t s = 0; s < bones.specs.size(); ++s) {
    const int b = bone_of.at(bones.specs[s].name);
    pr.bone_node[b] = bones.spec_node[s];
    pr.bone_tail_node[b] = bones.spec_tail_node[s];
    pr.bone_tail_end[b] = bones.spec_tail_end[s];
  }
  return pr;
}

void pivot_pose(const PivotRig& pr, const std::vector<Quat>& node_rotation_world,
                const Vec3& root_pivot_world, BoneFrames& scratch, Pose& out) {
  const Rig& rig = pr.rig;
  scratch.resize(rig.nbone);
  // a bone that follows no pivot (a pinned root's handle) keeps its rest orientation
  const auto turn = [&](int b) {
    return pr.bone_node[b] >= 0 ? node_rotation_world[pr.bone_node[b]] : Quat::Identity();
  };
  for (int b = 0; b < rig.nbone; ++b) {
    scratch.orient_world[b] = (turn(b) * rig.bone_rest_orient_world[b]).normalized();
  }
  scratch.head_world[0] =
      root_pivot_world + turn(0) * (rig.bone_rest_head_world[0] - pr.nodes[0].rest_world);
  local_rotations_from_world(rig, scratch, out);
}

void pivot_bone_targets(const PivotRig& pr, const std::vector<Vec3>& node_pos_world,
                        const std::vector<Quat>& node_rotation_world, std::vector<Vec3>& head,
                        std::vector<Vec3>& tail) {
  const Rig& rig = pr.rig;
  head.resize(rig.nbone);
  tail.resize(rig.nbone);
  for (int b = 0; b < rig.nbone; ++b) {
    const int j = pr.bone_node[b];
    if (b == 0 && pr.synthetic_root) {
      const Quat turn = j >= 0 ? node_rotation_world[0] : Quat::Identity();
      tail[b] = node_pos_world[0];
      head[b] = node_pos_world[0] + turn * (rig.bone_rest_head_world[0] - pr.nodes[0].rest_world);
      continue;
    }
    head[b] = node_pos_world[j];
    if (pr.bone_tail_node[b] >= 0) {
      tail[b] = node_pos_world[pr.bone_tail_node[b]];
    } else {
      tail[b] = node_pos_world[j] +
                node_rotation_world[j] *
                    (pr.nodes[j].ends_world[pr.bone_tail_end[b]] - pr.nodes[j].rest_world);
    }
  }
}

}  // namespace physik
