// From a tree of pivots (points that rotate, as BVH joints and MuJoCo bodies are) to a rig of
// bones (rods that meet head-to-tail), and from the pivots' rotations to a Pose.
//
// A pivot J sits at a rest position p_J (world, rig units) and turns, with everything below it,
// by a world rotation R_J (relative to rest, world frame). Its children C sit at offsets
// o_C = p_C - p_J. The rig model needs every bone's head on its parent's tail, so:
//   1. segments: the children of J (and J's extra end points, e.g. a BVH End Site) are grouped by
//      offset; every group with a non-zero offset becomes one bone from p_J to that point. The
//      bone follows J: its world orientation is R_J * rest_orient_world. Children at the same
//      point share one bone (this is what makes export -> import give back the same rig).
//   2. zero offsets: a child C at J's own position has no bone of its own; C's segments hang from
//      the bone that ends at p_J (the "incoming" bone of J), and C's rotation still drives them
//      (the local rotation becomes the product of J's and C's).
//   3. the root: if exactly one bone starts at the root pivot, it is the rig's root. Otherwise
//      (0 or >= 2, e.g. BVH Hips -> Spine, LeftUpLeg, RightUpLeg) a synthetic root bone is added
//      from p_root - l * Z to p_root (l = mean length of the bones starting there, 1 if none), that
//      follows the root pivot; the other bones hang from its tail.
//   3b. welds (rig.h "Welds"): a pivot's segments turn together, one rigid body: its first segment
//      carries the pivot's joint, the others are welded to it (siblings); below a synthetic root
//      the root pivot's segments are welded to it (their parent), which follows the same pivot.
//   3c. a pinned root pivot (a BVH root with no position channels: it turns in place): a rig
//      whose root bone starts at the root pivot pins it there (RootJoint::kPinned); a synthetic
//      root, whose head lies below the pivot, would swing the pivot about that head, so it
//      becomes a fixed handle that follows no pivot (bone_node -1, RootJoint::kFixed), and the
//      root pivot's own segments turn on a ball at the handle's tail, the pivot: the first a ball,
//      the others welded to it (pin_root_pivot).
//   4. names: a bone is named after its pivot when the pivot has one segment, otherwise
//      "<pivot>><first child pivot>" (or "<pivot>>end", "<pivot>>end2", ... for end points); the
//      synthetic root takes the root pivot's name (or "<root>_root" if that is taken).
// Pose (kinematics.h): bone orientation O_b = R_node(b) * O_rest_b; the root head is
// p_root + R_root (h_rest_0 - p_root_rest); local rotations follow from local_rotations_from_world.
#pragma once

#include <string>
#include <vector>

#include "physik/model/kinematics.h"
#include "physik/model/rig.h"

namespace physik {

struct PivotNode {
  std::string name;
  int parent = -1;                 // index into the node list, parents first; -1 for the root
  Vec3 rest_world = Vec3::Zero();  // rest position of the pivot (rig units)
  std::vector<Vec3> ends_world;    // extra tail points that turn with this pivot (rig units)
};

// The bones before build_rig, so a caller can set masses, frames and limits first.
struct PivotBones {
  std::vector<BoneSpec> specs;      // in DFS order
  std::vector<int> spec_node;       // (nspec) the pivot whose rotation the bone follows; -1: none
                                    // (a pinned root's fixed handle, 3c.)
  std::vector<int> spec_parent;     // (nspec) parent spec, -1 for the root
  std::vector<int> spec_tail_node;  // (nspec) child pivot at the tail, or -1
  std::vector<int> spec_tail_end;   // (nspec) index into the pivot's ends_world at the tail, or -1
  bool synthetic_root = false;      // spec 0 is the synthetic root (tail = root pivot)
  RootJoint root_joint = RootJoint::kFree;   // the root's joint to the world (the caller's)
  std::vector<std::vector<int>> node_specs;  // (nnode) segments starting at each pivot
  std::vector<int> node_incoming;            // (nnode) spec whose tail is at the pivot, -1 for none
};

// Groups and names segments, builds the specs (roll 0 frames, mass = mass_per_length * length,
// the given radius). Throws InputError (naming `source`) if the pivots do not form a tree.
PivotBones pivot_bones(const std::vector<PivotNode>& nodes, const std::string& source,
                       double mass_per_length = 1.0, double radius = 0.5);

// Holds the root pivot in place while it turns (3c.): pins the root bone, or makes a synthetic
// root a fixed handle with the root pivot's segments on a ball at its tail.
void pin_root_pivot(PivotBones& bones);

struct PivotRig {
  Rig rig;
  std::vector<PivotNode> nodes;
  std::vector<int> bone_node;       // (nbone) pivot whose rotation the bone follows, -1: none
  std::vector<int> bone_tail_node;  // (nbone) child pivot at the tail, or -1
  std::vector<int> bone_tail_end;   // (nbone) end point of bone_node at the tail, or -1
  bool synthetic_root = false;      // bone 0 ends at the root pivot and follows it
};

// build_rig on the (possibly edited) specs, keeping the bone -> pivot maps.
PivotRig finish_pivot_rig(const std::vector<PivotNode>& nodes, const PivotBones& bones,
                          const std::string& source, const std::string& name);

// Pose from every pivot's world rotation relative to rest (world frame) and the root pivot's
// world position (rig units). `scratch` is resized as needed.
void pivot_pose(const PivotRig& pr, const std::vector<Quat>& node_rotation_world,
                const Vec3& root_pivot_world, BoneFrames& scratch, Pose& out);

// World positions every bone's head and tail should have, given every pivot's world position and
// rotation (for checks): head = pivot, tail = child pivot or pivot + R * (end - pivot rest).
void pivot_bone_targets(const PivotRig& pr, const std::vector<Vec3>& node_pos_world,
                        const std::vector<Quat>& node_rotation_world, std::vector<Vec3>& head,
                        std::vector<Vec3>& tail);

}  // namespace physik
