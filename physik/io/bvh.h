// BVH (Biovision hierarchy) and qBVH: read into a Rig plus one Pose per frame, write any Rig and
// any pose sequence.
//
// BVH semantics used here (as Blender's importer reads them):
//   every joint J has a frame; at rest all frames are parallel to the file's axes. Per frame
//     R_J = R_parent * L_J,   p_J = p_parent + R_parent * t_J        (root: R_J = L_J, p_J = t_J)
//   t_J is the OFFSET, except that position channels replace it component by component
//   (so a root's Xposition.. are its absolute position). L_J is the product of the rotation
//   channels in the order listed: "Zrotation Xrotation Yrotation" means L = Rz(a) Rx(b) Ry(c),
//   angles in degrees. An End Site's point is p_J + R_J * OFFSET.
// qBVH (seed 002: "identical to bvh, except that instead of storing Euler rotations, it stores
// quaternions"). Our exact format: the same file, where a joint's rotation channels are the four
//     Wquaternion Xquaternion Yquaternion Zquaternion
// (in any order, all four, never mixed with Euler channels). The values are the unit quaternion
// (w, x, y, z) of L_J (Hamilton convention, L_J rotates the joint's frame into its parent's, as the
// Euler matrix does). Readers reject a quaternion whose norm is not within 1e-3 of 1 and then
// normalise; the writer keeps consecutive frames in the same hemisphere (w >= 0 on frame 0).
// Files we write use the extension .qbvh.
//
// Sizes (rig_sizing.h): every bone's radius and collision radius 0.14 x its length (or
// --radius), its mass a rod of density 1000 kg/m^3 (or mass_per_length x L), all after the scale;
// the pairs of bones whose capsules overlap at rest are added to the rig's collision_exclude.
//
// BVH -> rig (pivot_rig.h): every BVH joint is a pivot; its children and End Sites give bones from
// the joint to each distinct child offset. A joint with one such offset gives one bone named after
// the joint (Blender's convention: bone "LeftArm" starts at joint LeftArm and carries its
// rotation). A joint whose children sit at several offsets gives one bone per offset, named
// "<joint>><child>", all turning with the joint; children at a zero offset merge into the bone that
// ends there. A root with several bones (Hips -> Spine, LeftUpLeg, RightUpLeg) gets a synthetic
// root bone named after it, from 1 bone-length below (-Z) up to the root joint; it carries the
// root's translation and rotation, and the bones below it are fixed to it (identity local
// rotation). FK of the rig then reproduces every joint and End Site position of every frame
// (BvhAnimation::max_position_error measures it). Position channels on non-root joints cannot be
// represented when they differ from the OFFSET (bones have fixed lengths): their rotation is kept
// and max_position_error reports the gap. The rig keeps the file's skeleton (Rig::
// source_skeleton: joints, OFFSETs, channels, End Sites, the axes and the scale, and the bones
// that turn with each joint), which the writer below writes back.
//
// Rig -> BVH: one BVH joint per bone at its head (named after the bone, spaces -> '_'), OFFSET the
// rest head relative to the parent's rest head; a leaf gets an End Site at its tail. Rotation of
// joint b per frame: L_b = Rw_parent^-1 Rw_b with Rw_b = O_b O_rest_b^-1 (the bone's world rotation
// from rest). The root has position channels (its head). Exported then imported, every bone keeps
// its name, parent, head and tail.
//
// Rig -> its source skeleton (source_skeleton.h, written by default for a rig that has one, the
// rig made by bvh_to_rig): the source file's joints, OFFSETs, End Sites and channels as they
// were (names, hierarchy, channel order, file units), so the pose goes back onto the character it
// came from. Per frame (source_pose.h): each joint's world rotation from rest in file axes,
// Rf_J = A^-1 R_J A; its rotation channels hold L_J = Rf_parent^-1 Rf_J decomposed in the
// joint's own channel order (closest to the previous frame's angles; qBVH: its quaternion, in
// one hemisphere from frame to frame); the root's position channels hold the root joint's
// position, A^-1 p_root / scale; a non-root joint's position channels its OFFSET (a rig's bone
// keeps its length). What the file cannot hold is said (BvhWriteReport): a root that moved along
// an axis it has no position channel for, a turn about an axis a joint has no rotation channel
// for (a joint with fewer than three: the decomposition in its order followed by the missing
// axes, their angles left out). Options: `quaternion` writes every rotating joint's rotation
// channels as the four quaternion channels, `euler_order` every three-angle joint's in that
// order, the rest kept; the file's axes and scale are the source's (the options' are not read).
//
// Axes: BvhAxes::kYUp (default) treats the file as Y up (the BVH habit; Blender's importer default
// axis_forward=-Z, axis_up=Y) and maps file (x, y, z) -> rig (x, -z, y) (+90 deg about X);
// kZUp uses file coordinates as they are.
#pragma once

