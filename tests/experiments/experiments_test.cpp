// The experiments register themselves (experiments/experiment.h): every expected one is there,
// in the run order of `make reproduce`; the report builder (experiments/report.h) writes the
// "report" section analysis/report.py reads; an experiment's trajectory table is the recorder's.
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "experiments/common.h"
#include "experiments/experiment.h"
#include "experiments/report.h"
#include "physik/io/bvh.h"
#include "physik/io/json_fields.h"
#include "physik/io/scene_io.h"
#include "tests/experiments/experiments_test_util.h"
#include "tests/test_util.h"

namespace physik::experiments {
namespace {

TEST(Experiments, EveryExpectedExperimentIsRegisteredInRunOrder) {
  std::vector<std::string> names;
  for (const Experiment& e : all_experiments()) names.push_back(e.name);
  const std::vector<std::string> expected = {"rest_poses",
                                             "fig5_running",
                                             "fig6_elbow",
                                             "fig7_cannon",
                                             "fig8_wobble",
                                             "fig9_outstretched",
                                             "fig10_interpolation",
                                             "fig11_sit",
                                             "hand_explodes",
                                             "timing",
                                             "damping_sweep",
                                             "mujoco_gap",
                                             "ik_comparison",
                                             "orientation_targets",
                                             "equilibrium_solve",
                                             "tracking",
                                             "linearisation",
                                             "tuning_study",
                                             "scaling",
                                             "beyond_the_paper",
                                             "outside_rigs",
                                             "human_body",
                                             "contacts",
                                             "contacts_cost",
                                             "clip_following"};
  EXPECT_EQ(names, expected);
}

TEST(Experiments, EachHasAFigureADescriptionAndARun) {
  std::set<std::string> names;
  for (const Experiment& e : all_experiments()) {
    EXPECT_FALSE(e.figure.empty()) << e.name;
    EXPECT_FALSE(e.description.empty()) << e.name;
    EXPECT_TRUE(static_cast<bool>(e.run)) << e.name;
    EXPECT_TRUE(names.insert(e.name).second) << "registered twice: " << e.name;
  }
}

TEST(Report, WritesTitleAndClaimsAndOnlyTheSectionsGiven) {
  Report bare("A title");
  const nlohmann::json b = bare.to_json();
  EXPECT_EQ(b["title"], "A title");
  EXPECT_TRUE(b["claims"].is_array());
  EXPECT_TRUE(b["claims"].empty());
  for (const char* key : {"section", "notes", "figures", "settings", "tables"})
    EXPECT_FALSE(b.contains(key)) << key;

  Report full("T");
  full.section("baselines")
      .claim("c1", "m1", "yes")
      .claim("c2", "m2", "partly (why)")
      .note("n1")
      .note("n2")
      .figures({"a.png", "b.png"})
      .settings({{"dt", 0.05}})
      .table("t", {"a", "b"}, {{1, "x"}, {2, "y"}});
  const nlohmann::json f = full.to_json();
  EXPECT_EQ(f["tables"][0]["title"], "t");
  EXPECT_EQ(f["tables"][0]["columns"], (nlohmann::json{"a", "b"}));
  EXPECT_EQ(f["tables"][0]["rows"][1], (nlohmann::json{2, "y"}));
  EXPECT_THROW(full.table("short", {"a", "b"}, {{1}}), std::logic_error);
  EXPECT_EQ(f["section"], "baselines");
  ASSERT_EQ(f["claims"].size(), 2u);
  EXPECT_EQ(f["claims"][1],
            (nlohmann::json{{"claim", "c2"}, {"measured", "m2"}, {"holds", "partly (why)"}}));
  EXPECT_EQ(f["notes"], (nlohmann::json{"n1", "n2"}));
  EXPECT_EQ(f["figures"], (nlohmann::json{"a.png", "b.png"}));
  EXPECT_EQ(f["settings"]["dt"], 0.05);
}

// A claim's name is what prose cites (claim `experiment/name`): the last claim's, checked.
TEST(Report, NamesTheLastClaimAndRefusesBadOrRepeatedNames) {
  Report r("T");
  EXPECT_THROW(r.named("early"), std::logic_error);  // no claim yet
  r.claim("c1", "m1", "yes").named("first-claim").claim("c2", "m2", "no");
  const nlohmann::json j = r.to_json();
  EXPECT_EQ(j["claims"][0]["name"], "first-claim");
  EXPECT_FALSE(j["claims"][1].contains("name"));
  EXPECT_THROW(r.named("first-claim"), std::logic_error);  // two claims of one name
  EXPECT_THROW(r.named("Upper"), std::logic_error);
  EXPECT_THROW(r.named("with space"), std::logic_error);
  r.named("second");
  EXPECT_EQ(r.to_json()["claims"][1]["name"], "second");
}

// A claim's holds cell is a verdict word, alone or with a reason in parentheses; a sentence
// there (the contacts experiment's "no: a resting pose that moves ...") is refused, by Report
// and by the hand-assembled rows alike, so REPORT.md's summary column stays one word a row.
TEST(Report, RefusesAVerdictThatIsNotYesNoPartlyOrNa) {
  Report r("T");
  for (const char* ok : {"yes", "no", "partly", "n/a", "no (a run diverged)", "n/a (quick run)",
                         "partly (on the seat; 2 feet off the floor)"}) {
    EXPECT_NO_THROW(r.claim("c", "m", ok)) << ok;
    EXPECT_NO_THROW(claim("c", "m", ok)) << ok;
  }
  for (const char* bad : {"no: a resting pose that moves by more than 2% when its engine halves "
                          "the step is picked by the path",
                          "", "maybe", "Yes", "yes.", "no ()", "partly (unclosed", "no(x)"}) {
    EXPECT_THROW(r.claim("c", "m", bad), std::logic_error) << bad;
    EXPECT_THROW(claim("c", "m", bad), std::logic_error) << bad;
  }
  EXPECT_EQ(r.to_json()["claims"].size(), 7u);  // the refused rows are not kept
}

// fig5_running (quick): its summary carries the report, and its trajectory table is the bytes a
// recorder writes with the experiments' rule (a row every 10 steps and at step 1)
TEST(Experiments, Fig5WritesItsReportAndTheRecordersTable) {
  const std::string out_dir = test::fresh_temp_dir("experiments_fig5");
  const nlohmann::json summary = test::run_quick_experiment("fig5_running", out_dir);
  const nlohmann::json& report = summary["report"];
  EXPECT_EQ(report["title"], "Fig 5: a running pose from 8 control points");
  ASSERT_EQ(report["claims"].size(), 2u);
  for (const auto& c : report["claims"]) {
    for (const char* key : {"claim", "measured", "holds"}) EXPECT_TRUE(c[key].is_string()) << key;
  }
  EXPECT_TRUE(report["settings"].is_object());

  Scene scene = load_scene(test::model_path("scenes/fig5_running.json"));
  scene.steps = 100;  // the quick run's
  std::ostringstream csv;
  RecordOptions o = trajectory_table("", 10);
  o.csv_stream = &csv;
  record_run(scene, o);
  EXPECT_EQ(test::read_file(out_dir + "/trajectory.csv"), csv.str());
  // the first rows are the initial state (step 0) and step 1
  const std::string rows = csv.str().substr(csv.str().find('\n') + 1);
  EXPECT_EQ(rows.substr(0, 2), "0,");
  EXPECT_EQ(rows.substr(rows.find('\n') + 1, 2), "1,");
}

// clip_following (quick): the walk it writes is a clip of its rig's source skeleton whose feet
// stand on the floor and stay planted (the measures read 0 on the clip itself), and every run is
// measured without diverging
TEST(Experiments, ClipFollowingWritesAPlantedWalkAndMeasuresEachRun) {
  const std::string out_dir = test::fresh_temp_dir("experiments_clip_following");
  const nlohmann::json summary = test::run_quick_experiment("clip_following", out_dir);
  const nlohmann::json& rows = summary["rows"];
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[0]["run"], "clip");
  EXPECT_LT(rows[0]["max_foot_penetration_cm"].get<double>(), 1e-9);
  EXPECT_LT(rows[0]["planted_toe_speed_mean_cm_s"].get<double>(), 1e-6);
  EXPECT_EQ(rows[0]["time_lag_frames"], 0);
  for (const auto& r : rows) EXPECT_FALSE(r["diverged"].get<bool>()) << r["run"];
  const BvhFile walk = read_bvh_file(out_dir + "/walk.bvh");
  EXPECT_EQ(walk.joints.size(), 19u);
  EXPECT_EQ(walk.frames.size(), 40u);
}

// fig11_sit (quick) leaves its run as a run folder for the viewer, listed in runs/order.txt,
// and it is the experiment's own run (the same final state)
TEST(Experiments, Fig11LeavesItsRunAsARunFolder) {
  const std::string out_dir = test::fresh_temp_dir("experiments_fig11");
  const nlohmann::json summary = test::run_quick_experiment("fig11_sit", out_dir);

  EXPECT_EQ(test::read_file(out_dir + "/runs/order.txt"), "sit\n");
  const std::string run = out_dir + "/runs/sit";
  for (const char* f : {"scene.json", "trajectory.csv", "targets_and_limits.csv", "summary.json",
                        "final_pose.csv"}) {
    EXPECT_TRUE(std::filesystem::exists(run + "/" + f)) << f;
  }
  const nlohmann::json mine = read_json_file(run + "/summary.json");
  const nlohmann::json theirs = summary.at("run");
  EXPECT_EQ(mine["final_state_hash"], theirs["final_state_hash"]);
  EXPECT_EQ(mine["steps_run"], theirs["steps_run"]);
}

}  // namespace
}  // namespace physik::experiments
