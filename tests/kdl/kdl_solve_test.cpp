// Orocos KDL as a scene solver (kdl/kdl_solve.h): `--solver kdl` (LMA) and `kdl-nr` (the
// joint-limited Newton-Raphson) on one chain with orientation rows, and what they refuse.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "experiments/common.h"
#include "kdl/kdl_solve.h"
#include "physik/engine/measures.h"
#include "physik/io/rig_io.h"
#include "physik/model/errors.h"
#include "physik/model/joint_angles.h"
#include "physik/model/rig_generators.h"
#include "tests/test_util.h"

namespace physik {
namespace {

Scene pinhead_hand(const Vec3& target) {
  const Rig rig = load_rig(test::model_path("rigs/pinhead.json"));
  Scene s = experiments::effector_scene("kdl_test", rig, rig.find_bone("hand.L"), false);
  s.control_points[0].target_world = target;
  return s;
}

SceneSolveOptions kdl_options(const std::string& solver) {
  SceneSolveOptions o;
  o.solver = solver;
  return o;
}

// a hand target from a legal pose of the arm: both reach it within the tolerance, kdl-nr inside
// the limits (its joints clamped), and the position by the goal's own measure
TEST(KdlSolve, BothReachALegalHandTarget) {
  const Rig rig = load_rig(test::model_path("rigs/pinhead.json"));
  const int hand = rig.find_bone("hand.L");
  std::mt19937 rng(3);
  for (int k = 0; k < 5; ++k) {
    const Vec3 t =
        forward_kinematics(rig, experiments::random_legal_pose(rig, rng)).tail_world[hand];
    for (const char* solver : {"kdl", "kdl-nr"}) {
      const SceneSolveResult r = kdl::solve_scene_kdl(pinhead_hand(t), kdl_options(solver));
      EXPECT_TRUE(r.classic.converged) << solver << " target " << k;
      EXPECT_LT((r.frames.tail_world[hand] - t).norm(), r.classic.tolerance) << solver;
      EXPECT_GT(r.classic.iterations, 0) << solver;
      // the chain's base holds the root's head where the rest puts it
      EXPECT_LT((r.frames.head_world[0] - rig.bone_rest_head_world[0]).norm(), 1e-12);
    }
  }
}

// NR_JL clamps every joint to its axis's limits: pinhead's locked collar and elbow axes stay put
TEST(KdlSolve, TheJointLimitedNewtonKeepsTheLimits) {
  const Rig rig = load_rig(test::model_path("rigs/pinhead.json"));
  const SceneSolveResult r =
      kdl::solve_scene_kdl(pinhead_hand(Vec3(1.5, -0.8, 1.0)), kdl_options("kdl-nr"));
  // hinges and locked axes: Euler angles are the rotation vector's components there
  EXPECT_LT(max_limit_violation(rig, LockedAxes::kSprings, r.pose), 1e-9);
}

// orientation rows: the hand's frame turned onto its target within --tol-angle (rad)
TEST(KdlSolve, OrientationRowsMeetTheAngleTolerance) {
  const Rig rig = load_rig(test::model_path("rigs/pinhead.json"));
  const int hand = rig.find_bone("hand.L");
  Pose p = rest_pose(rig);
  p.bone_local_rotation[hand] = Quat(Eigen::AngleAxisd(0.4, Vec3::UnitX()));
  p.bone_local_rotation[rig.bone_parent[hand]] = Quat(Eigen::AngleAxisd(-0.6, Vec3::UnitX()));
  const BoneFrames f = forward_kinematics(rig, p);
  Scene s = pinhead_hand(f.tail_world[hand]);
  OrientationTarget o;
  o.bone = hand;
  o.target_world = f.orient_world[hand];
  s.orientation_targets = {o};
  for (const char* solver : {"kdl", "kdl-nr"}) {
    SceneSolveOptions opt = kdl_options(solver);
    opt.tol_angle = 1e-5;
    const SceneSolveResult r = kdl::solve_scene_kdl(s, opt);
    EXPECT_TRUE(r.classic.converged) << solver;
    EXPECT_LT(orientation_residual(r.frames, o), 1e-5) << solver;
    ASSERT_EQ(r.classic.orientation_residuals.size(), 1u);
  }
}

// what one chain cannot take: an aim, a pin, goals on two bones, gravity: InputError naming the
// field and the reason
TEST(KdlSolve, RefusesWhatOneChainCannotTake) {
  const auto refused = [](const Scene& s, const std::string& text) {
    try {
      kdl::solve_scene_kdl(s, kdl_options("kdl"));
      ADD_FAILURE() << "no InputError; expected " << text;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
    }
  };
  Scene aim = pinhead_hand(Vec3(0.5, -0.3, 1.2));
  AimTarget a;
  a.bone = aim.rig.find_bone("head");
  a.point_world = Vec3(0, -3, 2);
  aim.aim_targets = {a};
  refused(aim, "aim_targets: --solver kdl and kdl-nr take no aims");
  Scene two = pinhead_hand(Vec3(0.5, -0.3, 1.2));
  ControlPoint other = two.control_points[0];
  other.bone = two.rig.find_bone("hand.R");
  two.control_points.push_back(other);
  refused(two, "their goals must be on one bone");
  Scene heavy = pinhead_hand(Vec3(0.5, -0.3, 1.2));
  heavy.gravity_world = Vec3(0, 0, -9.81);
  refused(heavy, "gravity: --solver kdl and kdl-nr solve the rig's geometry");
  Scene pinned = pinhead_hand(Vec3(0.5, -0.3, 1.2));
  Pin pin;
  pin.bone = pinned.rig.find_bone("hand.R");
  pinned.pins = {pin};
  refused(pinned, "pins: --solver kdl and kdl-nr take no pins");
}

}  // namespace
}  // namespace physik
