// The rig: a constant description of an articulated character (the model half of the
// MuJoCo-style model/data split). Nothing here changes during a simulation or a solve.
//
// Bodies (paper Sec. 3, "each bone is a rigid rod"; original fwik.py):
//   mass    m = mass_per_length * L                       (kg), or a total mass given directly
//   inertia of a solid cylinder of radius r and length L about its centre, in the bone frame
//   (local +Y along the bone):
//     I_yy = 1/2 m r^2,   I_xx = I_zz = 1/12 m (3 r^2 + L^2)   (kg m^2)
//   The original code uses r = 0.5 and mass_per_length = 1 for every bone.
//
// Joints (paper Sec. 3.2; original: one joint per parent with children, [parent] + children):
//   a joint is the tail of a parent bone together with the heads of all its children, which must
//   meet there at rest. A bone without children has no joint at its tail.
//
// Limits: per bone, per local axis x, y, z, an interval [min, max] (rad) on the component of the
// rotation vector (exponential map, as the original's quaternion log) of the bone's rotation
// relative to its rest orientation in its parent's frame. An absent axis is free; min == max
// locks the axis.
//
// Welds (models/README.md "Welded bones"): a bone may be welded to its parent, or to a sibling
// listed before it (the segments of one BVH joint or MuJoCo body, which turn together). A welded
// bone has no degree of freedom of its own: it keeps its rest orientation relative to the bone it
// is welded to, and a group of bones welded together is one rigid body. Its joint (the joint
// types below) is a weld; its joint parent is the bone it is welded to.
//
// The root's joint to the world: free (6 DOF, the default), pinned (a ball at its head, held at
// its rest position: 3 DOF, its limits relative to its rest frame in the world, so that two
// locked axes make a hinge to the world) or fixed (0 DOF, it never moves).
//
// Locked axes (docs/engine.md "Hinges and two-axis joints"). The exact and implicit schemes (and
// MuJoCo's model of them) give a joint only its free coordinates, as MuJoCo does: with L the
// joint's lock rotation exp(sum over locked axes k of min_k e_k) (identity when every locked
// axis is locked at zero), a bone's local rotation is
//   2 locked axes  hinge      q = L exp(t e_a)                     1 coordinate t
//   1 locked axis  universal  q = L exp(t1 e_a) exp(t2 e_b)        2 coordinates (t1, t2)
//   3 locked axes  weld       q = L                                0 coordinates
// with e_a, e_b the free local axes in x, y, z order: two hinges in sequence, as MuJoCo writes
// two hinges in one body (its second axis turns with the first). The coordinates are holonomic:
// the pose never leaves this set, so a locked axis never turns. A limit on a free axis bounds its
// coordinate t (a hinge's angle exactly where its locked axes are at zero, the rotation vector's
// component to first order elsewhere). The gauss-seidel scheme (the paper's) keeps every bone
// that is not welded a ball, its locked axes held by torsion springs (LockedAxes::kSprings).
//
// Arrays are indexed by bone in DFS order: every parent comes before its children.
//
// Sizes and magnitudes (checked by build_rig, so every product the engine forms stays finite:
// the inertia m (3 r^2 + L^2) / 12 and its inverse, squared distances, kinetic energies):
//   at most kMaxBones bones; |coordinate| <= kMaxCoordinate rig units; mass and radius within
//   [kMinScale, kMaxScale] (kg, rig units); explicit moments within [kMinScale^3, kMaxScale^3]
//   kg m^2. Names are valid UTF-8 without control characters (names.h).
#pragma once

#include <array>
#include <string>
#include <utility>
#include <vector>

#include "physik/model/source_skeleton.h"
#include "physik/model/types.h"

