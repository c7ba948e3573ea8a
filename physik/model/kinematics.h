// Poses and forward kinematics.
//
// A Pose is the rig's configuration in joint space:
//   root_head_world        world position of the root bone's head (rig units)
//   bone_local_rotation[i] rotation of bone i relative to its rest orientation, expressed in the
//                          bone's rest frame (Blender's pose-bone rotation). Identity = rest.
// Forward kinematics (DFS order, parents first), with R = orientation world<-bone:
//   R_root = R_rest_root * q_root,                 head_root = root_head_world
//   R_i    = R_parent * R_rest_in_parent_i * q_i,  head_i    = head_parent + R_parent * h_i
//   tail_i = head_i + R_i * (0, L_i, 0)
// where R_rest_in_parent_i and h_i (= (0, L_parent, 0) for a connected child) are rig constants.
// A welded bone ignores its q: R_i = R_weld * R_rest_in_weld_i (rig.h "Welds"), so every pose
// gives a welded group its rest shape.
//
// Joint angles for limits: the rotation vector (exponential map, |v| <= pi) of q_i, whose
// components along the bone's local x, y, z are compared with the per-axis limits.
#pragma once

#include <vector>

#include "physik/model/rig.h"

namespace physik {

struct Pose {
  Vec3 root_head_world = Vec3::Zero();    // rig units
  std::vector<Quat> bone_local_rotation;  // (nbone) rest-relative, bone frame
};

// World-space frames of every bone: what FK produces and what the engine integrates.
struct BoneFrames {
  std::vector<Vec3> head_world;    // (nbone) rig units
  std::vector<Vec3> tail_world;    // (nbone) rig units
  std::vector<Quat> orient_world;  // (nbone) world<-bone
  void resize(int nbone);
};

Pose rest_pose(const Rig& rig);

// FK into preallocated frames (no allocation when `out` is already sized).
void forward_kinematics(const Rig& rig, const Pose& pose, BoneFrames& out);
BoneFrames forward_kinematics(const Rig& rig, const Pose& pose);

// Inverse of FK for orientations: the local rotations and root position that reproduce the given
// world orientations (heads other than the root's are ignored).
void local_rotations_from_world(const Rig& rig, const BoneFrames& frames, Pose& out);
// One bone's local rotation from the world orientations (the same expression).
Quat local_rotation_from_world(const Rig& rig, const BoneFrames& frames, int bone);

// The local rotations of the welded bones only (rig.h "Welds"), from their world orientations,
// which forward kinematics puts at their welds' frames whatever a pose says: a pose made
// consistent with its frames, every other bone's rotation left exactly as it was.
void welded_local_rotations(const Rig& rig, const BoneFrames& frames, Pose& pose);

// Rotation vector of a unit quaternion (angle in [0, pi], radians times unit axis).
Vec3 rotation_vector(const Quat& q);

// Per-axis joint angles of bone i (rad): the rotation vector of its local rotation.
inline Vec3 joint_angles(const Pose& pose, int bone) {
  return rotation_vector(pose.bone_local_rotation[bone]);
}

// Distance (rig units) from a bone-attached point at fraction alpha along bone (0 = head,
// 1 = tail), in world coordinates.
inline Vec3 point_on_bone(const BoneFrames& f, int bone, double alpha) {
  return f.head_world[bone] + alpha * (f.tail_world[bone] - f.head_world[bone]);
}

// Centre of mass of the whole rig (rods: each bone's centre is its midpoint).
Vec3 center_of_mass(const Rig& rig, const BoneFrames& frames);

}  // namespace physik
