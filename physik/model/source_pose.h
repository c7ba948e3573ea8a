// Poses of a rig and poses of its source skeleton (source_skeleton.h), both ways. The source's
// pose is every joint's world rotation relative to rest and the root joint's world position,
// both in the rig's world frame and units (the file's axes and units are the BVH reader's and
// writer's business, physik/io/bvh.h).
//
// Source -> rig (pivot_rig.h "Pose"): a bone turning with joint J has the world orientation
//   O_b = R_J O_rest_b,
// a bone no joint lists keeps its rest orientation relative to its parent's, a welded bone its
// rest orientation relative to the bone it is welded to (as forward kinematics puts it, so a
// joint whose bone is welded to another joint's turns with that one); the root bone's head
//   head_0 = p_root + R_J0 (rest_head_0 - rest_p_root)      (J0 the root bone's joint)
// with rest_p_root = s A offset_root; the local rotations follow by local_rotations_from_world.
// Rig -> source: R_J = O_b O_rest_b^-1 of the first bone joint J lists (the one carrying its
// rotation; every bone of a welded group turns the same); p_root from head_0 as above.
// A joint with no bone of its own (all its children at its own position, like CMU's Spine1 and
// LeftHand, or no child at all) has a rotation the rig cannot see apart from its children's: any
// R_J with the children's local rotations R_J^-1 R_C gives the same bones. So has a joint whose
// bones are welded to another joint's (no degree of freedom of its own: the rig holds it at rest
// relative to that joint, whatever the file turned it by). Such a joint is held: it keeps a local
// rotation H_J given by the caller, the one it had in the source frame the pose came from
// (identity: its rest):
//   R_J = R_parent H_J                                     (the root: H_J)
// and its children's local rotations, R_J^-1 R_C, absorb the rest. So a pose that came from a
// source frame and that nothing moved gives that frame's rotations back, and one that a solve
// moved keeps the boneless joint as it was while its children follow the bones.
#pragma once

#include <vector>

#include "physik/model/kinematics.h"

namespace physik {

// The rest position of the source's root joint in the rig's world (rig units).
Vec3 source_root_rest_world(const Rig& rig);

// The rig's pose for joint rotations `joint_rotation_world` (one per source joint, world frame,
// relative to rest) and the root joint at `root_joint_world` (rig units). `scratch` is resized.
// The rig must have a source skeleton.
void pose_from_source(const Rig& rig, const std::vector<Quat>& joint_rotation_world,
                      const Vec3& root_joint_world, BoneFrames& scratch, Pose& out);

// Whether source joint `j` is held (above): it has no bone of its own, or its first bone is
// welded to a bone of another joint; its rotation is then not read from the rig's bones.
bool source_joint_held(const Rig& rig, int j);

// The source's pose of the rig's world frames: each joint's world rotation relative to rest, and
// the root joint's world position. `held_local` (njoint, rig world axes, each relative to its
// parent's frame) gives the rotation H_J of every joint with no bone of its own; empty: the
// identity for each (rest).
void source_from_frames(const Rig& rig, const BoneFrames& frames,
                        const std::vector<Quat>& held_local,
                        std::vector<Quat>& joint_rotation_world, Vec3& root_joint_world);

}  // namespace physik
