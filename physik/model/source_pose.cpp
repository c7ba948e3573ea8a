// Rig poses from and to the source skeleton's joint rotations (source_pose.h).
#include "physik/model/source_pose.h"

#include <algorithm>

namespace physik {

Vec3 source_root_rest_world(const Rig& rig) {
  const SourceSkeleton& s = rig.source_skeleton;
  return s.scale * (source_axes_to_rig(s.axes) * s.joints.at(0).offset);
}

void pose_from_source(const Rig& rig, const std::vector<Quat>& joint_rotation_world,
                      const Vec3& root_joint_world, BoneFrames& scratch, Pose& out) {
  const std::vector<int> joint_of = source_bone_joints(rig.source_skeleton, rig.nbone);
  scratch.resize(rig.nbone);
  // each bone's world rotation from rest: its joint's, or (no joint lists it) its parent's
  for (int b = 0; b < rig.nbone; ++b) {
    Quat from_rest = Quat::Identity();
    if (rig.welded(b)) {
      // forward kinematics holds a welded bone at its weld's frame, whatever its joint turned
      const int w = rig.bone_weld[b];
      scratch.orient_world[b] =
          (scratch.orient_world[w] * rig.bone_rest_orient_weld[b]).normalized();
      continue;
    }
    if (joint_of[b] >= 0) {
      from_rest = joint_rotation_world[joint_of[b]];
    } else if (rig.bone_parent[b] >= 0) {
      const int p = rig.bone_parent[b];
      from_rest = scratch.orient_world[p] * rig.bone_rest_orient_world[p].conjugate();
    }
    scratch.orient_world[b] = (from_rest * rig.bone_rest_orient_world[b]).normalized();
  }
  const Quat root_turn = joint_of[0] >= 0 ? joint_rotation_world[joint_of[0]] : Quat::Identity();
  scratch.head_world[0] =
      root_joint_world + root_turn * (rig.bone_rest_head_world[0] - source_root_rest_world(rig));
  local_rotations_from_world(rig, scratch, out);
}

bool source_joint_held(const Rig& rig, int j) {
  const std::vector<int>& bones = rig.source_skeleton.joints[j].bones;
  if (bones.empty()) return true;
  const int weld = rig.bone_weld[bones[0]];
  return weld >= 0 && !std::binary_search(bones.begin(), bones.end(), weld);
}

void source_from_frames(const Rig& rig, const BoneFrames& frames,
                        const std::vector<Quat>& held_local,
                        std::vector<Quat>& joint_rotation_world, Vec3& root_joint_world) {
  const SourceSkeleton& s = rig.source_skeleton;
  joint_rotation_world.resize(s.joints.size());
  for (std::size_t j = 0; j < s.joints.size(); ++j) {
    const SourceJoint& joint = s.joints[j];
    if (!source_joint_held(rig, static_cast<int>(j))) {
      const int b = joint.bones[0];
      joint_rotation_world[j] =
          (frames.orient_world[b] * rig.bone_rest_orient_world[b].conjugate()).normalized();
      continue;
    }
    // a held joint: its parent's rotation times the held one (source_pose.h)
    const Quat parent = joint.parent >= 0 ? joint_rotation_world[joint.parent] : Quat::Identity();
    const Quat held = held_local.empty() ? Quat::Identity() : held_local[j];
    joint_rotation_world[j] = (parent * held).normalized();
  }
  const std::vector<int> joint_of = source_bone_joints(s, rig.nbone);
  const Quat root_turn = joint_of[0] >= 0 ? joint_rotation_world[joint_of[0]] : Quat::Identity();
  root_joint_world = frames.head_world[0] -
                     root_turn * (rig.bone_rest_head_world[0] - source_root_rest_world(rig));
}

}  // namespace physik