namespace physik {

constexpr int kMaxBones = 1000000;      // bones per rig (about 1 GB of rig and state)
constexpr double kMaxCoordinate = 1e9;  // rig units, any head or tail coordinate
constexpr double kMinScale = 1e-9;      // smallest mass (kg) or radius (rig units)
constexpr double kMaxScale = 1e9;       // largest mass (kg) or radius (rig units)
// a bone's collision capsule radius when neither the bone nor the rig's defaults give one, as a
// fraction of the bone's length: the capsule the MJCF export has always drawn, so PhysIK and the
// MuJoCo reference collide the same shapes, and it scales with each rig's own units
constexpr double kCollisionRadiusPerLength = 0.06;

// How a bone is attached across its joint (MuJoCo's mjtJoint, less slide; a universal joint is
// two of MuJoCo's hinges in one body)
enum class JointType {
  kFree,       // the root only: 6 DOF, velocity (v_com world, w local)
  kBall,       // 3 DOF at the bone's head: a ball to its parent, or a pinned root's to the world
  kHinge,      // 1 DOF at the head: two locked axes (a pinned root's too)
  kUniversal,  // 2 DOF at the head: one locked axis, two hinges in sequence
  kWeld,       // 0 DOF: welded to its joint parent, every axis locked, or a fixed root
};
const char* to_string(JointType type);

// The root's attachment to the world, as a rig file names it ("root").
enum class RootJoint { kFree, kPinned, kFixed };
const char* to_string(RootJoint root);

struct AxisLimit {
  bool limited = false;  // false: the axis is free
  double min = 0.0;      // rad, lower bound of the rotation-vector component
  double max = 0.0;      // rad, upper bound
  bool locked() const { return limited && min == max; }
};

// One bone as written in a rig file, before derived quantities are computed.
struct BoneSpec {
  std::string name;
  std::string parent;                        // empty for the root
  Vec3 head_world{0, 0, 0};                  // rest position of the head (rig units)
  Vec3 tail_world{0, 1, 0};                  // rest position of the tail (rig units)
  Mat3 rest_frame_world = Mat3::Identity();  // columns: bone x, y, z axes in world at rest
  std::array<AxisLimit, 3> limit{};          // per local axis x, y, z
  double mass = 1.0;                         // kg, total
  double radius = 0.5;  // rig units, radius of the cylinder used for the inertia
  // optional explicit principal moments about the bone's centre, bone-local x, y, z (kg m^2);
  // zero (the default) means the cylinder of `radius` (e.g. MuJoCo bodies imported as bones)
  Vec3 inertia_local = Vec3::Zero();
  // rig units, the collision capsule's radius (contacts); 0 (the default) means
  // kCollisionRadiusPerLength x the bone's length
  double collision_radius = 0.0;
  // the bone this one is welded to (its parent, or a sibling listed before it); empty: not welded
  std::string weld;
  // the human template's segment it belongs to ("thigh.L"; human_template.h), "" for none
  std::string segment;
  // unit, bone frame: the template's forward axis (the face, a palm); zero for none
  Vec3 forward_local = Vec3::Zero();
};

struct Joint {
  int parent = -1;            // the bone whose tail is the joint; -1: the world (a pinned root's
                              // head, its only child the root)
  std::vector<int> children;  // bones whose heads meet there, in DFS order
  bool anchored = false;      // held by the world: the point does not accelerate (a pinned
                              // root's head; a fixed root's tail)
  int nbone() const { return (parent >= 0 ? 1 : 0) + static_cast<int>(children.size()); }
};

struct Rig {
  std::string name;  // from the file, or generated
  int nbone = 0;
  RootJoint root_joint = RootJoint::kFree;
  int nv = 0;          // velocity coordinates: 6, 3, 2, 1 or 0 for the root, 3 per ball, 2 per
                       // universal joint, 1 per hinge, 0 per weld (LockedAxes::kRemoved)
  int nv_springs = 0;  // the same with LockedAxes::kSprings: 6, 3 or 0 for the root, 3 per bone
                       // that is not welded

