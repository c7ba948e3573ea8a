// Poses of a rig and poses of its source skeleton (source_skeleton.h), both ways. The source's
// pose is every joint's world rotation relative to rest and the root joint's world position,
// both in the rig's world frame and units (the file's axes and units are the BVH reader's and
// writer's business, physik/io/bvh.h).
//
// Source -> rig (pivot_rig.h "Pose"): a bone turning with joint J has the world orientation
//   O_b = R_J O_rest_b,
// a bone no joint lists keeps its rest orientation relative to its parent's; the root bone's head
//   head_0 = p_root + R_J0 (rest_head_0 - rest_p_root)      (J0 the root bone's joint)
// with rest_p_root = s A offset_root; the local rotations follow by local_rotations_from_world.
// Rig -> source: R_J = O_b O_rest_b^-1 of the first bone joint J lists (the one carrying its
// rotation; every bone of a welded group turns the same); a joint with no bone of its own turns
// with its parent (its local rotation the identity: a joint whose only children sit at its own
// position, whose rotation the rig cannot see apart from theirs); p_root from head_0 as above.
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

// The source's pose of the rig's world frames: each joint's world rotation relative to rest, and
// the root joint's world position.
void source_from_frames(const Rig& rig, const BoneFrames& frames,
                        std::vector<Quat>& joint_rotation_world, Vec3& root_joint_world);

}  // namespace physik
