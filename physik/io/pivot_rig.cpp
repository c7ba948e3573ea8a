// Pivot tree -> rig; see pivot_rig.h for the mapping.
#include "physik/io/pivot_rig.h"

#include <algorithm>
#include <set>

#include "physik/model/errors.h"

namespace physik {

namespace {

std::string unique_name(const std::string& base, std::set<std::string>& used) {
  if (used.insert(base).second) return base;
  for (int k = 2;; ++k) {
    const std::string n = base + "_" + std::to_string(k);
    if (used.insert(n).second) return n;
  }
}

struct Segment {
  int node = -1;
  Vec3 tail = Vec3::Zero();
  int tail_node = -1;   // first child pivot in the group
  int tail_end = -1;    // or the end point
  int parent = -1;      // parent segment, -1 = root level
  std::string name;
};

}  // namespace

PivotBones pivot_bones(const std::vector<PivotNode>& nodes, const std::string& source,
                       double mass_per_length, double radius) {
  const int n = static_cast<int>(nodes.size());
  if (n == 0) throw_input_error(source, "", "", "no joints to make bones from");
  if (nodes[0].parent != -1) throw_input_error(source, nodes[0].name, "parent", "the first joint must be the root");
  double extent = 1.0;
  for (int i = 0; i < n; ++i) {
    if (i > 0 && (nodes[i].parent < 0 || nodes[i].parent >= i)) {
      throw_input_error(source, nodes[i].name, "parent", "parents must come before children");
    }
    extent = std::max(extent, nodes[i].rest_world.cwiseAbs().maxCoeff());
  }
  const double tol = 1e-9 * extent;  // offsets shorter than this are zero

  std::vector<std::vector<int>> children(n);
  for (int i = 1; i < n; ++i) children[nodes[i].parent].push_back(i);

  // 1. segments per pivot: children and ends grouped by offset
  std::vector<Segment> segs;
  std::vector<std::vector<int>> node_segs(n);
  std::vector<int> child_seg(n, -1);  // the segment of the parent that ends at this child
  for (int j = 0; j < n; ++j) {
    auto find_group = [&](const Vec3& p) {
      for (int s : node_segs[j]) {
        if ((segs[s].tail - p).norm() <= tol) return s;
      }
      return -1;
    };
    for (int c : children[j]) {
      const Vec3& p = nodes[c].rest_world;
      if ((p - nodes[j].rest_world).norm() <= tol) continue;
      int s = find_group(p);
      if (s < 0) {
        Segment seg;
        seg.node = j;
        seg.tail = p;
        seg.tail_node = c;
        s = static_cast<int>(segs.size());
        segs.push_back(seg);
        node_segs[j].push_back(s);
      }
      child_seg[c] = s;
    }
    for (std::size_t e = 0; e < nodes[j].ends_world.size(); ++e) {
      const Vec3& p = nodes[j].ends_world[e];
      if ((p - nodes[j].rest_world).norm() <= tol) continue;
      if (find_group(p) >= 0) continue;
      Segment seg;
      seg.node = j;
      seg.tail = p;
      seg.tail_end = static_cast<int>(e);
      node_segs[j].push_back(static_cast<int>(segs.size()));
      segs.push_back(seg);
    }
  }

  // 2. the bone whose tail is at each pivot
  std::vector<int> incoming(n, -1);
  for (int c = 1; c < n; ++c) {
    incoming[c] = child_seg[c] >= 0 ? child_seg[c] : incoming[nodes[c].parent];
  }
  int root_level = 0;
  double root_len = 0.0;
  for (Segment& s : segs) {
    s.parent = incoming[s.node];
    if (s.parent < 0) {
      ++root_level;
      root_len += (s.tail - nodes[s.node].rest_world).norm();
    }
  }

  // 4. names
  std::set<std::string> used;
  for (int j = 0; j < n; ++j) {
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
      seg.name = unique_name(base, used);
    }
  }

  PivotBones out;
  out.synthetic_root = root_level != 1;
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
  std::string synthetic_name;
  if (out.synthetic_root) {
    // 3. a handle bone ending at the root pivot
    const double len = root_level > 0 ? root_len / root_level : 1.0;
    synthetic_name = used.count(nodes[0].name) ? unique_name(nodes[0].name + "_root", used)
                                               : unique_name(nodes[0].name, used);
    add_spec(synthetic_name, "", nodes[0].rest_world - Vec3(0, 0, len), nodes[0].rest_world, 0,
             -1, -1, -1);
  }

  // segments in DFS order of the segment tree (children in pivot order)
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

  out.node_specs.assign(n, {});
  out.node_incoming.assign(n, -1);
  for (int j = 0; j < n; ++j) {
    for (int s : node_segs[j]) out.node_specs[j].push_back(spec_of_seg[s]);
    out.node_incoming[j] = incoming[j] >= 0 ? spec_of_seg[incoming[j]] : (out.synthetic_root ? 0 : -1);
  }
  return out;
}

PivotRig finish_pivot_rig(const std::vector<PivotNode>& nodes, const PivotBones& bones,
                          const std::string& source, const std::string& name) {
  PivotRig pr;
  pr.rig = build_rig(bones.specs, source, name);
  pr.nodes = nodes;
  pr.synthetic_root = bones.synthetic_root;
  pr.bone_node.assign(pr.rig.nbone, -1);
  pr.bone_tail_node.assign(pr.rig.nbone, -1);
  pr.bone_tail_end.assign(pr.rig.nbone, -1);
  for (std::size_t s = 0; s < bones.specs.size(); ++s) {
    const int b = pr.rig.find_bone(bones.specs[s].name);
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
  for (int b = 0; b < rig.nbone; ++b) {
    scratch.orient_world[b] =
        (node_rotation_world[pr.bone_node[b]] * rig.bone_rest_orient_world[b]).normalized();
  }
  scratch.head_world[0] = root_pivot_world + node_rotation_world[0] *
                                                 (rig.bone_rest_head_world[0] -
                                                  pr.nodes[0].rest_world);
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
      tail[b] = node_pos_world[0];
      head[b] = node_pos_world[0] +
                node_rotation_world[0] * (rig.bone_rest_head_world[0] - pr.nodes[0].rest_world);
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