  // per bone, DFS order
  std::vector<std::string> bone_name;           // (nbone)
  std::vector<int> bone_parent;                 // (nbone) -1 for the root; bone_parent[i] < i
  std::vector<std::vector<int>> bone_children;  // (nbone) x (varies)
  std::vector<Vec3> bone_rest_head_world;       // (nbone) rig units
  std::vector<Vec3> bone_rest_tail_world;       // (nbone) rig units
  std::vector<Quat> bone_rest_orient_world;     // (nbone) rest frame as a rotation world<-bone
  std::vector<Quat> bone_rest_orient_parent;    // (nbone) rest frame in the parent's rest frame
                                                //         (root: = bone_rest_orient_world)
  std::vector<Vec3> bone_head_in_parent;        // (nbone) head, in the parent's frame, relative to
                                                //         the parent's head (root: zero)
  std::vector<double> bone_length;              // (nbone) rig units
  std::vector<double> bone_mass;                // (nbone) kg
  std::vector<double> bone_radius;              // (nbone) rig units, the inertia cylinder's
  std::vector<double> bone_collision_radius;    // (nbone) rig units, the collision capsule's
  std::vector<Vec3> bone_inertia_local;         // (nbone) principal moments about the centre of
                                                //         mass, bone-local x, y, z (kg m^2)
  std::vector<std::array<AxisLimit, 3>> bone_limit;  // (nbone) per local axis
  // the human template's segment of each bone ("" for none) and its forward axis (unit, bone
  // frame: the face, a palm; zero for none): what an aim without an axis turns toward its point
  // (human_body.h; a rig converted from a skeleton recognised as human has them)
  std::vector<std::string> bone_segment;  // (nbone)
  std::vector<Vec3> bone_forward_local;   // (nbone)
  std::vector<int> bone_joint_at_tail;    // (nbone) joint index at the tail, or -1
  std::vector<int> bone_joint_at_head;    // (nbone) joint index at the head, or -1 (root)

  // the joint model of the exact and implicit schemes (and MuJoCo's): per bone its joint's type,
  // the bone across it, and where its velocity coordinates start
  std::vector<JointType> bone_joint_type;  // (nbone) root: free, ball, hinge, universal
                                           //         (pinned) or weld (fixed, or pinned and
                                           //         locked on every axis)
  std::vector<int> bone_joint_parent;      // (nbone) the bone it is welded to, else its parent;
                                           //         -1 for the root (the world)
  std::vector<int> bone_dofadr;            // (nbone) its first coordinate in (nv)
  std::vector<std::array<int, 2>> bone_joint_axes;  // (nbone) a hinge's free local axis [0], a
                                                    //   universal's [0] then [1] (0, 1, 2 = x,
                                                    //   y, z); -1 where unused
  std::vector<Quat> bone_joint_lock;     // (nbone) L = exp(locked angles): a hinge's, universal's
                                         //         or locked weld's frame in the bone's rest frame
                                         //         (identity where no axis is locked away from 0)
  std::vector<int> bone_dofadr_springs;  // (nbone) its first coordinate in (nv_springs)
  std::vector<int> bone_weld;            // (nbone) the bone it is welded to, or -1
  std::vector<Quat> bone_rest_orient_weld;  // (nbone) a welded bone's rest frame in the frame of
                                            //         the bone it is welded to (else identity)
  std::vector<int> bone_body;   // (nbone) the first bone of its rigid body: a bone that is not
                                //         welded is its own; a welded one, its weld's body
  std::vector<int> body_nbone;  // (nbone) the bones of the body bone i starts (0: i is welded)

  // joints, one per bone with children (but a joint inside one welded body), in DFS order of the
  // parent; a pinned root's head first
  std::vector<Joint> joints;
  // the same joints' members flattened for the joint solve: a joint's parent, then its children,
  // one member per rigid body (a joint inside one welded body is not among the joints)
  std::vector<int> joint_member_bone;     // (nmember) bone index (the body's first bone there)
  std::vector<int> joint_member_body;     // (nmember) its body (Rig::bone_body)
  std::vector<int> joint_member_at_tail;  // (nmember) 1 if the joint point is that bone's tail
  std::vector<int> joint_first_member;    // (njoint + 1) offsets into the member arrays
  std::vector<int> joint_anchored;        // (njoint) 1 where Joint::anchored

