#include "physik/model/kinematics.h"

#include <algorithm>
#include <cmath>

namespace physik {

void BoneFrames::resize(int nbone) {
  head_world.resize(nbone);
  tail_world.resize(nbone);
  orient_world.resize(nbone);
}

Pose rest_pose(const Rig& rig) {
  Pose p;
  p.root_head_world = rig.nbone ? rig.bone_rest_head_world[0] : Vec3::Zero();
  p.bone_local_rotation.assign(rig.nbone, Quat::Identity());
  return p;
}

void forward_kinematics(const Rig& rig, const Pose& pose, BoneFrames& out) {
  out.resize(rig.nbone);
  for (int i = 0; i < rig.nbone; ++i) {
    const int p = rig.bone_parent[i];
    if (p < 0) {
      out.orient_world[i] = rig.bone_rest_orient_parent[i] * pose.bone_local_rotation[i];
      out.head_world[i] = pose.root_head_world;
    } else {
      const int w = rig.bone_weld[i];
      // a welded bone keeps its rest frame in its weld's frame, whatever the pose says
      out.orient_world[i] = w >= 0 ? Quat(out.orient_world[w] * rig.bone_rest_orient_weld[i])
                                   : Quat(out.orient_world[p] * rig.bone_rest_orient_parent[i] *
                                          pose.bone_local_rotation[i]);
      out.head_world[i] = out.head_world[p] + out.orient_world[p] * rig.bone_head_in_parent[i];
    }
    out.orient_world[i].normalize();
    out.tail_world[i] = out.head_world[i] + out.orient_world[i] * Vec3(0, rig.bone_length[i], 0);
  }
}

BoneFrames forward_kinematics(const Rig& rig, const Pose& pose) {
  BoneFrames f;
  forward_kinematics(rig, pose, f);
  return f;
}

Quat local_rotation_from_world(const Rig& rig, const BoneFrames& frames, int i) {
  const int p = rig.bone_parent[i];
  const Quat parent_world = p < 0 ? Quat::Identity() : frames.orient_world[p];
  // R_i = R_parent * R_rest_in_parent * q  =>  q = R_rest_in_parent^-1 R_parent^-1 R_i
  return (rig.bone_rest_orient_parent[i].conjugate() * parent_world.conjugate() *
          frames.orient_world[i])
      .normalized();
}

void local_rotations_from_world(const Rig& rig, const BoneFrames& frames, Pose& out) {
  out.bone_local_rotation.resize(rig.nbone);
  out.root_head_world = frames.head_world[0];
  for (int i = 0; i < rig.nbone; ++i) {
    out.bone_local_rotation[i] = local_rotation_from_world(rig, frames, i);
  }
}

void welded_local_rotations(const Rig& rig, const BoneFrames& frames, Pose& pose) {
  if (!rig.has_welds()) return;
  for (int i = 1; i < rig.nbone; ++i) {
    if (rig.welded(i)) pose.bone_local_rotation[i] = local_rotation_from_world(rig, frames, i);
  }
}

Vec3 rotation_vector(const Quat& q_in) {
  // pick the hemisphere with w >= 0 so the angle is in [0, pi]
  Quat q = q_in.w() < 0.0 ? Quat(-q_in.w(), -q_in.x(), -q_in.y(), -q_in.z()) : q_in;
  const Vec3 v = q.vec();
  const double s = v.norm();
  if (s < 1e-12) return 2.0 * v;  // first order: angle ~ 2 |v|
  const double angle = 2.0 * std::atan2(s, q.w());
  return v * (angle / s);
}

Vec3 center_of_mass(const Rig& rig, const BoneFrames& frames) {
  Vec3 c = Vec3::Zero();
  double m = 0.0;
  for (int i = 0; i < rig.nbone; ++i) {
    c += rig.bone_mass[i] * 0.5 * (frames.head_world[i] + frames.tail_world[i]);
    m += rig.bone_mass[i];
  }
  return m > 0.0 ? Vec3(c / m) : c;
}

}  // namespace physik
