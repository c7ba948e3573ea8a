// Run folders (physik/io/run_folder.h), their targets-and-limits table
// (physik/io/targets_limits.h) and their contacts table (physik/io/contacts_table.h): a pose
// past a known limit gives its excess, the tables keep the same rows, the table's largest excess
// is the run's limit violation, an interpolated target's path is the interpolation's (a straight
// segment for linear); a rod resting on the floor records its two end contacts at the analytic
// depth and force, a dropped rod none before it can reach the floor, a run without contacts no
// table; the params recorded are every one the run reads; a rerun, and a run of the folder's
// scene.json, is the same run bit for bit; clearing an earlier run removes its files and keeps
// the user's.
#include "physik/io/run_folder.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "physik/engine/engine.h"
#include "physik/io/contacts_table.h"
#include "physik/io/scene_io.h"
#include "tests/contact_test_util.h"
#include "tests/test_util.h"

namespace physik {
namespace {

constexpr double kDegToRad = 3.14159265358979323846 / 180.0;

struct Table {
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;

  int column(const std::string& name) const {
    for (std::size_t k = 0; k < columns.size(); ++k) {
      if (columns[k] == name) return static_cast<int>(k);
    }
    ADD_FAILURE() << "no column " << name;
    return 0;
  }
};

// a table whose names hold no comma (these tests' rigs)
Table read_table(const std::string& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in) << path;
  Table t;
  std::string line, cell;
  std::getline(in, line);
  std::stringstream header(line);
  while (std::getline(header, cell, ',')) t.columns.push_back(cell);
  while (std::getline(in, line)) {
    std::stringstream row(line);
    t.rows.emplace_back();
    while (std::getline(row, cell, ',')) t.rows.back().push_back(std::stod(cell));
  }
  return t;
}

std::string fresh_dir(const std::string& name) {
  const std::string dir = ::testing::TempDir() + "/run_folder_" + name;
  std::filesystem::remove_all(dir);
  return dir;
}

// the elbow (forearm x limited to [-90, 0] deg) bent 120 deg: 30 deg below the limit's min
TEST(RunFolder, PoseFolderGivesTheExcessPastAKnownLimit) {
  const Scene scene = load_scene(test::model_path("scenes/fig6_elbow_linear.json"));
  Pose pose = rest_pose(scene.rig);
  const int forearm = scene.rig.find_bone("forearm");
  pose.bone_local_rotation[forearm] = Quat(Eigen::AngleAxisd(-120 * kDegToRad, Vec3::UnitX()));
  const BoneFrames frames = forward_kinematics(scene.rig, pose);
  const std::string dir = fresh_dir("pose");
  write_pose_folder(scene, dir, frames, {{"solver", "test"}});

  const Table limits = read_table(dir + "/targets_and_limits.csv");
  ASSERT_EQ(limits.rows.size(), 1u);
  const std::vector<double>& row = limits.rows[0];
  EXPECT_EQ(row[0], 0);  // step 0
  EXPECT_NEAR(row[limits.column("forearm.limit_excess_x")], -30 * kDegToRad, 1e-7);
  EXPECT_NEAR(row[limits.column("forearm.limit_excess_y")], 0.0, 1e-12);
  EXPECT_NEAR(row[limits.column("forearm.limit_excess_z")], 0.0, 1e-12);
  EXPECT_EQ(row[limits.column("upper_arm.limit_excess_x")], 0.0);  // the root is never limited
  const Vec3& wrist = scene.control_points[2].target_world;
  EXPECT_NEAR(row[limits.column("wrist.target_y")], wrist.y(), 1e-9);
  EXPECT_NEAR(row[limits.column("wrist.target_z")], wrist.z(), 1e-9);

  // the trajectory's one row: at rest, the wrist's residual its distance to the target
  const Table traj = read_table(dir + "/trajectory.csv");
  ASSERT_EQ(traj.rows.size(), 1u);
  EXPECT_EQ(traj.rows[0][traj.column("kinetic_energy")], 0.0);
  EXPECT_NEAR(traj.rows[0][traj.column("residual_wrist")],
              (frames.tail_world[forearm] - wrist).norm(), 1e-7);
  std::ifstream summary(dir + "/summary.json");
  std::stringstream text;
  text << summary.rdbuf();
  EXPECT_NE(text.str().find("\"kind\": \"pose\""), std::string::npos);
  EXPECT_TRUE(std::filesystem::exists(dir + "/scene.json"));
  EXPECT_TRUE(std::filesystem::exists(dir + "/final_pose.csv"));
}

// both tables have the same steps; with a row every step, the table's largest |excess| is the
// run monitor's limit violation (two code paths over the same poses)
TEST(RunFolder, TablesShareRowsAndTheExcessIsTheRunsViolation) {
  Scene scene = load_scene(test::model_path("scenes/fig6_elbow_linear.json"));
  scene.steps = 120;
  const std::string dir = fresh_dir("elbow");
  const RunSummary sum = simulate_into_folder(scene, dir, 1);
  const Table traj = read_table(dir + "/trajectory.csv");
  const Table limits = read_table(dir + "/targets_and_limits.csv");
  ASSERT_EQ(traj.rows.size(), limits.rows.size());
  ASSERT_EQ(traj.rows.size(), 121u);
  double largest = 0.0;
  for (std::size_t r = 0; r < traj.rows.size(); ++r) {
    EXPECT_EQ(traj.rows[r][0], limits.rows[r][0]);
    for (const char* axis : {"x", "y", "z"}) {
      const int c = limits.column(std::string("forearm.limit_excess_") + axis);
      largest = std::max(largest, std::abs(limits.rows[r][c]));
    }
  }
  ASSERT_GT(sum.max_limit_violation_deg, 1.0);  // the scene pulls past the limit
  EXPECT_NEAR(largest, sum.max_limit_violation_deg * kDegToRad, 1e-6);
}

// linear interpolation: the hand's target moves along the straight segment to its goal and
// stays there once the interpolation is over
TEST(RunFolder, LinearTargetPathIsAStraightSegment) {
  Scene scene = load_scene(test::model_path("scenes/fig10_raise_linear.json"));
  scene.steps = scene.params.interpolation_steps + 10;
  const std::string dir = fresh_dir("raise");
  simulate_into_folder(scene, dir, 1);
  const Table limits = read_table(dir + "/targets_and_limits.csv");
  const int x = limits.column("hand.L.target_x");
  const auto target = [&](std::size_t r) {
    return Vec3(limits.rows[r][x], limits.rows[r][x + 1], limits.rows[r][x + 2]);
  };
  const Vec3 start = target(0), goal = scene.control_points[0].target_world;
  ASSERT_GT((goal - start).norm(), 0.5);
  const Vec3 dir_unit = (goal - start).normalized();
  for (std::size_t r = 0; r < limits.rows.size(); ++r) {
    const Vec3 off = target(r) - start;
    EXPECT_LT((off - off.dot(dir_unit) * dir_unit).norm(), 1e-6) << "row " << r;
  }
  EXPECT_TRUE(test::near(target(limits.rows.size() - 1), goal, 1e-7));
}

// a 1 kg, 1 m rod lying on the floor (contacts_test.cpp): at rest each end carries m g / 2, so
// each end contact sinks by m g / (2 k) and its spring pushes m g / 2
TEST(RunFolder, RestingRodRecordsItsTwoEndContacts) {
  const double k = 1e4, load = 1.0 * 9.81 / 2.0;
  Scene scene = test::floor_scene(test::lying_rod(0.06), Scheme::kImplicit, 0.05);
  scene.params.contact_k = k;
  scene.steps = 60;  // 3 s
  const std::string dir = fresh_dir("rod");
  simulate_into_folder(scene, dir, 10);
  const Table traj = read_table(dir + "/trajectory.csv");
  const Table contacts = read_table(dir + "/" + kContactsFile);
  ASSERT_EQ(contacts.columns,
            std::vector<std::string>(std::begin(kContactsColumns), std::end(kContactsColumns)));
  // every row at a trajectory row's step and time; step 0 (no force stage yet) has none
  for (const std::vector<double>& row : contacts.rows) {
    ASSERT_EQ(row.size(), contacts.columns.size());
    EXPECT_GT(row[0], 0);
    bool found = false;
    for (const std::vector<double>& t : traj.rows) found |= t[0] == row[0] && t[1] == row[1];
    EXPECT_TRUE(found) << "step " << row[0];
  }
  std::vector<std::vector<double>> last;
  for (const std::vector<double>& row : contacts.rows) {
    if (row[0] == scene.steps) last.push_back(row);
  }
  ASSERT_EQ(last.size(), 2u);
  for (const std::vector<double>& row : last) {
    EXPECT_EQ(row[contacts.column("bone")], 0);
    EXPECT_EQ(row[contacts.column("other_bone")], -1);  // the ground
    const int n = contacts.column("normal_x");
    EXPECT_TRUE(test::near(Vec3(row[n], row[n + 1], row[n + 2]), Vec3::UnitZ(), 1e-12));
    const double depth = row[contacts.column("depth")];
    EXPECT_NEAR(depth, load / k, 1e-6 * load / k);
    EXPECT_NEAR(row[contacts.column("normal_force")], load, 1e-6 * load);
    // midway between the end sphere's bottom (-depth) and the floor (0)
    EXPECT_NEAR(row[contacts.column("point_z")], -0.5 * depth, 1e-9);
  }
  const int x = contacts.column("point_x");
  EXPECT_NEAR(std::min(last[0][x], last[1][x]), 0.0, 1e-6);  // the rod's two ends
  EXPECT_NEAR(std::max(last[0][x], last[1][x]), 1.0, 1e-6);
}

// dropped from 0.3 (its underside 0.24 above the floor), the rod touches nothing before it has
// fallen that far: t = sqrt(2 0.24 / g), and lies on the floor by the end
TEST(RunFolder, DroppedRodRecordsNoContactBeforeItReachesTheFloor) {
  Scene scene = test::floor_scene(test::lying_rod(0.3), Scheme::kImplicit, 0.01);
  scene.steps = 100;
  const std::string dir = fresh_dir("drop");
  simulate_into_folder(scene, dir, 2);
  const Table contacts = read_table(dir + "/" + kContactsFile);
  const double fall = std::sqrt(2.0 * 0.24 / 9.81);
  ASSERT_FALSE(contacts.rows.empty());
  double first = contacts.rows[0][1];
  for (const std::vector<double>& row : contacts.rows) first = std::min(first, row[1]);
  EXPECT_GT(first, 0.9 * fall);
  EXPECT_LT(first, 1.5 * fall);
  EXPECT_EQ(contacts.rows.back()[0], scene.steps);
}

// a scene without a ground or self-collision writes no contacts table
TEST(RunFolder, NoContactsTableWithoutContacts) {
  Scene scene = load_scene(test::model_path("scenes/fig6_elbow_linear.json"));
  scene.steps = 5;
  const std::string dir = fresh_dir("no_contacts");
  simulate_into_folder(scene, dir, 1);
  EXPECT_TRUE(std::filesystem::is_regular_file(dir + "/trajectory.csv"));
  EXPECT_FALSE(std::filesystem::exists(dir + "/" + kContactsFile));
}

// summary.json's and scene.json's params: every row the run reads, at the value it used, the
// rows the scene writer leaves out at their defaults (implicit_*, contact_*, friction*) too;
// read back, scene.json gives the same params; a scene without contacts lists no contact row
TEST(RunFolder, ParamsListEveryParameterTheRunReads) {
  const auto read_json = [](const std::string& path) {
    std::ifstream in(path);
    return nlohmann::json::parse(in);
  };
  Scene scene = test::floor_scene(test::lying_rod(0.06), Scheme::kImplicit, 0.05);
  scene.params.friction = 0.5;  // one value away from its default, the rest at theirs
  scene.steps = 3;
  const std::string dir = fresh_dir("params");
  simulate_into_folder(scene, dir, 1);
  const nlohmann::json params = read_json(dir + "/" + kSummaryFile)["params"];
  for (const ParamRow& row : param_table()) {
    if (row.name == "damping_auto") continue;  // the damping row's "auto"
    if (!row.conflict_reason(scene.params, param_scene(scene)).empty())
      continue;  // the run never reads it
    ASSERT_TRUE(params.contains(row.name)) << row.name << " in " << params.dump();
    EXPECT_EQ(params[row.name], param_value_json(row, row.get(scene.params))) << row.name;
  }
  for (const char* name : {"implicit_max_splits", "implicit_linearisation", "contact_k",
                           "contact_damping", "friction", "friction_speed"}) {
    EXPECT_TRUE(params.contains(name)) << name;
  }
  EXPECT_EQ(params["friction"], 0.5);
  const nlohmann::json scene_doc = read_json(dir + "/" + kSceneFile);
  EXPECT_EQ(scene_doc["params"], params);
  const Scene back = scene_from_json(scene_doc, "scene.json", dir);
  EXPECT_EQ(params_as_run_json(back), params);

  Scene plain = load_scene(test::model_path("scenes/fig6_elbow_linear.json"));
  plain.steps = 2;
  const std::string plain_dir = fresh_dir("params_plain");
  simulate_into_folder(plain, plain_dir, 1);
  const nlohmann::json plain_params = read_json(plain_dir + "/" + kSummaryFile)["params"];
  for (const char* name : {"contact_k", "contact_damping", "friction", "friction_speed"}) {
    EXPECT_FALSE(plain_params.contains(name)) << name;
  }
  EXPECT_TRUE(plain_params.contains("torsion_torque"));
}

// the same scene twice (contacts, self-collision, gravity, damping auto): the same trajectory and
// final state, bit for bit; and the run folder's scene.json, run again, is the same run (its rig
// the rig file's own numbers: the rig writer's rest frames read back an ulp away)
TEST(RunFolder, RerunsAndTheFoldersSceneGiveTheSameRun) {
  const auto text = [](const std::string& path) {
    std::ifstream in(path);
    std::stringstream all;
    all << in.rdbuf();
    return all.str();
  };
  const auto hash = [&](const std::string& dir) {
    std::ifstream in(dir + "/" + kSummaryFile);
    return nlohmann::json::parse(in)["final_state_hash"].get<std::string>();
  };
  const std::string scene_file = ::testing::TempDir() + "/run_folder_rerun_scene.json";
  std::ofstream(scene_file) << R"({"rig": ")" << test::model_path("rigs/pinhead.json")
                            << R"(", "steps": 40, "gravity": [0, 0, -9.81],
      "ground": {"height": -2.5}, "self_collision": true, "params": {"damping": "auto"},
      "control_points": [{"bone": "hand.L", "target": [0.8, -0.6, 1.2]}]})";
  const Scene scene = load_scene(scene_file);
  ASSERT_TRUE(scene.params.damping_auto);
  const std::string a = fresh_dir("rerun_a"), b = fresh_dir("rerun_b"), c = fresh_dir("rerun_c");
  simulate_into_folder(scene, a, 1);
  simulate_into_folder(load_scene(scene_file), b, 1);
  const Table contacts = read_table(a + "/" + kContactsFile);
  EXPECT_FALSE(contacts.rows.empty());  // the run touches the floor
  EXPECT_EQ(hash(a), hash(b));
  // the tables compared whole (a difference would print them: say which instead)
  EXPECT_TRUE(text(a + "/" + kTrajectoryFile) == text(b + "/" + kTrajectoryFile)) << "trajectory";
  EXPECT_TRUE(text(a + "/" + kContactsFile) == text(b + "/" + kContactsFile)) << "contacts";
  simulate_into_folder(load_scene(a + "/" + kSceneFile), c, 1);
  EXPECT_EQ(hash(c), hash(a));
  EXPECT_TRUE(text(c + "/" + kTrajectoryFile) == text(a + "/" + kTrajectoryFile)) << "rerun";
}