  int find_bone(const std::string& name) const;  // -1 if absent
  int root() const { return 0; }
  double total_mass() const;
  int max_bones_per_joint() const;
  // rotational degrees of freedom of a bone relative to its parent: 3 minus locked axes, 0 for a
  // welded bone (the root's: its limits' relative to the world for a pinned root, 0 for a fixed
  // one; a free root's 6 are not counted here)
  int bone_dof(int bone) const;
  // its joint's type in either joint model (LockedAxes): kRemoved is bone_joint_type; kSprings
  // turns every hinge, universal joint and weld by locks into a ball
  JointType joint_type(int bone, LockedAxes locked) const {
    const JointType t = bone_joint_type[bone];
    if (locked == LockedAxes::kRemoved || t == JointType::kFree || t == JointType::kBall) return t;
    if (bone_weld[bone] >= 0 || (bone == 0 && root_joint == RootJoint::kFixed)) {
      return JointType::kWeld;
    }
    return JointType::kBall;
  }
  int dofadr(int bone, LockedAxes locked) const {
    return locked == LockedAxes::kRemoved ? bone_dofadr[bone] : bone_dofadr_springs[bone];
  }
  int velocity_count(LockedAxes locked) const {
    return locked == LockedAxes::kRemoved ? nv : nv_springs;
  }
  // some joint has locked axes removed: a hinge, a universal joint, or a weld by locks
  bool has_locked_joints() const;
  bool welded(int bone) const { return bone_weld[bone] >= 0; }
  bool has_welds() const;
  // the root's head never moves (pinned or fixed)
  bool root_anchored() const { return root_joint != RootJoint::kFree; }
  // length of the longest root-to-leaf path plus nothing else: the rig's reach from its root
  double height() const;  // extent of the rest pose along world Z (rig units)
  // the mean bone length (rig units): the rig's own length scale, whatever the arrangement of its
  // bones (a flat rig has height 0, a 300-bone chain along Z a height of 300 bone lengths)
  double length_scale() const;
  // the length residuals, gaps and tolerances are taken over (rig units): the rest pose's height,
  // or its mean bone length when that is larger. A flat rig (a MuJoCo arm converted lying along
  // x has a height of 6e-17, round-off) would otherwise divide by nothing; an upright rig's
  // height is longer than its mean bone.
  double reference_length() const;
  // the path length from the root's head to the point `alpha` along `bone` (0 = head, 1 = tail):
  // the lengths of the bones above it and alpha of its own, rig units (its chain's reach)
  double chain_length(int bone, double alpha) const;
  // two bones meet at one joint (parent and child, or two children of one parent) or belong to
  // one rigid body (welded together): their collision capsules never collide
  bool bones_share_joint(int a, int b) const;

  // further bone pairs whose capsules never collide, in every scene of this rig (the rig file's
  // collision_exclude: e.g. the pairs a converter found overlapping at rest), each (lower index,
  // higher index), sorted, unique; a scene's own collision_exclude adds to them
  std::vector<std::pair<int, int>> collision_exclude;
  bool collision_excluded(int a, int b) const;  // the pair is in collision_exclude

  // the rig file's free text, kept so that a rig written back still says what it is
  std::string comment;
  std::string units;                // e.g. "metres (BVH centimetres x 0.01), kg"
  std::vector<std::string> source;  // notes: where the rig came from, what a converter changed
  // the skeleton it was converted from (rig from-bvh): its joints, channels, units and axes, and
  // which bones turn with each joint; empty for a rig made otherwise (source_skeleton.h)
  SourceSkeleton source_skeleton;
};

// Sets rig.collision_exclude from bone-name pairs (sorted, duplicates dropped). An unknown bone
// or a bone paired with itself is an InputError naming `source`, the field
// "collision_exclude[i]" and the bone.
void set_collision_exclude(Rig& rig, const std::vector<std::pair<std::string, std::string>>& pairs,
                           const std::string& source);

// Cylinder inertia about the centre, bone-local axes (local y along the bone). kg m^2.
Vec3 cylinder_inertia(double mass, double radius, double length);

// Build a rig from bone specs in any order: validates the tree (one root, known parents, no
// cycles, no duplicate names), lengths, frames, limits, masses and welds (to a parent or an
// earlier sibling, no cycle, no limits on a welded bone, none on a free root), reorders to DFS
// (children in the order given), derives joints, the joint model and inertias. `source` names
// the file in error messages. Throws InputError.
Rig build_rig(const std::vector<BoneSpec>& specs, const std::string& source,
              const std::string& name = "", RootJoint root = RootJoint::kFree);

// The joint model (bone_joint_type and the arrays beside it, nv) from the rig's welds, root and
// limits again, after bone_limit was edited (a limits file: joint_limits.h); build_rig calls it.
void refresh_joint_model(Rig& rig);

// Blender's rest frame from head, tail and roll: the minimal rotation taking +Y to the bone
// direction, followed by a roll about the bone's own Y (rad). Columns are bone x, y, z in world.
Mat3 rest_frame_from_roll(const Vec3& head_world, const Vec3& tail_world, double roll);

}  // namespace physik