#include <iosfwd>
#include <string>
#include <vector>

#include "physik/engine/bone_overlaps.h"
#include "physik/model/kinematics.h"
#include "physik/model/pivot_rig.h"
#include "physik/model/rig.h"
#include "physik/model/rig_sizing.h"
#include "physik/model/source_skeleton.h"

namespace physik {

enum class BvhChannel { kXpos, kYpos, kZpos, kXrot, kYrot, kZrot, kWquat, kXquat, kYquat, kZquat };

struct BvhJoint {
  std::string name;
  int parent = -1;                   // joint index, -1 for the root; parents first
  Vec3 offset = Vec3::Zero();        // file units, in the parent's frame
  std::vector<BvhChannel> channels;  // in file order
  int channel_start = 0;             // column of its first channel in a frame row
  std::vector<Vec3> end_sites;       // End Site offsets, file units, in this joint's frame
  int line = 0;                      // line of its ROOT/JOINT keyword
};

struct BvhFile {
  std::vector<BvhJoint> joints;  // DFS order, as in the file
  int nchannel = 0;
  double frame_time = 1.0 / 30.0;           // s
  std::vector<std::vector<double>> frames;  // (nframe x nchannel), degrees / file units
};

// Parse BVH or qBVH text. Throws InputError "<source>: line N: field '<what>': <reason>" on
// unbalanced braces, a CHANNELS count that does not match its names, an unknown keyword or
// channel, a frame whose value count differs from the channel count, a frame count that differs
// from "Frames:", a non-number, NaN or infinity, an OFFSET or position channel beyond
// +-kMaxCoordinate (rig.h), a joint name that is not printable UTF-8 (names.h), more than
// kMaxBones joints. Any nesting depth is read (no recursion).
BvhFile parse_bvh(const std::string& text, const std::string& source);
BvhFile read_bvh_file(const std::string& path);

// Local rotation L_J and translation t_J of joint j in a frame row (file axes; degrees -> rad).
Quat bvh_local_rotation(const BvhJoint& joint, const std::vector<double>& row);
Vec3 bvh_local_translation(const BvhJoint& joint, const std::vector<double>& row);
// Reference FK in file axes: world rotation and position of every joint for frame `frame`
// (-1 = rest: all channels zero and offsets as given).
void bvh_world(const BvhFile& bvh, int frame, std::vector<Quat>& rot_world,
               std::vector<Vec3>& pos_world);

using BvhAxes = SourceAxes;  // kYUp, kZUp

// file -> rig coordinates (rotation part; a vector maps as q * v, a rotation as q R q^-1)
Quat bvh_axes_to_rig(BvhAxes axes);

struct BvhImportOptions {
  BvhAxes axes = BvhAxes::kYUp;
  double scale = 1.0;    // rig units per file unit
  SizingOptions sizing;  // radii and masses (rig_sizing.h): by default r = 0.14 L, rod masses
  // add the bone pairs whose capsules overlap at rest to the rig's collision_exclude
  // (bone_overlaps.h); its cost grows with the pairs of bones piled at one point
  bool exclude_rest_overlaps = true;
};

struct BvhAnimation {
  PivotRig pivots;                         // the rig (pivots.rig) and its bone -> BVH joint map
  std::vector<Pose> poses;                 // one per frame
  double frame_time = 1.0 / 30.0;          // s
  double max_position_error = 0.0;         // rig units: largest |FK - BVH| of any joint or End Site
  std::vector<BoneOverlap> rest_overlaps;  // the pairs added to the rig's collision_exclude
  // what the file asks that the rig cannot quite be, by joint: "joint 'Hips' has 2 children at
  // its own position (zero OFFSET: Spine, Hip2)..."
  std::vector<std::string> warnings;
  const Rig& rig() const { return pivots.rig; }
};

// The unit a BVH file's standing figure of `height` file units x `scale` rig units looks like it
// is in, by the height of a person (1 to 2.5 m): "centimetres" for 100 to 250 rig units,
// "millimetres" for 1000 to 2500, "" otherwise; `suggested_scale` is then the --scale that makes
// metres (0.01, 0.001).
std::string guess_bvh_units(double height, double& suggested_scale);

BvhAnimation bvh_to_rig(const BvhFile& bvh, const std::string& source,
                        const BvhImportOptions& options = {});
BvhAnimation load_bvh(const std::string& path, const BvhImportOptions& options = {});

struct BvhExportOptions {
  bool quaternion = false;  // write qBVH
  // rotation channel order for BVH, any permutation of XYZ; "" = ZXY for the rig's own skeleton,
  // each joint's own order for the source skeleton
  std::string euler_order;
  // the rig's source skeleton when it has one (Rig::source_skeleton); false: the rig's own
  // skeleton, one joint per bone (axes and scale below are read for it only)
  bool source_skeleton = true;
  BvhAxes axes = BvhAxes::kYUp;
  double scale = 1.0;              // file units per rig unit
  double frame_time = 1.0 / 30.0;  // s
  std::string target;              // the file written, for error messages ("" = a stream)
};

// What a written file could not hold (the source skeleton's limits), one sentence each, e.g.
// "root joint 'Hips' has no Yposition channel: the rig's root moved up to 3.2 file units along
// file y, which the file leaves out". Empty for the rig's own skeleton, which holds every pose.
struct BvhWriteReport {
  bool source_skeleton = false;  // the source skeleton was written
  std::vector<std::string> warnings;
};

// The skeleton write_bvh writes for `rig` under `options`: the source's, or the rig's own.
bool writes_source_skeleton(const Rig& rig, const BvhExportOptions& options);

// Channel names as BVH writes them ("Xposition", ..., "Zquaternion"); bvh_channel_from_name reads
// any case and returns false for an unknown name.
const char* bvh_channel_name(BvhChannel channel);
bool bvh_channel_from_name(const std::string& name, BvhChannel& out);

// A BvhFile as text: HIERARCHY (iteratively: any depth; indentation stops deepening at 32
// levels) and MOTION with `frame_time`; the joints' channel_start and the file's nchannel are
// not read (each row holds every joint's channels in order). Throws InputError naming `target`
// for a value that is not finite.
void write_bvh_file(const BvhFile& bvh, const std::string& target, std::ostream& out);

// The source skeleton as a BvhFile (no frames): its joints, offsets, channels and End Sites.
BvhFile source_skeleton_bvh(const SourceSkeleton& skeleton);

// Whether `clip`'s skeleton is `skeleton`: the same joints in the same order with the same names,
// parents, channels (in order) and End Sites, every OFFSET and End Site within 1e-6 of the
// skeleton's size. "" when it is, else the first difference, e.g. "joint 4 is 'LeftArm' in the
// clip, 'LeftShoulder' in the rig's source skeleton".
std::string source_skeleton_mismatch(const SourceSkeleton& skeleton, const BvhFile& clip);

// The rig's pose at frame `frame` (0-based) of `clip`, a clip of the rig's source skeleton
// (source_skeleton_mismatch empty): its joints' rotations and root position through the source's
// axes and scale (source_pose.h). `scratch` is resized.
void source_clip_pose(const Rig& rig, const BvhFile& clip, int frame, BoneFrames& scratch,
                      Pose& out);

// source_clip_pose for a frame that a scene or a run will start from or aim at: InputError
// "<source>: <element>: field 'frame': ..." naming the frame when it puts the rig's root head past
// +-kMaxCoordinate (rig.h), the bound every coordinate of a scene keeps (a root position channel
// within the file's bound times a large source_skeleton scale).
void checked_clip_pose(const Rig& rig, const BvhFile& clip, int frame, const std::string& source,
                       const std::string& element, BoneFrames& scratch, Pose& out);

// true for paths ending in ".qbvh" (case-insensitive)
bool is_qbvh_path(const std::string& path);

// Euler angles (rad) of R = R_a0(e0) R_a1(e1) R_a2(e2) for an order such as "ZXY"; the middle
// angle in [-pi/2, pi/2]. Used by the writer; exposed for tests.
Vec3 euler_from_rotation(const Quat& q, const std::string& order);
Quat rotation_from_euler(const Vec3& angles, const std::string& order);

// Writes a rig and its poses (rest pose only when `poses` is empty). Throws InputError naming
// options.target (save_bvh: the path) for a bad Euler order, a scale or frame time that is not
// positive and finite, or a value that the scale pushes past double range.
BvhWriteReport write_bvh(const Rig& rig, const std::vector<Pose>& poses,
                         const BvhExportOptions& options, std::ostream& out);
BvhWriteReport save_bvh(const std::string& path, const Rig& rig, const std::vector<Pose>& poses,
                        const BvhExportOptions& options);

// Records a run as an animation: keeps the 1st, (every+1)th, ... call of record(); writes the file
// with frame_time = dt * every. For `physik simulate --bvh OUT [--every N]`.
class BvhRecorder {
 public:
  // dt: simulation step (s); every >= 1
  BvhRecorder(const Rig& rig, double dt, int every = 1, BvhExportOptions options = {});
  void record(const Pose& pose);
  void record(const BoneFrames& frames);  // world frames, as the engine holds them
  int recorded() const { return static_cast<int>(poses_.size()); }
  // qBVH if the path ends in .qbvh; folders are created. Throws InputError if it cannot write.
  BvhWriteReport save(const std::string& path) const;
  BvhWriteReport write(std::ostream& out) const;

 private:
  const Rig& rig_;
  int every_;
  long calls_ = 0;
  BvhExportOptions options_;
  std::vector<Pose> poses_;
};

}  // namespace physik
