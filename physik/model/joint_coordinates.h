// The coordinates of joints with locked axes (rig.h "Locked axes"; docs/engine.md "Hinges and
// two-axis joints"): hinges, universal joints and welds by locks in the exact and implicit
// schemes, as MuJoCo's hinges.
//
// With L = Rig::bone_joint_lock[i] and e_a, e_b the free local axes (Rig::bone_joint_axes[i]),
// bone i's local rotation (rest-relative, in its rest frame) at coordinates t is
//   hinge      q(t) = L exp(t0 e_a)
//   universal  q(t) = L exp(t0 e_a) exp(t1 e_b)     (MuJoCo: two hinges in one body, in order)
//   weld       q    = L                              (every axis locked)
// Its relative angular velocity, world axes, is w_i - w_parent = s0 t0' + s1 t1' with
//   s0 = R_parent R_rest_in_parent L e_a   (fixed in the parent)
//   s1 = R_i e_b                           (fixed in the bone; = R_parent R_rest L exp(t0 e_a) e_b)
// orthonormal (e_b is perpendicular to e_a, which exp(t0 e_a) keeps), so t_k' = s_k . (w_i - w_p)
// and a torque tau on the bone (minus on its parent) is the generalised force s_k . tau.
// A hinge's s0 is also R_i e_a (exp(t0 e_a) keeps e_a). A root's parent frame is the world's.
//
// Projection onto the joint's set (a start pose, a pose from elsewhere), with q' = L^-1 q:
//   hinge      t0 = 2 atan2(q'_a, q'_w) (q' in the w >= 0 hemisphere): the twist of q' about
//              e_a, the hinge rotation nearest q' (it maximises |<q', exp(t e_a)>|)
//   universal  (t0, t1) = the first two intrinsic Euler angles of q' in the axis order a, b, c
//              (c the locked axis): q' = exp(t0 e_a) exp(t1 e_b) exp(t2 e_c), t2 dropped, on
//              the branch nearer the joint's set: Tait-Bryan's (|t1| <= pi / 2) where
//              |t2| <= pi / 2, else the other, (t0 + pi, pi - t1, t2 + pi) wrapped to (-pi, pi]
//              (a joint bent past 90 deg on its second axis reads t2 = pi on Tait-Bryan's)
// Both are exact on the joint's set: q(project(q(t))) = q(t) (|t0| < pi; a universal's
// |t1| < pi, |t1| = pi / 2 being Tait-Bryan's own singularity).
// Units: rad, rad/s.
#pragma once

#include "physik/model/rig.h"

namespace physik {

// q(t) of bone i's joint (a hinge reads t[0]; a weld by locks gives L); the identity for a ball
// or a free root
Quat hinge_rotation(const Rig& rig, int bone, const Vec2& t);

// The coordinates of a local rotation q projected onto bone i's joint (above); zero for a joint
// without them.
Vec2 hinge_coordinates(const Rig& rig, int bone, const Quat& q);

// How far (rad) a local rotation q of bone i lies off its joint's set: the angle from the
// rotation of its projected coordinates, hinge_rotation(hinge_coordinates(q)), to q. 0 on the
// set, and for a ball or a free root (every rotation is on theirs). A rotation vector's locked
// component is no measure of it: on a joint locked away from zero it moves with the free angles.
double off_joint_set(const Rig& rig, int bone, const Quat& q);

// The world axes s0, s1 of bone i's coordinates (s1 zero for a hinge), from its parent's world
// orientation (the identity for the root) and its own.
void hinge_axes_world(const Rig& rig, int bone, const Quat& parent_orient_world,
                      const Quat& orient_world, Vec3& s0, Vec3& s1);

// The intrinsic Euler (Tait-Bryan) angles of R about axes i, j, k (a permutation of 0, 1, 2):
// R = exp(a0 e_i) exp(a1 e_j) exp(a2 e_k), a1 in [-pi/2, pi/2], a0 and a2 in (-pi, pi].
Vec3 intrinsic_euler(const Mat3& R, int i, int j, int k);

// The coordinates of a joint with rotational coordinates: 3 for a ball, 2, 1 and 0 for a
// universal, a hinge and a weld (a free root: 3 rotational of its 6).
inline int rotational_coordinates(JointType type) {
  switch (type) {
    case JointType::kFree:
    case JointType::kBall:
      return 3;
    case JointType::kUniversal:
      return 2;
    case JointType::kHinge:
      return 1;
    case JointType::kWeld:
      return 0;
  }
  return 0;
}

}  // namespace physik
