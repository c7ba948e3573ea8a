// The coordinates of joints with locked axes (physik/model/joint_coordinates.h; rig.h "Locked
// axes"): the joint model a rig's locks give, the rotation of a hinge and a universal joint at
// their angles and back, their world axes against finite differences of the rotation, and the
// intrinsic Euler angles of every axis order.
#include <random>

#include <gtest/gtest.h>

#include "physik/model/joint_coordinates.h"
#include "physik/model/kinematics.h"
#include "tests/engine_test_util.h"

namespace physik {
namespace {

Quat axis_angle(int axis, double angle) {
  return Quat(Eigen::AngleAxisd(angle, Vec3::Unit(axis)));
}

// root (free) -> a -> b -> c -> d along +Z, with the given limits on a, b, c
Rig chain_with(const std::array<std::array<AxisLimit, 3>, 3>& limits,
               RootJoint root = RootJoint::kFree, const std::array<AxisLimit, 3>& root_limit = {}) {
  std::vector<BoneSpec> bones;
  const char* names[] = {"root", "a", "b", "c", "d"};
  for (int i = 0; i < 5; ++i) {
    BoneSpec b;
    b.name = names[i];
    b.parent = i == 0 ? "" : names[i - 1];
    b.head_world = Vec3(0, 0, i);
    b.tail_world = Vec3(0, 0, i + 1);
    b.rest_frame_world = rest_frame_from_roll(b.head_world, b.tail_world, 0.3 * i);
    if (i >= 1 && i <= 3) b.limit = limits[i - 1];
    if (i == 0) b.limit = root_limit;
    bones.push_back(b);
  }
  return build_rig(bones, "<chain_with>", "chain_with", root);
}

constexpr AxisLimit kFree{};
AxisLimit locked(double v) {
  return AxisLimit{true, v, v};
}
AxisLimit range(double lo, double hi) {
  return AxisLimit{true, lo, hi};
}

TEST(JointModel, LockedAxesGiveHingesUniversalsAndWelds) {
  // a: hinge about z (x, y locked); b: universal x then y (z locked, at 0.2); c: every axis
  // locked (a weld by locks); d: a ball
  const Rig rig = chain_with({{{locked(0.0), locked(0.0), range(-1, 1)},
                               {range(-1, 2), kFree, locked(0.2)},
                               {locked(0.1), locked(0.0), locked(-0.3)}}});
  EXPECT_EQ(rig.bone_joint_type[0], JointType::kFree);
  EXPECT_EQ(rig.bone_joint_type[1], JointType::kHinge);
  EXPECT_EQ(rig.bone_joint_type[2], JointType::kUniversal);
  EXPECT_EQ(rig.bone_joint_type[3], JointType::kWeld);
  EXPECT_EQ(rig.bone_joint_type[4], JointType::kBall);
  EXPECT_EQ(rig.bone_joint_axes[1][0], 2);
  EXPECT_EQ(rig.bone_joint_axes[2][0], 0);
  EXPECT_EQ(rig.bone_joint_axes[2][1], 1);
  EXPECT_EQ(rig.bone_weld[3], -1);  // not welded by the rig: the paper's scheme keeps its springs
  EXPECT_EQ(rig.nv, 6 + 1 + 2 + 0 + 3);
  EXPECT_EQ(rig.nv_springs, 6 + 3 * 4);
  EXPECT_EQ(rig.bone_dofadr[4], 9);
  EXPECT_EQ(rig.bone_dofadr_springs[4], 15);
  EXPECT_TRUE(rig.has_locked_joints());
  for (int i = 1; i < 5; ++i) EXPECT_EQ(rig.joint_type(i, LockedAxes::kSprings), JointType::kBall);
  // the lock rotation: exp of the locked values
  EXPECT_LT(rig.bone_joint_lock[2].angularDistance(axis_angle(2, 0.2)), 1e-15);
  EXPECT_LT(rig.bone_joint_lock[3].angularDistance(Quat(
                Eigen::AngleAxisd(Vec3(0.1, 0.0, -0.3).norm(), Vec3(0.1, 0.0, -0.3).normalized()))),
            1e-15);
  EXPECT_TRUE(rig.bone_joint_lock[1].isApprox(Quat::Identity(), 0.0));

  // a rig without locks keeps its balls, and refresh_joint_model follows edited limits
  Rig free_rig = chain_with({});
  EXPECT_FALSE(free_rig.has_locked_joints());
  EXPECT_EQ(free_rig.nv, free_rig.nv_springs);
  free_rig.bone_limit[2] = {locked(0.0), kFree, locked(0.0)};
  refresh_joint_model(free_rig);
  EXPECT_EQ(free_rig.bone_joint_type[2], JointType::kHinge);
  EXPECT_EQ(free_rig.nv, 6 + 3 + 1 + 3 + 3);
}

TEST(JointModel, PinnedRootWithLocksIsAHingeToTheWorld) {
  const Rig hinge = chain_with({}, RootJoint::kPinned, {locked(0.0), range(-1, 1), locked(0.0)});
  EXPECT_EQ(hinge.bone_joint_type[0], JointType::kHinge);
  EXPECT_EQ(hinge.bone_joint_axes[0][0], 1);
  EXPECT_EQ(hinge.nv, 1 + 3 * 4);
  EXPECT_EQ(hinge.joint_type(0, LockedAxes::kSprings), JointType::kBall);
  EXPECT_EQ(hinge.nv_springs, 3 + 3 * 4);
  const Rig welded = chain_with({}, RootJoint::kPinned, {locked(0.1), locked(0.0), locked(0.0)});
  EXPECT_EQ(welded.bone_joint_type[0], JointType::kWeld);
  EXPECT_EQ(welded.nv, 3 * 4);
  const Rig fixed = chain_with({}, RootJoint::kFixed);
  EXPECT_EQ(fixed.joint_type(0, LockedAxes::kSprings), JointType::kWeld);
  EXPECT_FALSE(fixed.has_locked_joints());
}

TEST(JointCoordinates, RotationAndAnglesRoundTrip) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int a = 0; a < 3; ++a) {
    for (int b = 0; b < 3; ++b) {
      // a hinge about a (b == a) or a universal a, b (the locked axis the third), locks off zero
      std::array<AxisLimit, 3> l{locked(0.3), locked(-0.2), locked(0.1)};
      l[a] = kFree;
      if (b != a) l[b] = kFree;
      const Rig rig = chain_with({{l, {}, {}}});
      const bool hinge = a == b;
      ASSERT_EQ(rig.bone_joint_type[1], hinge ? JointType::kHinge : JointType::kUniversal);
      const int first = std::min(a, b), second = std::max(a, b);
      for (int k = 0; k < 20; ++k) {
        // a universal's second angle past 90 deg too, where Tait-Bryan's branch is the other
        const Vec2 t(3.0 * u(rng), hinge ? 0.0 : 3.0 * u(rng));
        const Quat q = hinge_rotation(rig, 1, t);
        // q = L exp(t0 e_first) exp(t1 e_second)
        const Quat expected =
            hinge ? rig.bone_joint_lock[1] * axis_angle(first, t[0])
                  : rig.bone_joint_lock[1] * axis_angle(first, t[0]) * axis_angle(second, t[1]);
        EXPECT_LT(q.angularDistance(expected), 1e-14);
        EXPECT_LT((hinge_coordinates(rig, 1, q) - t).norm(), 1e-12)
            << a << b << " " << t.transpose();
      }
    }
  }
}

