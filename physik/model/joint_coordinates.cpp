#include "physik/model/joint_coordinates.h"

#include <cmath>

namespace physik {

namespace {

inline Quat axis_rotation(int axis, double angle) {
  const double s = std::sin(0.5 * angle);
  Quat q(std::cos(0.5 * angle), 0.0, 0.0, 0.0);
  q.vec()[axis] = s;
  return q;
}

}  // namespace

Quat hinge_rotation(const Rig& rig, int i, const Vec2& t) {
  const auto& axes = rig.bone_joint_axes[i];
  switch (rig.bone_joint_type[i]) {
    case JointType::kHinge:
      return rig.bone_joint_lock[i] * axis_rotation(axes[0], t[0]);
    case JointType::kUniversal:
      return rig.bone_joint_lock[i] * axis_rotation(axes[0], t[0]) * axis_rotation(axes[1], t[1]);
    case JointType::kWeld:
      return rig.bone_joint_lock[i];
    case JointType::kFree:
    case JointType::kBall:
      break;
  }
  return Quat::Identity();
}

Vec3 intrinsic_euler(const Mat3& R, int i, int j, int k) {
  // +1 for a cyclic order (x y z, y z x, z x y), -1 otherwise
  const double e = ((j - i + 3) % 3 == 1) ? 1.0 : -1.0;
  const double s = std::max(-1.0, std::min(1.0, e * R(i, k)));
  return Vec3(std::atan2(-e * R(j, k), R(k, k)), std::asin(s), std::atan2(-e * R(i, j), R(i, i)));
}

Vec2 hinge_coordinates(const Rig& rig, int i, const Quat& q) {
  const auto& axes = rig.bone_joint_axes[i];
  Quat r = (rig.bone_joint_lock[i].conjugate() * q).normalized();
  switch (rig.bone_joint_type[i]) {
    case JointType::kHinge: {
      if (r.w() < 0.0) r.coeffs() = -r.coeffs();
      return Vec2(2.0 * std::atan2(r.vec()[axes[0]], r.w()), 0.0);
    }
    case JointType::kUniversal: {
      const int c = 3 - axes[0] - axes[1];
      const Vec3 a = intrinsic_euler(r.toRotationMatrix(), axes[0], axes[1], c);
      // the other branch, (a0 + pi, pi - a1, a2 + pi), where it lies nearer the joint's set
      // (|a2| > pi / 2): a joint bent past 90 deg on its second axis has a2 = pi on Euler's
      if (std::abs(a[2]) <= 0.5 * kPi) return Vec2(a[0], a[1]);
      const auto turn = [](double x) { return x > 0.0 ? x - kPi : x + kPi; };
      return Vec2(turn(a[0]), (a[1] >= 0.0 ? kPi : -kPi) - a[1]);
    }
    case JointType::kFree:
    case JointType::kBall:
    case JointType::kWeld:
      break;
  }
  return Vec2::Zero();
}

void hinge_axes_world(const Rig& rig, int i, const Quat& parent_orient_world,
                      const Quat& orient_world, Vec3& s0, Vec3& s1) {
  const auto& axes = rig.bone_joint_axes[i];
  s0.setZero();
  s1.setZero();
  switch (rig.bone_joint_type[i]) {
    case JointType::kHinge:
      s0 = orient_world * Vec3::Unit(axes[0]);  // exp(t e_a) keeps e_a
      return;
    case JointType::kUniversal:
      s0 = parent_orient_world *
           (rig.bone_rest_orient_parent[i] * (rig.bone_joint_lock[i] * Vec3::Unit(axes[0])));
      s1 = orient_world * Vec3::Unit(axes[1]);
      return;
    case JointType::kFree:
    case JointType::kBall:
    case JointType::kWeld:
      return;
  }
}

double off_joint_set(const Rig& rig, int i, const Quat& q) {
  const JointType t = rig.bone_joint_type[i];
  if (t == JointType::kBall || t == JointType::kFree || rig.welded(i)) return 0.0;
  if (i == 0 && rig.root_joint == RootJoint::kFixed) return 0.0;
  const Quat on = hinge_rotation(rig, i, hinge_coordinates(rig, i, q));
  const Quat d = (on.conjugate() * q).normalized();
  return 2.0 * std::atan2(d.vec().norm(), std::abs(d.w()));
}

}  // namespace physik
