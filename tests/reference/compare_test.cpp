// PhysIK against MuJoCo (reference/compare.h): a unique equilibrium is reached by both engines;
// with fewer control points the final gap is path dependence; the gap metrics themselves.
#include "reference/compare.h"

#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include <gtest/gtest.h>

#include "physik/io/rig_io.h"
#include "physik/model/errors.h"
#include "physik/model/rig_generators.h"
#include "tests/engine_test_util.h"
#include "tests/test_util.h"

namespace physik {
namespace {

// two free bones of length 1 (no limits); the targets put the joint and the tip at a bent pose
const Vec3 kRootHead(0.0, 0.0, 0.0);
const Vec3 kJoint(0.0, 0.6, 0.8);
const Vec3 kTip(0.8, 0.6, 1.4);

Scene two_bone_scene(bool all_three) {
  Scene s = test::scene_for(make_chain_rig(2, 1.0), preset_params("original"), 600);
  // start bent out of the plane of the targets, so no symmetry picks the final pose
  s.initial_pose.bone_local_rotation[1] =
      Quat(Eigen::AngleAxisd(0.6, Vec3(1, 0, 0.5).normalized()));
  if (all_three) {
    s.control_points.push_back(test::control(0, 0.0, kRootHead, 10.0));
    s.control_points.push_back(test::control(0, 1.0, kJoint, 10.0));
  } else {
    s.control_points.push_back(test::control(0, 0.0, kRootHead, 10.0));
  }
  s.control_points.push_back(test::control(1, 1.0, kTip, 10.0));
  return s;
}

TEST(Compare, TwoBoneChainWithThreeControlPointsSettlesToTheSameEquilibrium) {
  const Scene s = two_bone_scene(true);
  const Comparison c = compare_with_mujoco(s, ReferenceMode::kSameForces);
  ASSERT_TRUE(c.physik.summary.converged);
  ASSERT_TRUE(c.mujoco.summary.converged);
  // the control points fix every endpoint: the case where the final gap tests the heuristic
  EXPECT_EQ(c.free_endpoint_dof, 0);
  const double chain_length = 2.0;
  EXPECT_LT(c.gap.final_pose_gap, 1e-3 * chain_length);
  // and both met the targets (they are consistent with the bone lengths)
  for (double r : c.mujoco.summary.final_residuals) EXPECT_LT(r, 1e-3);
  for (double r : c.physik.summary.final_residuals) EXPECT_LT(r, 1e-3);
  std::cout << "two-bone chain, 3 control points (unique equilibrium): final pose gap "
            << c.gap.final_pose_gap << ", rms gap " << c.gap.rms_gap << ", max gap "
            << c.gap.max_gap << " (rig units; chain length 2)\n";
  RecordProperty("unique_final_pose_gap", std::to_string(c.gap.final_pose_gap));
}

TEST(Compare, FewerControlPointsLeaveAFamilyAndTheGapMeasuresPathDependence) {
  const Scene s = two_bone_scene(false);
  const Comparison c = compare_with_mujoco(s, ReferenceMode::kSameForces);
  ASSERT_TRUE(c.physik.summary.converged);
  ASSERT_TRUE(c.mujoco.summary.converged);
  // root head and tip fixed: the joint may swing on a circle about the head-tip line
  EXPECT_EQ(c.free_endpoint_dof, 1);
  // both meet the targets; where the joint ends up is path dependent
  for (double r : c.mujoco.summary.final_residuals) EXPECT_LT(r, 1e-3);
  for (double r : c.physik.summary.final_residuals) EXPECT_LT(r, 1e-3);
  std::cout << "two-bone chain, 2 control points (family: path dependence): final pose gap "
            << c.gap.final_pose_gap << ", rms gap " << c.gap.rms_gap << "\n";
  RecordProperty("family_final_pose_gap", std::to_string(c.gap.final_pose_gap));
  const nlohmann::json j = comparison_to_json(s, c);
  EXPECT_NE(j["equilibrium"].get<std::string>().find("path dependence"), std::string::npos);
}

TEST(Compare, GapOfARigidlyShiftedTrajectoryIsTheShift) {
  const Rig rig = make_chain_rig(3, 1.0);
  const BoneFrames a = forward_kinematics(rig, rest_pose(rig));
  BoneFrames b = a;
  for (int i = 0; i < rig.nbone; ++i) {
    b.head_world[i] += Vec3(0.3, 0.0, 0.4);
    b.tail_world[i] += Vec3(0.3, 0.0, 0.4);
  }
  EXPECT_NEAR(pose_gap(a, b), 0.5, 1e-15);
  const GapStats g = trajectory_gap({a, a, a}, {a, b, b, b}, a, b);  // the shorter run counts
  EXPECT_EQ(g.steps_compared, 3);
  EXPECT_NEAR(g.max_gap, 0.5, 1e-15);
  EXPECT_NEAR(g.rms_gap, 0.5 * std::sqrt(2.0 / 3.0), 1e-15);
  EXPECT_NEAR(g.final_pose_gap, 0.5, 1e-15);
  EXPECT_NEAR(g.final_pose_rms_gap, 0.5, 1e-15);
}

TEST(Compare, ReferenceSpecs) {
  EXPECT_EQ(parse_reference_spec("mujoco"), ReferenceMode::kSameForces);
  EXPECT_EQ(parse_reference_spec("mujoco:same-forces"), ReferenceMode::kSameForces);
  EXPECT_EQ(parse_reference_spec("mujoco:exact-constraints"), ReferenceMode::kExactConstraints);
  EXPECT_THROW(parse_reference_spec("bullet"), InputError);
  EXPECT_THROW(parse_reference_spec("mujoco:exact"), InputError);
}

TEST(Compare, ComparisonJsonHasTheIssuesFields) {
  Scene s = two_bone_scene(true);
  s.steps = 50;
  const nlohmann::json j =
      comparison_to_json(s, compare_with_mujoco(s, ReferenceMode::kExactConstraints));
  for (const char* key :
       {"rms_gap", "max_gap", "final_pose_gap", "free_endpoint_dof", "equilibrium"}) {
    EXPECT_TRUE(j.contains(key)) << key;
  }
  for (const char* engine : {"physik", "mujoco"}) {
    EXPECT_TRUE(j[engine].contains("steps_to_converge")) << engine;
    EXPECT_TRUE(j[engine].contains("max_limit_violation_deg")) << engine;
  }
  EXPECT_TRUE(j["free_rods"].contains("max_joint_separation"));
  EXPECT_EQ(j["mode"], "exact-constraints");
}

// `simulate --reference` writes MuJoCo's run folder (mujoco/) with the recorder: its trajectory
// table is the same bytes as a recorder on MuJoCo's run, the initial state, a row every N steps
// and the scene's last step
TEST(Compare, ReferenceTableIsTheRecordersTable) {
  Scene s = two_bone_scene(true);
  s.steps = 40;
  const std::string out = ::testing::TempDir() + "/compare_reference_table";
  std::filesystem::remove_all(out);
  write_reference_comparison(s, "mujoco", out, 3, false);
  std::ostringstream csv;
  RecordOptions o;
  o.csv_stream = &csv;
  o.csv_every = 3;
  o.csv_rows = RowRule::kEveryAndLast;
  const RecordedRun run = record_mujoco(s, ReferenceMode::kSameForces, o);
  ASSERT_EQ(run.summary.steps_run, 40);
  std::ifstream in(out + "/mujoco/trajectory.csv");
  std::stringstream written;
  written << in.rdbuf();
  EXPECT_EQ(written.str(), csv.str());
  std::vector<int> steps;
  std::string line;
  std::getline(written, line);  // header
  while (std::getline(written, line)) steps.push_back(std::stoi(line.substr(0, line.find(','))));
  ASSERT_EQ(steps.size(), 15u);  // the initial state, 3, 6, ..., 39, then 40
  EXPECT_EQ(steps.front(), 0);
  EXPECT_EQ(steps[1], 3);
  EXPECT_EQ(steps[13], 39);
  EXPECT_EQ(steps.back(), 40);
}

}  // namespace
}  // namespace physik