// clearing an earlier run: its own files and the named extras go, the user's stay, and a folder
// that is not a run folder (no summary.json) loses nothing
TEST(RunFolder, ClearingAnEarlierRunKeepsTheUsersFiles) {
  namespace fs = std::filesystem;
  Scene scene = load_scene(test::model_path("scenes/fig6_elbow_linear.json"));
  scene.steps = 2;
  const std::string dir = fresh_dir("clear");
  simulate_into_folder(scene, dir, 1);
  simulate_into_folder(scene, dir + "/ref", 1);
  simulate_into_folder(scene, dir + "/ref_kept", 1);
  std::ofstream(dir + "/extra.json") << "{}";
  std::ofstream(dir + "/notes.txt") << "mine";
  std::ofstream(dir + "/ref_kept/notes.txt") << "mine";
  clear_run_folder(dir, "--out", {"extra.json"}, {"ref", "ref_kept", "absent"});
  for (const char* name : {kSceneFile, kTrajectoryFile, kTargetsLimitsFile, kSummaryFile,
                           kFinalPoseFile, "extra.json", "ref"}) {
    EXPECT_FALSE(fs::exists(dir + "/" + name)) << name;
  }
  EXPECT_TRUE(fs::is_regular_file(dir + "/notes.txt"));
  EXPECT_TRUE(fs::is_regular_file(dir + "/ref_kept/notes.txt"));
  EXPECT_FALSE(fs::exists(dir + "/ref_kept/" + kSummaryFile));
  // no summary.json now: not a run folder, so the user's notes.txt and ref_kept stay as they are
  std::ofstream(dir + "/" + kTrajectoryFile) << "mine";
  clear_run_folder(dir, "--out", {}, {"ref_kept"});
  EXPECT_TRUE(fs::is_regular_file(dir + "/" + kTrajectoryFile));
  EXPECT_TRUE(fs::is_regular_file(dir + "/ref_kept/notes.txt"));
}

}  // namespace
}  // namespace physik
