// Welded bones and anchored roots (rig.h "Welds", the root's joint) in every scheme: a welded
// group stays one rigid body through a run in every scheme (its relative turn at round-off: the
// recursion's zero-coordinate joint, the paper's scheme's composite bodies), a rig at rest stays
// at rest, a pinned root's head and a fixed root stay where they are, and the linear modes of
// damping auto agree with the dense reference on such rigs.
#include <algorithm>
#include <cmath>
#include <iostream>
#include <random>

#include <gtest/gtest.h>

#include "experiments/weld_turn.h"
#include "physik/engine/engine.h"
#include "physik/engine/integrate_joint_space.h"
#include "physik/engine/joint_space_state.h"
#include "physik/engine/linear_modes.h"
#include "physik/engine/linear_modes_dense.h"
#include "physik/engine/torsion_springs.h"
#include "tests/engine_test_util.h"

namespace physik {
namespace {

const Scheme kSchemes[] = {Scheme::kGaussSeidel, Scheme::kExact, Scheme::kImplicit};

using experiments::max_weld_turn;

// a figure pulled by its hands and feet, stable in every scheme (the original's damping)
Scene pulled_figure(RootJoint root, Scheme scheme, int steps = 200) {
  const Rig rig = test::welded_figure(root);
  EngineParams p = preset_params("original");
  p.scheme = scheme;
  Scene s = test::scene_for(rig, p, steps);
  s.control_points.push_back(
      test::control(rig.find_bone("arm.L"), 1.0, Vec3(0.3, -0.4, 1.9), 10.0, SpringLaw::kCapped));
  s.control_points.push_back(
      test::control(rig.find_bone("shin.L"), 1.0, Vec3(0.3, -0.3, 0.3), 10.0, SpringLaw::kCapped));
  s.control_points.push_back(
      test::control(rig.find_bone("shin.R"), 1.0, Vec3(-0.2, 0.3, 0.2), 10.0, SpringLaw::kCapped));
  return s;
}

TEST(Welds, TheRigKnowsItsBodiesAndCoordinates) {
  const Rig rig = test::welded_figure();
  ASSERT_EQ(rig.nbone, 10);
  const int spine = rig.find_bone("spine");
  for (const char* name : {"hip.L", "hip.R", "chest"}) {
    const int b = rig.find_bone(name);
    EXPECT_EQ(rig.bone_body[b], spine) << name;
    EXPECT_EQ(rig.bone_joint_type[b], JointType::kWeld) << name;
    EXPECT_EQ(rig.bone_dof(b), 0) << name;
  }
  EXPECT_EQ(rig.bone_weld[rig.find_bone("chest")], spine);
  EXPECT_EQ(rig.bone_joint_parent[rig.find_bone("hip.L")], spine);
  EXPECT_EQ(rig.bone_parent[rig.find_bone("hip.L")], rig.find_bone("pelvis"));
  EXPECT_EQ(rig.nv, 6 + 3 * 6);  // the free root and six balls
  // pinned, the root is a hinge to the world (two locked axes: rig.h "Locked axes"); the paper's
  // scheme keeps it a ball held by its torsion springs
  EXPECT_EQ(test::welded_figure(RootJoint::kPinned).nv, 1 + 3 * 6);
  EXPECT_EQ(test::welded_figure(RootJoint::kPinned).nv_springs, 3 + 3 * 6);
  EXPECT_EQ(test::welded_figure(RootJoint::kFixed).nv, 3 * 6);
  // bones of one body never collide; a thigh and the other hip do
  EXPECT_TRUE(rig.bones_share_joint(rig.find_bone("hip.L"), rig.find_bone("chest")));
  EXPECT_FALSE(rig.bones_share_joint(rig.find_bone("thigh.L"), rig.find_bone("hip.R")));
}

TEST(Welds, ForwardKinematicsKeepsAWeldedBoneAtItsRestFrameInItsWelds) {
  const Rig rig = test::welded_figure();
  Pose pose = rest_pose(rig);
  // turn the spine and, to no effect, the bones welded to it
  pose.bone_local_rotation[rig.find_bone("spine")] = Quat(Eigen::AngleAxisd(0.4, Vec3::UnitX()));
  pose.bone_local_rotation[rig.find_bone("hip.L")] = Quat(Eigen::AngleAxisd(1.0, Vec3::UnitZ()));
  pose.bone_local_rotation[rig.find_bone("chest")] = Quat(Eigen::AngleAxisd(-0.7, Vec3::UnitY()));
  const BoneFrames f = forward_kinematics(rig, pose);
  EXPECT_LE(max_weld_turn(rig, f), 1e-15);
  // the hip turned with the spine: its tail moved by the spine's turn about the joint
  const int hip = rig.find_bone("hip.L");
  const Vec3 expected = Vec3(0, 0, 1.0) + Eigen::AngleAxisd(0.4, Vec3::UnitX()).toRotationMatrix() *
                                              (rig.bone_rest_tail_world[hip] - Vec3(0, 0, 1.0));
  EXPECT_LE((f.tail_world[hip] - expected).norm(), 1e-12);
}

// Every scheme moves a welded group as one body (the recursion's composite inertia; the paper's
// scheme's composite Newton-Euler and joint solve over bodies): the turn inside a group is
// round-off
TEST(Welds, AWeldedGroupStaysRigidThroughARunInEveryScheme) {
  for (const RootJoint root : {RootJoint::kFree, RootJoint::kPinned}) {
    for (const Scheme scheme : kSchemes) {
      const Scene s = pulled_figure(root, scheme);
      SimState st;
      init_state(s, st);
      const Vec3 tail0 = st.frames.tail_world[s.rig.find_bone("arm.L")];
      double turn = 0.0, ke = 0.0;
      for (int k = 0; k < s.steps; ++k) {
        const StepStats stats = step(s, st);
        ASSERT_TRUE(std::isfinite(stats.kinetic_energy));
        turn = std::max(turn, max_weld_turn(s.rig, st.frames));
        ke = std::max(ke, stats.kinetic_energy);
      }
      const double moved = (st.frames.tail_world[s.rig.find_bone("arm.L")] - tail0).norm();
      std::cout << "[welds] root " << to_string(root) << ", " << to_string(scheme)
                << ": largest turn inside a welded group " << turn << " rad, hand moved " << moved
                << ", peak KE " << ke << " J\n";
      EXPECT_GT(moved, 0.1) << "the run must really move";
      EXPECT_LE(turn, 1e-9) << to_string(scheme);
    }
  }
}

TEST(Welds, ARigAtRestStaysAtRestInEveryScheme) {
  for (const RootJoint root : {RootJoint::kFree, RootJoint::kPinned, RootJoint::kFixed}) {
    for (const Scheme scheme : kSchemes) {
      Scene s = pulled_figure(root, scheme, 100);
      s.control_points.clear();
      SimState st;
      init_state(s, st);
      const BoneFrames f0 = st.frames;
      for (int k = 0; k < s.steps; ++k) step(s, st);
      double moved = 0.0;
      for (int i = 0; i < s.rig.nbone; ++i) {
        moved = std::max(moved, (st.frames.tail_world[i] - f0.tail_world[i]).norm());
      }
      EXPECT_EQ(kinetic_energy(s.rig, st), 0.0) << to_string(root) << " " << to_string(scheme);
      EXPECT_LE(moved, 1e-12) << to_string(root) << " " << to_string(scheme);
    }
  }
}

// An L of two bones welded together, free, with no force on it (no damper, no spring), spinning
// about an axis through its centre of mass that is not a principal one (so it also precesses):
// its centre of mass must not move, whatever the angular-velocity factor does to its turn. The
// paper's scheme moves a free root's body by F / m at its centre of mass and turns it about it,
// as it does a root rod (integrate.h). It used to move the root bone's own centre by the body's
// acceleration there, a_c + alpha x r: that leaves out the factor's share of the turn, (f - 1) w,
// and the centripetal term, and pushed the body by (1 - f) w x r every step (with f = 1 by the
// centripetal term alone). The free-rods form moved every body about its centre already.
TEST(Welds, AFreeWeldedBodySpinningWithNoForceKeepsItsCentreOfMass) {
  std::vector<BoneSpec> bones(2);
  bones[0].name = "upright";
  bones[0].tail_world = Vec3(0, 0, 1);
  bones[1].name = "arm";
  bones[1].parent = "upright";
  bones[1].weld = "upright";
  bones[1].head_world = Vec3(0, 0, 1);
  bones[1].tail_world = Vec3(1, 0, 1);
  for (BoneSpec& b : bones) {
    b.rest_frame_world = rest_frame_from_roll(b.head_world, b.tail_world, 0.0);
    b.mass = 1.0;
    b.radius = 0.2;
  }
  const Rig rig = build_rig(bones, "welded_l", "welded_l");
  const auto centre = [&](const SimState& st) {
    return Vec3((st.com_world[0] + st.com_world[1]) / 2.0);  // equal masses
  };
  for (const double f : {0.5, 1.0}) {
    for (const int form : {0, 1, 2}) {  // articulated, with the factor in the solve, free rods
      EngineParams p = test::bare_params(0.01);
      p.angular_velocity_factor = f;
      p.factor_in_joint_solve = form == 1;
      p.free_rods = form == 2;
      const Scene s = test::scene_for(rig, p, 300);
      SimState st;
      init_state(s, st);
      const Vec3 c0 = centre(st), w(0.4, -0.3, 3.0);  // rad/s
      for (int i = 0; i < rig.nbone; ++i) {
        st.omega_world[i] = w;
        st.vel_world[i] = w.cross(Vec3(st.com_world[i] - c0));
      }
      const Quat q0 = st.frames.orient_world[0];
      double drift = 0.0;
      for (int k = 0; k < s.steps; ++k) {
        step(s, st);
        drift = std::max(drift, (centre(st) - c0).norm());
      }
      SCOPED_TRACE("f " + std::to_string(f) + ", form " + std::to_string(form));
      EXPECT_GT(st.frames.orient_world[0].angularDistance(q0), 0.01);  // it did turn
      EXPECT_LE(max_weld_turn(rig, st.frames), 1e-12);
      EXPECT_LE(drift, 1e-12) << "the centre of mass moved";
    }
  }
}

// The paper's joint solve over composite bodies is the exact dynamics up to its eps: from states
// along a run of the pulled figure, one step of the paper's scheme with the factor left out
// (f = 1), a tight eps and the centripetal term changes every bone's angular velocity and the
// rig's momentum as the exact scheme's step does. What is left is the exact step's world view,
// rebuilt from the joint state with the step's new orientations: of the order |w| dt of the change.
TEST(Welds, ThePapersJointSolveOverCompositeBodiesIsTheExactStep) {
  for (const RootJoint root : {RootJoint::kFree, RootJoint::kPinned}) {
    // one joint model for both: the pinned root's locked axes held by springs, as the paper's
    // scheme holds them (the exact scheme would make it a hinge)
    Scene run = pulled_figure(root, Scheme::kGaussSeidel, 60);
    run.rig = test::with_spring_locks(run.rig);
    Scene gs = run;
    gs.params.angular_velocity_factor = 1.0;
    gs.params.joint_eps = 1e-10;
    gs.params.centripetal = true;
    Scene exact = gs;
    exact.params.scheme = Scheme::kExact;
    const Rig& rig = run.rig;
    SimState s;
    init_state(run, s);
    for (int k = 1; k <= run.steps; ++k) {
      step(run, s);
      if (k % 20 != 0) continue;
      SimState a = s, b = s;
      step(gs, a);
      size_joint_space(rig, b.joint_space);
      init_joint_space(rig, b);
      step(exact, b);
      double dw = 0.0, w = 0.0, p = 0.0, dp = 0.0;
      Vec3 pa = Vec3::Zero(), pb = Vec3::Zero();
      for (int i = 0; i < rig.nbone; ++i) {
        dw = std::max(dw, (a.omega_world[i] - b.omega_world[i]).norm());
        w = std::max(w, (b.omega_world[i] - s.omega_world[i]).norm());
        pa += rig.bone_mass[i] * (a.vel_world[i] - s.vel_world[i]);
        pb += rig.bone_mass[i] * (b.vel_world[i] - s.vel_world[i]);
      }
      dp = (pa - pb).norm();
      p = pb.norm();
      std::cout << "[welds] " << to_string(root) << " root, step " << k
                << ": paper's step against the exact step, angular velocity " << dw << " of " << w
                << " rad/s, momentum " << dp << " of " << p << " kg m/s\n";
      SCOPED_TRACE(std::string(to_string(root)) + " step " + std::to_string(k));
      ASSERT_GT(w, 0.0);
      EXPECT_LE(dw, 1e-2 * w);
      EXPECT_LE(dp, 1e-2 * p);
    }
  }
}

TEST(Welds, AnAnchoredRootStaysWhereItIsUnderAPull) {
  for (const RootJoint root : {RootJoint::kPinned, RootJoint::kFixed}) {
    for (const Scheme scheme : kSchemes) {
      const Scene s = pulled_figure(root, scheme);
      SimState st;
      init_state(s, st);
      const Quat q0 = st.frames.orient_world[0];
      double drift = 0.0, turn = 0.0;
      for (int k = 0; k < s.steps; ++k) {
        step(s, st);
        drift = std::max(drift, (st.frames.head_world[0] - s.rig.bone_rest_head_world[0]).norm());
        turn = std::max(turn, st.frames.orient_world[0].angularDistance(q0));
      }
      SCOPED_TRACE(std::string(to_string(root)) + " " + to_string(scheme));
      EXPECT_EQ(drift, 0.0);
      if (root == RootJoint::kFixed) {
        EXPECT_EQ(turn, 0.0);
      } else {
        EXPECT_GT(turn, 1e-3);  // a pinned root turns about its head
      }
    }
  }
}

// the hinge of a pinned root: its two locked axes' torsion springs hold it against the world
TEST(Welds, APinnedRootsLockedAxesHoldItsHinge) {
  // (the explicit schemes' torsion bound k dt^2 / I < 2 does not hold for this stiff hinge)
  for (const Scheme scheme : {Scheme::kImplicit}) {
    Scene s = pulled_figure(RootJoint::kPinned, scheme, 400);
    s.params.torsion_k = 200.0;
    SimState st;
    init_state(s, st);
    double off_hinge = 0.0, about_hinge = 0.0;
    for (int k = 0; k < s.steps; ++k) {
      step(s, st);
      const Vec3 theta = rotation_vector(st.pose.bone_local_rotation[0]);
      off_hinge = std::max({off_hinge, std::abs(theta.y()), std::abs(theta.z())});
      about_hinge = std::max(about_hinge, std::abs(theta.x()));
    }
    std::cout << "[welds] pinned root hinge, " << to_string(scheme) << ": about the hinge "
              << about_hinge << " rad, off it " << off_hinge << " rad\n";
    EXPECT_GT(about_hinge, 3.0 * off_hinge) << to_string(scheme);
  }
}

TEST(Welds, LinearModesAgreeWithTheDenseReferenceOnWeldedAndAnchoredRigs) {
  std::mt19937 rng(46);
  std::uniform_real_distribution<double> u(-0.6, 0.6);
  for (const RootJoint root : {RootJoint::kFree, RootJoint::kPinned, RootJoint::kFixed}) {
    for (int trial = 0; trial < 4; ++trial) {
      Scene s = pulled_figure(root, Scheme::kImplicit);
      s.params.torsion_k = 5.0;
      for (int i = root == RootJoint::kFixed ? 1 : 0; i < s.rig.nbone; ++i) {
        s.initial_pose.bone_local_rotation[i] =
            Quat(Eigen::AngleAxisd(1.0, Vec3(u(rng), u(rng), u(rng)).normalized()))
                .slerp(0.5 + u(rng), Quat::Identity());
      }
      SimState st;
      init_state(s, st);
      std::vector<Vec3> targets;
      for (const ControlPoint& cp : s.control_points) targets.push_back(cp.target_world);
      const DenseLinearModes ref = linear_modes_dense(s, st, targets);
      const LinearModes it = linear_modes(s, st, targets);
      SCOPED_TRACE(std::string(to_string(root)) + " trial " + std::to_string(trial));
      ASSERT_EQ(it.found, ref.modes.found);
      ASSERT_TRUE(ref.modes.found);
      EXPECT_NEAR(it.slowest_omega, ref.modes.slowest_omega, 1e-6 * ref.modes.slowest_omega);
      EXPECT_NEAR(it.critical_damping, ref.modes.critical_damping,
                  1e-6 * ref.modes.critical_damping);
      EXPECT_EQ(static_cast<int>(ref.omega.size()), s.rig.nv);
    }
  }
}

}  // namespace
}  // namespace physik
