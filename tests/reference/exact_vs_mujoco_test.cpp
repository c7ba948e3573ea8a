// The exact joint solve (scheme exact: the articulated-body algorithm and MuJoCo's Euler in
// joint space, physik/engine/integrate_joint_space.h) against MuJoCo's same-forces run (the
// rig's joints, hinges where it locks axes, PhysIK's forces, reference/mujoco_runner.h): on every
// scene in models/scenes where both are stable (pinhead's elbows and knees are hinges, its torso
// a universal joint, its hips and collarbones welds by locks), the largest head/tail gap over all
// bones and 400 steps is at most 1e-9 rig units.
// A scene where either run diverges is named and skipped (its explicit Euler is unstable in both).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>

#include <gtest/gtest.h>

#include "physik/io/scene_io.h"
#include "physik/model/rig_generators.h"
#include "reference/mujoco_runner.h"
#include "tests/engine_test_util.h"
#include "tests/test_util.h"

namespace physik {
namespace {

constexpr int kSteps = 400;

struct Gap {
  double max_gap = 0.0;  // rig units, largest head/tail distance over bones and steps
  double travel = 0.0;   // rig units, largest distance a tail moved from its start
  bool stable = true;    // both runs finite and below the scene's divergence energy
};

bool sane(const Scene& scene, const StepStats& st) {
  return std::isfinite(st.kinetic_energy) && st.kinetic_energy < scene.divergence_energy();
}

Gap exact_vs_mujoco(Scene scene) {
  scene.params.scheme = Scheme::kExact;
  SimState p;
  init_state(scene, p);
  const std::vector<Vec3> tail0 = p.frames.tail_world;
  MujocoReference ref(scene, ReferenceMode::kSameForces);
  Gap g;
  for (int k = 0; k < kSteps; ++k) {
    const StepStats a = step(scene, p);
    const StepStats b = ref.step();
    if (!sane(scene, a) || !sane(scene, b) || ref.bad_acceleration()) {
      g.stable = false;
      return g;
    }
    const BoneFrames& m = ref.state().frames;
    for (int i = 0; i < scene.rig.nbone; ++i) {
      g.max_gap = std::max({g.max_gap, (p.frames.head_world[i] - m.head_world[i]).norm(),
                            (p.frames.tail_world[i] - m.tail_world[i]).norm()});
      g.travel = std::max(g.travel, (p.frames.tail_world[i] - tail0[i]).norm());
    }
  }
  return g;
}

TEST(ExactVsMujoco, EveryStablePaperSceneAgreesTo1e9) {
  std::vector<std::string> files;
  for (const auto& e : std::filesystem::directory_iterator(test::model_path("scenes"))) {
    if (e.path().extension() == ".json") files.push_back(e.path().string());
  }
  std::sort(files.begin(), files.end());
  ASSERT_GE(files.size(), 10u);
  int stable = 0;
  for (const std::string& f : files) {
    SCOPED_TRACE(f);
    const Gap g = exact_vs_mujoco(load_scene(f));
    const std::string name = std::filesystem::path(f).stem().string();
    std::cout << "[exact vs MuJoCo] " << name << ": " << (g.stable ? "" : "diverged; before that ")
              << "max gap " << g.max_gap << " rig units, travel " << g.travel << "\n";
    RecordProperty(name, g.stable ? std::to_string(g.max_gap) : "diverged");
    if (!g.stable) continue;
    ++stable;
    EXPECT_LE(g.max_gap, 1e-9) << name;
    EXPECT_GT(g.travel, 0.1) << name << ": the scene must really move";
  }
  EXPECT_GE(stable, 8);  // most paper scenes are stable in both
}

TEST(ExactVsMujoco, ChainWithGyroscopicTermOffAgrees) {
  // a 40-bone chain, two targets, the gyroscopic term cancelled in both
  Scene s = test::scene_for(make_chain_rig(40), preset_params("original"), kSteps);
  s.params.gyroscopic = false;
  s.control_points.push_back(test::control(39, 1.0, Vec3(4.0, 1.0, 38.0), 10.0));
  s.control_points.push_back(
      test::control(20, 0.5, Vec3(-3.0, 0.0, 18.0), 10.0, SpringLaw::kCapped));
  const Gap g = exact_vs_mujoco(s);
  ASSERT_TRUE(g.stable);
  std::cout << "[exact vs MuJoCo] chain40 gyroscopic off: max gap " << g.max_gap << "\n";
  EXPECT_LE(g.max_gap, 1e-9);
  EXPECT_GT(g.travel, 0.5);
}

TEST(ExactVsMujoco, BalancedTreeAgrees) {
  // 31 bones, binary: three bones meet at every inner joint; three bones pulled
  Scene s = test::scene_for(make_tree_rig(31, 2), preset_params("original"), kSteps);
  s.control_points.push_back(test::control(30, 1.0, Vec3(3.0, 1.0, 2.0), 10.0));
  s.control_points.push_back(
      test::control(15, 1.0, Vec3(-3.0, 2.0, 1.0), 10.0, SpringLaw::kCapped));
  s.control_points.push_back(test::control(22, 0.5, Vec3(0.0, -3.0, 4.0), 10.0));
  const Gap g = exact_vs_mujoco(s);
  ASSERT_TRUE(g.stable);
  std::cout << "[exact vs MuJoCo] tree31: max gap " << g.max_gap << "\n";
  EXPECT_LE(g.max_gap, 1e-9);
  EXPECT_GT(g.travel, 0.5);
}

// welded groups are one MuJoCo body with several geoms (mjcf_export.h); an anchored root is a
// ball (pinned) or no joint (fixed) to the world
TEST(ExactVsMujoco, WeldedAndAnchoredRigsAgree) {
  for (const RootJoint root : {RootJoint::kFree, RootJoint::kPinned, RootJoint::kFixed}) {
    const Rig rig = test::welded_figure(root);
    Scene s = test::scene_for(rig, preset_params("original"), kSteps);
    s.control_points.push_back(
        test::control(rig.find_bone("arm.L"), 1.0, Vec3(0.3, -0.4, 1.9), 10.0, SpringLaw::kCapped));
    s.control_points.push_back(test::control(rig.find_bone("shin.L"), 1.0, Vec3(0.3, -0.3, 0.3),
                                             10.0, SpringLaw::kCapped));
    s.control_points.push_back(
        test::control(rig.find_bone("shin.R"), 0.5, Vec3(-0.2, 0.3, 0.2), 10.0));
    for (const bool gyroscopic : {true, false}) {
      s.params.gyroscopic = gyroscopic;
      const Gap g = exact_vs_mujoco(s);
      ASSERT_TRUE(g.stable) << to_string(root);
      std::cout << "[exact vs MuJoCo] welded figure, root " << to_string(root)
                << (gyroscopic ? "" : ", gyroscopic off") << ": max gap " << g.max_gap << "\n";
      EXPECT_LE(g.max_gap, 1e-9) << to_string(root);
      EXPECT_GT(g.travel, 0.1) << to_string(root);
    }
  }
}

// rig.h "Locked axes": hinges (elbows, knees), universal joints (wrists, ankles; one with its
// lock away from zero), welds by locks (collarbones, hips) and a pinned root that is a hinge to
// the world, with engaged limits on free axes (the torsion springs on the angles): MuJoCo's
// same-forces model writes them as hinges (mjcf_export.h kHingeJoints), and the exact step equals
// its run; also with the gyroscopic term off and the paper's torque
TEST(ExactVsMujoco, HingedFigureAgrees) {
  for (const RootJoint root : {RootJoint::kFree, RootJoint::kPinned}) {
    Rig rig = test::hinged_figure(root);
    for (int i = 0; i < rig.nbone; ++i) {  // stout rods: explicit Euler's torsion bound holds
      rig.bone_radius[i] = 0.3;
      rig.bone_inertia_local[i] = cylinder_inertia(rig.bone_mass[i], 0.3, rig.bone_length[i]);
    }
    Scene s = test::scene_for(rig, preset_params("original"), kSteps);
    using test::control;
    s.control_points = {
        control(rig.find_bone("hand.L"), 1.0, Vec3(-0.3, -0.5, 1.9), 10.0, SpringLaw::kCapped),
        control(rig.find_bone("hand.R"), 1.0, Vec3(0.4, 0.6, 0.8), 10.0),
        control(rig.find_bone("foot.L"), 1.0, Vec3(-0.4, 0.5, 0.4), 10.0),
        control(rig.find_bone("foot.R"), 1.0, Vec3(0.5, -0.6, 0.2), 10.0, SpringLaw::kCapped)};
    // the start bends the knees and elbows past their limits, off their joints' sets (init_state
    // puts them on), so the torsion springs on the angles engage from the first step
    s.initial_pose.bone_local_rotation[rig.find_bone("shin.L")] =
        Quat(Eigen::AngleAxisd(0.3, Vec3(1, 0.2, 0).normalized()));
    s.initial_pose.bone_local_rotation[rig.find_bone("forearm.R")] =
        Quat(Eigen::AngleAxisd(-0.5, Vec3::UnitX()));
    for (const bool gyroscopic : {true, false}) {
      s.params.gyroscopic = gyroscopic;
      const Gap g = exact_vs_mujoco(s);
      ASSERT_TRUE(g.stable) << to_string(root);
      std::cout << "[exact vs MuJoCo] hinged figure, root " << to_string(root)
                << (gyroscopic ? "" : ", gyroscopic off") << ": max gap " << g.max_gap << "\n";
      EXPECT_LE(g.max_gap, 1e-9) << to_string(root);
      EXPECT_GT(g.travel, 0.1) << to_string(root);
    }
  }
}

// the bone targets, on a welded figure with a control spring: orientation targets
// (orientation_springs.h) linear and capped, an aim and a pin; MuJoCo's reference applies the same
// couples and forces through the force list
TEST(ExactVsMujoco, BoneTargetsAgree) {
  const Rig rig = test::welded_figure();
  Scene s = test::scene_for(rig, preset_params("original"), kSteps);
  s.control_points.push_back(
      test::control(rig.find_bone("arm.L"), 1.0, Vec3(0.3, -0.4, 1.9), 10.0, SpringLaw::kCapped));
  const auto add = [&](const char* bone, const Vec3& turn, SpringLaw law) {
    OrientationTarget t;
    t.bone = rig.find_bone(bone);
    t.target_world = Quat(Eigen::AngleAxisd(turn.norm(), turn.normalized())) *
                     rig.bone_rest_orient_world[t.bone];
    t.k = 4.0;
    t.spring = law;
    t.cap = 0.2;
    s.orientation_targets.push_back(t);
  };
  add("shin.R", Vec3(0.8, 0.3, 0.0), SpringLaw::kLinear);
  add("pelvis", Vec3(0.0, 0.4, 0.2), SpringLaw::kCapped);
  add("hip.L", Vec3(-0.3, 0.0, 0.5), SpringLaw::kLinear);  // a welded bone: its group turns
  // an aim (aim_springs.h: a couple and a force at the head) and a pin (pins.h)
  AimTarget aim;
  aim.bone = rig.find_bone("chest");
  aim.point_world = Vec3(0.8, -0.6, 1.9);
  aim.k = 3.0;
  aim.spring = SpringLaw::kCapped;
  aim.cap = 0.4;
  s.aim_targets.push_back(aim);
  Pin pin;
  pin.bone = rig.find_bone("shin.L");
  pin.alpha = 1.0;
  pin.point_world = rig.bone_rest_tail_world[pin.bone] + Vec3(0.05, 0.0, 0.0);
  pin.k = 200.0;
  s.pins.push_back(pin);
  const Gap g = exact_vs_mujoco(s);
  ASSERT_TRUE(g.stable);
  std::cout << "[exact vs MuJoCo] welded figure with orientation, aim and pin targets: max gap "
            << g.max_gap << "\n";
  EXPECT_LE(g.max_gap, 1e-9);
  EXPECT_GT(g.travel, 0.1);
}

}  // namespace
}  // namespace physik
