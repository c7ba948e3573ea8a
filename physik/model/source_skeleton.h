// The skeleton a rig was converted from: a BVH file's joints, kept in the rig (Rig::
// source_skeleton, the rig file's "source_skeleton"; models/README.md "BVH and qBVH") so
// that a pose of the rig goes back onto the character it came from, and a clip of that character
// comes onto the rig.
//
// What is kept, as the file had it: each joint's name, parent, OFFSET (file units, file axes,
// in its parent's frame), channels in file order, End Sites; the file's axes convention and the
// scale of the conversion (rig units per file unit). And the map from the joints to the rig:
// the bones that turn with each joint (pivot_rig.h: a joint's segments, welded into one body; a
// synthetic root and the root joint's segments below it), the first of them carrying the
// joint's rotation.
//
// Frames: a joint's world rotation R_J (relative to rest, where every BVH frame is parallel to
// the file's axes) in file axes maps to the rig's world as A R_J A^-1, positions as s A p, with A
// the axes rotation below and s the scale:
//   y-up: file (x, y, z) -> rig (x, -z, y), +90 deg about X (the BVH habit, Blender's default)
//   z-up: the file's axes as they are
#pragma once

#include <string>
#include <vector>

#include "physik/model/types.h"

namespace physik {

// How a source file's axes sit in the rig's world (Z up).
enum class SourceAxes { kYUp, kZUp };

// The rotation taking file coordinates to rig coordinates (a vector maps as A v).
Quat source_axes_to_rig(SourceAxes axes);
const char* to_string(SourceAxes axes);  // "y-up", "z-up"

struct SourceJoint {
  std::string name;
  int parent = -1;                    // index into the joints, parents first; -1 for the root
  Vec3 offset = Vec3::Zero();         // file units, file axes, in the parent's frame
  std::vector<std::string> channels;  // in file order, as BVH names them: Xposition, Yposition,
                                      // Zposition, Xrotation, ..., Wquaternion, ... (qBVH)
  std::vector<Vec3> end_sites;        // End Site OFFSETs, file units, in this joint's frame
  std::vector<int> bones;  // rig bones that turn with this joint, ascending (DFS order); the
                           // first carries its rotation; empty: a joint with no bone of its own
};

struct SourceSkeleton {
  std::string format;  // "bvh"; empty: the rig has no source skeleton
  SourceAxes axes = SourceAxes::kYUp;
  double scale = 1.0;       // rig units per file unit
  double frame_time = 0.0;  // s, the source file's Frame Time; 0: not known (older rig files)
  std::vector<SourceJoint> joints;
  bool empty() const { return joints.empty(); }
};

// The joint every bone turns with (-1 for a bone no joint lists), from the joints' bone lists.
std::vector<int> source_bone_joints(const SourceSkeleton& skeleton, int nbone);

// Checks a skeleton against a rig of `nbone` bones: a format, a positive finite scale, a frame
// time that is 0 or positive and finite, at least one joint, listed depth-first as a BVH file
// lists them (parents before children, the first joint the only root, and each joint's parent
// the joint before it or one of that joint's ancestors: a file's hierarchy), finite offsets and End
// Sites, known channel names (at most one of each), no Euler rotation beside quaternion
// channels and all four quaternion channels or none, names that are valid UTF-8 without control
// characters, bone indices in range and each bone listed by one joint at most. InputError
// naming `source`, "source_skeleton" and the field.
void check_source_skeleton(const SourceSkeleton& skeleton, int nbone, const std::string& source);

}  // namespace physik
