// The recorder (physik/io/recorder.h): which steps get a trajectory row, the columns, never a
// non-finite row, frames at chosen steps or every step, the per-step vectors, and that it is the
// one writer of the trajectory table (`physik simulate` writes the same bytes).
#include "physik/io/recorder.h"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "physik/engine/engine.h"
#include "physik/io/scene_io.h"
#include "physik/model/errors.h"
#include "tests/test_util.h"

namespace physik {
namespace {

Scene short_scene(int steps) {
  Scene s = load_scene(test::model_path("scenes/pinhead_two_hands.json"));
  s.steps = steps;
  return s;
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream in(line);
  std::string cell;
  while (std::getline(in, cell, ',')) out.push_back(cell);
  return out;
}

// the rows of a table (header dropped), each split into cells
std::vector<std::vector<std::string>> rows_of(const std::string& text) {
  std::stringstream in(text);
  std::string line;
  std::getline(in, line);
  std::vector<std::vector<std::string>> rows;
  while (std::getline(in, line)) rows.push_back(split(line));
  return rows;
}

std::vector<int> row_steps(const std::string& text) {
  std::vector<int> steps;
  for (const auto& r : rows_of(text)) steps.push_back(std::stoi(r.at(0)));
  return steps;
}

std::string table_of(const Scene& scene, int every, RowRule rule, RecordedRun* run = nullptr) {
  std::ostringstream csv;
  RecordOptions o;
  o.csv_stream = &csv;
  o.csv_every = every;
  o.csv_rows = rule;
  o.stats = o.residuals = true;
  RecordedRun r = record_run(scene, o);
  if (run) *run = std::move(r);
  return csv.str();
}

TEST(Recorder, EveryNAndTheScenesLastStep) {
  const Scene scene = short_scene(7);
  // step 0 is the initial state
  EXPECT_EQ(row_steps(table_of(scene, 3, RowRule::kEveryAndLast)), (std::vector<int>{0, 3, 6, 7}));
}

TEST(Recorder, EveryNAndTheFirstStep) {
  const Scene scene = short_scene(7);
  EXPECT_EQ(row_steps(table_of(scene, 3, RowRule::kEveryAndFirst)), (std::vector<int>{0, 1, 3, 6}));
}

TEST(Recorder, EveryStepWhenNIsOne) {
  const Scene scene = short_scene(5);
  for (RowRule rule : {RowRule::kEveryAndLast, RowRule::kEveryAndFirst}) {
    EXPECT_EQ(row_steps(table_of(scene, 1, rule)), (std::vector<int>{0, 1, 2, 3, 4, 5}));
  }
}

TEST(Recorder, HeaderNamesEveryColumnAndRowsFillThem) {
  const Scene scene = short_scene(4);
  const std::string text = table_of(scene, 2, RowRule::kEveryAndLast);
  std::string want = "step,time,kinetic_energy,passes,joint_mismatch,joint_separation";
  // residuals are named after their control points (pinhead_two_hands: hand.L, hand.R)
  for (const ControlPoint& cp : scene.control_points) want += ",residual_" + cp.name;
  for (const std::string& b : scene.rig.bone_name) {
    for (const char* end : {"head", "tail"}) {
      for (const char* axis : {"x", "y", "z"}) want += "," + b + "." + end + "_" + axis;
    }
  }
  EXPECT_EQ(text.substr(0, text.find('\n')), want);
  for (const auto& r : rows_of(text)) EXPECT_EQ(r.size(), split(want).size());
}

TEST(Recorder, ResidualColumnsAreNamedAfterTheirPointsUniqueAndQuoted) {
  Scene scene = short_scene(2);
  scene.control_points[0].name = "";                        // no name: its index
  scene.control_points[1].name = "grip, left";              // a comma: quoted
  scene.control_points.push_back(scene.control_points[1]);  // the same name again: suffixed
  EXPECT_EQ(residual_column_names(scene),
            (std::vector<std::string>{"residual_0", "\"residual_grip, left\"",
                                      "\"residual_grip, left_2\""}));
}

TEST(Recorder, RowsHoldTheRecordedStepValues) {
  const Scene scene = short_scene(6);
  RecordedRun run;
  const std::string text = table_of(scene, 1, RowRule::kEveryAndLast, &run);
  const auto rows = rows_of(text);
  ASSERT_EQ(rows.size(), run.stats.size() + 1);  // the initial state, then every step
  ASSERT_EQ(run.residuals.size(), run.stats.size());
  // step 0: at rest, nothing solved yet, each point at its distance from its target on the
  // initial pose
  const BoneFrames f0 = forward_kinematics(scene.rig, scene.initial_pose);
  EXPECT_EQ(rows[0][0], "0");
  EXPECT_EQ(std::stod(rows[0][1]), 0.0);
  EXPECT_EQ(std::stod(rows[0][2]), 0.0);
  EXPECT_EQ(rows[0][3], "0");
  for (std::size_t c = 0; c < scene.control_points.size(); ++c) {
    const ControlPoint& cp = scene.control_points[c];
    const double d0 = (point_on_bone(f0, cp.bone, cp.alpha) - cp.target_world).norm();
    EXPECT_NEAR(std::stod(rows[0][6 + c]), d0, 1e-8 * d0);
  }
  for (std::size_t k = 0; k + 1 < rows.size(); ++k) {
    const StepStats& st = run.stats[k];
    const auto& row = rows[k + 1];
    EXPECT_NEAR(std::stod(row[1]), (k + 1) * scene.params.dt, 1e-9);
    EXPECT_NEAR(std::stod(row[2]), st.kinetic_energy, 1e-8 * std::abs(st.kinetic_energy));
    EXPECT_EQ(std::stoi(row[3]), st.passes);
    for (std::size_t c = 0; c < run.residuals[k].size(); ++c) {
      EXPECT_NEAR(std::stod(row[6 + c]), run.residuals[k][c], 1e-8 * run.residuals[k][c] + 1e-12);
    }
  }
}

TEST(Recorder, NeverWritesANonFiniteRow) {
  const Scene scene = short_scene(3);
  SimState s;
  init_state(scene, s);
  s.step = 1;
  std::vector<double> res(scene.control_points.size(), 0.5);
  std::ostringstream out;
  TrajectoryCsv csv(scene, out, 1, RowRule::kEveryAndLast);
  const std::string header = out.str();
  StepStats st;
  st.kinetic_energy = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(csv.write_row(s, st, res));
  st.kinetic_energy = 1.0;
  res[0] = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(csv.write_row(s, st, res));
  res[0] = 0.5;
  s.frames.tail_world[2].y() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(csv.write_row(s, st, res));
  EXPECT_EQ(out.str(), header);  // nothing written
  s.frames.tail_world[2].y() = 0.0;
  EXPECT_TRUE(csv.write_row(s, st, res));
  EXPECT_NE(out.str(), header);
}

TEST(Recorder, DivergingRunKeepsOnlyFiniteRows) {
  Scene scene = short_scene(400);
  scene.params.damping = 20.0;  // the paper's damping diverges on pinhead (damping_sweep)
  RecordedRun run;
  const std::string text = table_of(scene, 1, RowRule::kEveryAndLast, &run);
  ASSERT_TRUE(run.summary.diverged);
  const auto rows = rows_of(text);
  ASSERT_FALSE(rows.empty());
  EXPECT_LE(static_cast<int>(rows.size()), run.summary.steps_run + 1);  // + the initial state
  for (const auto& r : rows) {
    for (const std::string& cell : r) EXPECT_TRUE(std::isfinite(std::stod(cell))) << cell;
  }
}

TEST(Recorder, FramesAtChosenStepsAndAtEveryStep) {
  const Scene scene = short_scene(6);
  RecordOptions every;
  every.all_frames = true;
  every.stats = every.residuals = every.poses = true;
  const RecordedRun all = record_run(scene, every);
  ASSERT_EQ(all.summary.steps_run, 6);
  ASSERT_EQ(all.frames.size(), 6u);
  EXPECT_EQ(all.frame_steps, (std::vector<int>{1, 2, 3, 4, 5, 6}));
  EXPECT_EQ(all.stats.size(), 6u);
  EXPECT_EQ(all.residuals.size(), 6u);
  EXPECT_EQ(all.poses.size(), 6u);
  EXPECT_EQ(state_hash(all.frames.back()), state_hash(all.summary.final_frames));

  RecordOptions chosen;
  chosen.frame_steps = {0, 2, 5};
  const RecordedRun some = record_run(scene, chosen);
  EXPECT_EQ(some.frame_steps, (std::vector<int>{0, 2, 5}));
  ASSERT_EQ(some.frames.size(), 3u);
  EXPECT_EQ(state_hash(some.frames[0]),
            state_hash(forward_kinematics(scene.rig, scene.initial_pose)));
  EXPECT_EQ(state_hash(some.frames[1]), state_hash(all.frames[1]));
  EXPECT_EQ(state_hash(some.frames[2]), state_hash(all.frames[4]));
  EXPECT_TRUE(some.stats.empty());  // not asked for
  EXPECT_TRUE(some.residuals.empty());
  EXPECT_TRUE(some.poses.empty());
}

TEST(Recorder, UnwritablePathIsAnInputErrorNamingIt) {
  const Scene scene = short_scene(2);
  RecordOptions o;
  o.csv_path = "/nonexistent_dir_for_recorder_test/trajectory.csv";
  try {
    record_run(scene, o);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(o.csv_path), std::string::npos) << e.what();
  }
}

// `physik simulate` writes its trajectory.csv with the recorder: the same bytes
TEST(Recorder, SimulateWritesTheRecordersTable) {
  const std::string out = ::testing::TempDir() + "/recorder_simulate";
  std::filesystem::remove_all(out);
  const std::string cmd = std::string(PHYSIK_BINARY) + " simulate " +
                          test::model_path("scenes/pinhead_two_hands.json") +
                          " --steps 25 --every 4 --quiet --out " + out;
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  const Scene scene = short_scene(25);
  EXPECT_EQ(test::read_file(out + "/trajectory.csv"), table_of(scene, 4, RowRule::kEveryAndLast));
}

// the table's header is spelled in one source file: every writer goes through the recorder
TEST(Recorder, OneWriterOfTheTrajectoryTable) {
  std::vector<std::string> spelled;
  for (const char* dir : {"physik", "cli", "experiments", "reference", "tune", "bench"}) {
    const std::filesystem::path root = std::filesystem::path(PHYSIK_SOURCE_DIR) / dir;
    if (!std::filesystem::exists(root)) continue;
    for (const auto& e : std::filesystem::recursive_directory_iterator(root)) {
      const std::string ext = e.path().extension().string();
      if (ext != ".cpp" && ext != ".h") continue;
      if (test::read_file(e.path().string()).find("\"step,time,kinetic_energy") !=
          std::string::npos) {
        spelled.push_back(std::filesystem::relative(e.path(), PHYSIK_SOURCE_DIR).string());
      }
    }
  }
  EXPECT_EQ(spelled, (std::vector<std::string>{"physik/io/recorder.cpp"}));
}

}  // namespace
}  // namespace physik