TEST(JointCoordinates, AHingeIsItsRotationVectorWhereItsLocksAreZero) {
  const Rig rig = chain_with({{{range(-2, 2), locked(0.0), locked(0.0)}, {}, {}}});
  for (double t : {-2.5, -0.4, 0.0, 1e-9, 0.7, 3.0}) {
    const Vec3 theta = rotation_vector(hinge_rotation(rig, 1, Vec2(t, 0)));
    EXPECT_NEAR(theta.x(), t, 1e-15);
    EXPECT_EQ(theta.y(), 0.0);
    EXPECT_EQ(theta.z(), 0.0);
  }
  // off the joint's set, the hinge angle is the twist: the nearest rotation about the axis
  const Quat off = axis_angle(0, 0.5) * axis_angle(1, 0.2);
  const double t = hinge_coordinates(rig, 1, off)[0];
  for (double d : {-1e-4, 1e-4}) {
    EXPECT_LT(off.angularDistance(axis_angle(0, t)), off.angularDistance(axis_angle(0, t + d)));
  }
}

// s0 t0' + s1 t1' is the relative angular velocity: (R(t + e s) R(t)^T) / e -> [w]x
TEST(JointCoordinates, WorldAxesAreTheRatesOfTheAngles) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Rig rig = chain_with({{{kFree, locked(0.25), kFree}, {}, {}}});
  const Quat parent = Quat(Eigen::AngleAxisd(1.1, Vec3(1, 2, 3).normalized()));
  for (int k = 0; k < 10; ++k) {
    const Vec2 t(2.0 * u(rng), 1.2 * u(rng)), rate(u(rng), u(rng));
    const auto world = [&](const Vec2& x) {
      return Quat(parent * rig.bone_rest_orient_parent[1] * hinge_rotation(rig, 1, x));
    };
    Vec3 s0, s1;
    hinge_axes_world(rig, 1, parent, world(t), s0, s1);
    EXPECT_NEAR(s0.norm(), 1.0, 1e-14);
    EXPECT_NEAR(s1.norm(), 1.0, 1e-14);
    EXPECT_NEAR(s0.dot(s1), 0.0, 1e-14);
    const double e = 1e-6;
    const Quat dq = world(t + e * rate) * world(t - e * rate).conjugate();
    const Vec3 w = rotation_vector(dq) / (2.0 * e);
    EXPECT_LT((w - (s0 * rate[0] + s1 * rate[1])).norm(), 1e-8);
  }
}

TEST(JointCoordinates, IntrinsicEulerAnglesOfEveryOrder) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const int orders[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (const auto& o : orders) {
    for (int k = 0; k < 20; ++k) {
      const Vec3 a(3.0 * u(rng), 1.5 * u(rng), 3.0 * u(rng));
      const Mat3 R = (axis_angle(o[0], a[0]) * axis_angle(o[1], a[1]) * axis_angle(o[2], a[2]))
                         .toRotationMatrix();
      EXPECT_LT((intrinsic_euler(R, o[0], o[1], o[2]) - a).norm(), 1e-12)
          << o[0] << o[1] << o[2] << " " << a.transpose();
    }
  }
}

}  // namespace
}  // namespace physik
