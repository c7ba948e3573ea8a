// The outside_rigs experiment (experiments/outside_rigs.h):
//  - the target rule on a hand-built Y and a chain: the farthest leaf, moved a quarter of the
//    rig's size along the fixed directions; the second leaf farthest from the first; one leaf
//    pins the root's head;
//  - two of MuJoCo's sample files holding one humanoid (renamed, moved) are the same rig; a mass
//    or a limit changed makes them differ; a broken file and a duplicate are skipped with reasons;
//  - damping auto runs on a long chain (past the dense modes' old 400-bone cap) and a short one;
//  - the turn inside a welded group sees a welded bone turned against its weld (and only it), the
//    root's drift its head moved; a non-finite state is left out; arm26 with its root made free
//    drops the root's limits;
//  - the quick run: runs.csv and summary.json agree, every configuration's counts add up to its
//    runs, the claims are short and their verdicts follow the counts, and the CSV rows of one
//    converted rig equal a scene built directly in C++ (no JSON, no --set) and run with run_scene;
//  - the quick run's checks (checks.csv): one row per sample rig, arm26 with its root made free and
//    the BVH skeleton; the body claims' verdicts follow the rows; the free root drifts where the
//    pinned one stays; the BVH skeleton's file is the one converted, its pelvis one body.
#include "experiments/outside_rigs.h"

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include <gtest/gtest.h>

#include "experiments/common.h"
#include "experiments/experiment.h"
#include "experiments/mocap_bvh.h"
#include "experiments/weld_turn.h"
#include "physik/engine/engine.h"
#include "physik/io/bvh.h"
#include "physik/io/json_fields.h"
#include "physik/io/rig_io.h"
#include "physik/model/kinematics.h"
#include "physik/model/params.h"
#include "physik/model/rig_generators.h"
#include "reference/mjcf_import.h"
#include "tests/experiments/experiments_test_util.h"

namespace physik::experiments::outside_rigs {
namespace {

std::string fresh_dir(const std::string& name) {
  const std::string d = ::testing::TempDir() + "/outside_rigs_" + name;
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

std::string sample(const std::string& name) {
  return std::string(kSamplesDir) + "/" + name;
}

BoneSpec bone(const std::string& name, const std::string& parent, const Vec3& h, const Vec3& t) {
  BoneSpec b;
  b.name = name;
  b.parent = parent;
  b.head_world = h;
  b.tail_world = t;
  b.rest_frame_world = rest_frame_from_roll(h, t, 0.0);
  return b;
}

TEST(OutsideRigs, TheRuleMovesTheFarthestLeafsTailByAQuarterOfTheRigsSize) {
  // a Y: left's tail is sqrt 5 from the root's head, right's sqrt 4.5; the box is 2.5 x 0 x 2
  const Rig y = build_rig(
      {bone("spine", "", {0, 0, 0}, {0, 0, 1}), bone("left", "spine", {0, 0, 1}, {-1, 0, 2}),
       bone("right", "spine", {0, 0, 1}, {1.5, 0, 1.5})},
      "Y");
  EXPECT_DOUBLE_EQ(rig_size(y), 2.5);
  const std::vector<Pick> p = pick_targets(y, 2);
  ASSERT_EQ(p.size(), 2u);
  const double r = std::sqrt(0.5);
  EXPECT_EQ(y.bone_name[p[0].bone], "left");
  EXPECT_EQ(p[0].alpha, 1.0);
  EXPECT_TRUE(p[0].target_world.isApprox(Vec3(-1 + 0.625 * r, 0, 2 + 0.625 * r), 1e-12));
  EXPECT_EQ(y.bone_name[p[1].bone], "right");
  EXPECT_TRUE(p[1].target_world.isApprox(Vec3(1.5 - 0.625 * r, 0, 1.5 + 0.625 * r), 1e-12));
  EXPECT_EQ(pick_targets(y, 1).size(), 1u);
  EXPECT_THROW(pick_targets(y, 3), std::logic_error);

  // a chain has one leaf: the second point pins the root's head where it is
  const Rig chain = make_chain_rig(3);
  const std::vector<Pick> c = pick_targets(chain, 2);
  EXPECT_EQ(c[0].bone, 2);
  EXPECT_EQ(c[1].bone, 0);
  EXPECT_EQ(c[1].alpha, 0.0);
  EXPECT_EQ(c[1].target_world, chain.bone_rest_head_world[0]);
}

TEST(OutsideRigs, OneHumanoidInTwoFilesIsOneRigAndAChangedMassOrLimitIsAnother) {
  const Rig a = load_mjcf(sample("humanoid/humanoid.xml")).rig();
  const Rig b = load_mjcf(sample("humanoid/22_humanoids.xml")).rig();  // renamed and moved
  ASSERT_NE(a.bone_name[0], b.bone_name[0]);
  ASSERT_GT((a.bone_rest_head_world[0] - b.bone_rest_head_world[0]).norm(), 0.5);
  EXPECT_TRUE(same_rig(a, b));
  Rig heavier = b;
  heavier.bone_mass[5] *= 1.001;
  EXPECT_FALSE(same_rig(a, heavier));
  Rig looser = b;
  for (auto& l : looser.bone_limit) {
    if (l[0].limited) l[0].max += 0.01;
  }
  EXPECT_FALSE(same_rig(a, looser));
  EXPECT_FALSE(same_rig(a, make_chain_rig(21)));
}

TEST(OutsideRigs, ABrokenFileAndADuplicateAreSkippedWithTheirReasons) {
  const std::string dir = fresh_dir("collect");
  for (const char* sub : {"a", "b"}) std::filesystem::create_directories(dir + "/" + sub);
  std::filesystem::copy_file(sample("humanoid/humanoid.xml"), dir + "/a/first.xml");
  std::filesystem::copy_file(sample("humanoid/humanoid.xml"), dir + "/b/again.xml");
  std::ofstream(dir + "/b/broken.xml") << "<mujoco><worldbody><body></mujoco>";
  std::ofstream(dir + "/b/notes.txt") << "not a model";
  const std::vector<std::string> files = sample_files(dir);
  ASSERT_EQ(files.size(), 3u);  // the .xml files, in path order
  EXPECT_EQ(files[0], dir + "/a/first.xml");
  const Collection c = collect_rigs(files);
  ASSERT_EQ(c.rigs.size(), 1u);
  EXPECT_EQ(c.rigs[0].name, "a-first");
  EXPECT_EQ(c.rigs[0].rig.nbone, 21);
  ASSERT_EQ(c.skipped.size(), 2u);
  EXPECT_EQ(c.skipped[0].file, dir + "/b/again.xml");
  EXPECT_NE(c.skipped[0].reason.find("the same rig as a-first"), std::string::npos);
  EXPECT_EQ(c.skipped[1].file, dir + "/b/broken.xml");
  EXPECT_NE(c.skipped[1].reason.find("broken.xml"), std::string::npos) << c.skipped[1].reason;
  EXPECT_THROW(sample_files(dir + "/absent"), std::runtime_error);
}

TEST(OutsideRigs, DampingAutoRunsOnALongChainAndAShortOne) {
  const std::string dir = fresh_dir("refused");
  const auto implicit = [](const char* torque) {
    for (const Configuration& c : configurations()) {
      if (c.name == std::string("implicit-auto-") + torque) return c;
    }
    throw std::logic_error("no configuration");
  };
  for (int n : {401, 3}) {
    const Rig rig = make_chain_rig(n);
    const std::string rig_file = dir + "/chain" + std::to_string(n) + ".json";
    const std::string scene_file = dir + "/chain" + std::to_string(n) + "-scene.json";
    write_json(rig_to_json(rig), rig_file);
    write_json(scene_json(rig_file, rig, pick_targets(rig, 1), 300), scene_file);
    for (const char* torque : {"axes", "gradient"}) {
      const RunResult r = run_configuration(scene_file, implicit(torque));
      // the long chain need not settle in 300 steps; it must run, and not diverge
      if (n < 400) {
        EXPECT_EQ(r.outcome, Outcome::kConverged) << torque;
      }
      EXPECT_NE(r.outcome, Outcome::kRefused) << r.refusal;
      EXPECT_NE(r.outcome, Outcome::kDiverged) << torque;
      EXPECT_GT(r.steps_run, 0);
      EXPECT_GT(r.damping, 0.0);  // damping auto's choice, not the preset's value
      EXPECT_NE(r.damping, preset_params("original").damping);
    }
  }
}

TEST(OutsideRigs, TheWeldTurnSeesAWeldedBoneTurnedAgainstItsWeldAndOnlyIt) {
  // a root, a bone welded to it, and a free child of the welded one
  std::vector<BoneSpec> specs = {bone("root", "", {0, 0, 0}, {0, 0, 1}),
                                 bone("welded", "root", {0, 0, 1}, {1, 0, 1}),
                                 bone("free", "welded", {1, 0, 1}, {1, 0, 2})};
  specs[1].weld = "root";
  const Rig rig = build_rig(specs, "weld-turn");
  ASSERT_TRUE(rig.welded(1));
  ASSERT_FALSE(rig.welded(2));
  BoneFrames frames = forward_kinematics(rig, rest_pose(rig));
  EXPECT_EQ(max_weld_turn(rig, frames), 0.0);
  BodyMeasure m;
  m.observe(rig, frames);
  EXPECT_EQ(m.weld_turn, 0.0);
  EXPECT_EQ(m.root_drift, 0.0);

  // the free bone turned: no weld turns
  frames.orient_world[2] = Quat(Eigen::AngleAxisd(0.7, Vec3::UnitX())) * frames.orient_world[2];
  EXPECT_EQ(max_weld_turn(rig, frames), 0.0);
  // the whole welded body turned together: no weld turns either
  const Quat whole(Eigen::AngleAxisd(0.4, Vec3(1, 2, 3).normalized()));
  for (int i : {0, 1}) frames.orient_world[i] = whole * frames.orient_world[i];
  EXPECT_LT(max_weld_turn(rig, frames), 1e-15);
  // the welded bone turned against its weld by 0.3 rad: the turn, in the root's body too
  frames.orient_world[1] = Quat(Eigen::AngleAxisd(0.3, Vec3::UnitZ())) * frames.orient_world[1];
  EXPECT_NEAR(max_weld_turn(rig, frames), 0.3, 1e-12);
  EXPECT_NEAR(max_weld_turn(rig, frames, rig.bone_body[0]), 0.3, 1e-12);
  EXPECT_EQ(max_weld_turn(rig, frames, rig.bone_body[2]), 0.0);
  frames.head_world[0] += Vec3(0, 0.25, 0);
  m.observe(rig, frames);
  EXPECT_NEAR(m.weld_turn, 0.3, 1e-12);
  EXPECT_NEAR(m.root_turn, 0.3, 1e-12);
  EXPECT_NEAR(m.root_drift, 0.25, 1e-15);
  // a state gone non-finite is left out, not taken for a turn of 0 or a NaN maximum
  frames.orient_world[1].coeffs().setConstant(std::nan(""));
  m.observe(rig, frames);
  EXPECT_NEAR(m.weld_turn, 0.3, 1e-12);
  BodyMeasure more;
  more.root_drift = 1.0;
  m.add(more);
  EXPECT_EQ(m.root_drift, 1.0);
  EXPECT_NEAR(m.weld_turn, 0.3, 1e-12);
}

TEST(OutsideRigs, Arm26WithItsRootMadeFreeHasNoRootLimits) {
  const Rig arm = load_mjcf(sample("tendon_arm/arm26.xml")).rig();
  ASSERT_EQ(arm.root_joint, RootJoint::kPinned);
  const Rig free = with_free_root(arm);
  EXPECT_EQ(free.root_joint, RootJoint::kFree);
  EXPECT_EQ(free.nbone, arm.nbone);
  for (const AxisLimit& l : free.bone_limit[free.root()]) EXPECT_FALSE(l.limited);
  // the rest of the rig is the same
  EXPECT_EQ(free.bone_limit[1][0].limited, arm.bone_limit[1][0].limited);
  EXPECT_EQ(free.bone_rest_head_world, arm.bone_rest_head_world);
}

// runs.csv as rows of named cells
std::vector<std::map<std::string, std::string>> read_csv(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> header;
  std::stringstream hs(line);
  for (std::string cell; std::getline(hs, cell, ',');) header.push_back(cell);
  std::vector<std::map<std::string, std::string>> rows;
  while (std::getline(in, line)) {
    std::stringstream ls(line);
    std::map<std::string, std::string> row;
    for (const std::string& h : header) std::getline(ls, row[h], ',');
    rows.push_back(row);
  }
  return rows;
}

void run_quick(const std::string& out_dir) {
  test::run_quick_experiment("outside_rigs", out_dir);
}

// the quick run's folder, run once per process for the tests below (named after the first test
// that asks, so tests that ctest runs side by side never share it)
const std::string& quick_dir() {
  static const std::string dir = [] {
    const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
    const std::string d = fresh_dir(std::string("quick_") + test->name());
    run_quick(d);
    return d;
  }();
  return dir;
}

TEST(OutsideRigs, TheQuickRunsCountsAddUpInTheCsvAndTheSummary) {
  const nlohmann::json s = read_json_file(quick_dir() + "/summary.json");
  const auto rows = read_csv(quick_dir() + "/runs.csv");
  // one humanoid in two of the quick files: the second is skipped as its duplicate
  ASSERT_EQ(s["skipped"].size(), 1u);
  EXPECT_EQ(s["skipped"][0]["file"], sample("humanoid/humanoid.xml"));
  EXPECT_NE(s["skipped"][0]["reason"].get<std::string>().find("hammock-humanoid_body"),
            std::string::npos);
  const std::size_t nrigs = kQuickFiles.size() - 1;
  ASSERT_EQ(s["rigs"].size(), nrigs);
  const std::size_t nconfig = configurations().size();
  ASSERT_EQ(rows.size(), nrigs * 2 * nconfig);
  ASSERT_EQ(s["runs"].size(), rows.size());
  ASSERT_EQ(s["configurations"].size(), nconfig);
  for (const auto& c : s["configurations"]) {
    const nlohmann::json& n = c["counts"];
    const int runs = n["runs"];
    EXPECT_EQ(runs, static_cast<int>(nrigs * 2)) << c["name"];
    EXPECT_EQ(n["converged"].get<int>() + n["not_converged"].get<int>() + n["diverged"].get<int>() +
                  n["refused"].get<int>(),
              runs)
        << c["name"];
    for (const char* outcome : {"converged", "not_converged", "diverged", "refused"}) {
      int in_csv = 0;
      for (const auto& r : rows) {
        in_csv += r.at("configuration") == c["name"] && r.at("outcome") == outcome;
      }
      EXPECT_EQ(in_csv, n[outcome].get<int>()) << c["name"] << " " << outcome;
    }
  }
  for (const auto& r : rows) {
    if (r.at("configuration") == "default") {
      EXPECT_EQ(r.at("preset"), kDefaultPreset);
    }
    EXPECT_EQ(r.at("residual_over_size").empty(), r.at("outcome") == "refused");
    const int steps = std::stoi(r.at("steps_to_converge"));
    EXPECT_EQ(steps >= 0, r.at("outcome") == "converged");
    EXPECT_LE(steps, std::stoi(r.at("steps_run")));
    // the scene file names no params, so the default is the engine's
    const nlohmann::json scene =
        read_json_file(quick_dir() + "/scenes/" + r.at("rig") + "-" + r.at("points") + "pt.json");
    EXPECT_FALSE(scene.contains("params"));
    EXPECT_EQ(scene["control_points"].size(), std::stoul(r.at("points")));
  }
}

TEST(OutsideRigs, TheQuickRunsClaimsAreShortAndFollowTheCounts) {
  const nlohmann::json s = read_json_file(quick_dir() + "/summary.json");
  const nlohmann::json& claims = s["report"]["claims"];
  ASSERT_EQ(claims.size(), 7u);
  for (const auto& c : claims) EXPECT_LE(c["measured"].get<std::string>().size(), 200u);
  const nlohmann::json& d = s["configurations"][0]["counts"];
  ASSERT_EQ(s["configurations"][0]["name"], "default");
  EXPECT_EQ(claims[0]["holds"], d["converged_share"].get<double>() >= 0.9 ? "yes" : "no");
  EXPECT_NE(claims[0]["measured"].get<std::string>().find(
                std::to_string(d["converged"].get<int>()) + " of " +
                std::to_string(d["runs"].get<int>()) + " runs"),
            std::string::npos);
  const nlohmann::json& t = s["torsion_comparison"];
  EXPECT_EQ(t["axes_converged"], s["configurations"][2]["counts"]["converged"]);
  EXPECT_EQ(t["gradient_converged"], s["configurations"][3]["counts"]["converged"]);
}

// the scene the rule gives, built in C++ on the rig the experiment converted and wrote (its rest
// frames read back from rigs/NAME.json as every run of them reads them): no scene file, no --set
Scene direct_scene(const std::string& model, const std::string& rig_file, int points,
                   bool implicit_gradient) {
  Scene sc;
  sc.rig = load_rig(rig_file);
  EXPECT_EQ(sc.rig.nbone, load_mjcf(model).rig().nbone);
  sc.params = preset_params("original");
  if (implicit_gradient) {
    sc.params.scheme = Scheme::kImplicit;
    sc.params.damping_auto = true;
    sc.params.torsion_torque = TorsionTorque::kGradient;
  }
  for (const Pick& p : pick_targets(sc.rig, points)) {
    ControlPoint cp;
    cp.bone = p.bone;
    cp.alpha = p.alpha;
    cp.target_world = p.target_world;
    sc.control_points.push_back(cp);
  }
  sc.steps = kQuickStepCap;
  sc.convergence.stop_when_converged = true;
  sc.initial_pose = rest_pose(sc.rig);
  return sc;
}

TEST(OutsideRigs, AConvertedRigsRowsAreADirectRunOfTheSameScene) {
  const auto rows = read_csv(quick_dir() + "/runs.csv");
  int checked = 0;
  for (const auto& r : rows) {
    if (r.at("rig") != "hammock-humanoid_body") continue;
    const bool gradient = r.at("configuration") == "implicit-auto-gradient";
    if (r.at("configuration") != "original" && !gradient) continue;
    SCOPED_TRACE(r.at("configuration") + " " + r.at("points"));
    const RunSummary d = run_scene(direct_scene(sample("hammock/humanoid_body.xml"),
                                                quick_dir() + "/rigs/hammock-humanoid_body.json",
                                                std::stoi(r.at("points")), gradient));
    const std::string outcome = d.diverged    ? "diverged"
                                : d.converged ? "converged"
                                              : "not_converged";
    EXPECT_EQ(r.at("outcome"), outcome);
    EXPECT_EQ(std::stoi(r.at("steps_run")), d.steps_run);
    EXPECT_EQ(std::stoi(r.at("steps_to_converge")), d.converged ? d.steps_to_converge : -1);
    double worst = 0.0;
    for (double x : d.final_residuals) worst = std::max(worst, x);
    const double size = rig_size(load_mjcf(sample("hammock/humanoid_body.xml")).rig());
    EXPECT_NEAR(std::stod(r.at("residual_over_size")), worst / size, 1e-9 * (1 + worst / size));
    ++checked;
  }
  EXPECT_EQ(checked, 4);  // two scenes x two configurations
}

// the claim named `name` in the quick run's report
const nlohmann::json& named_claim(const nlohmann::json& summary, const std::string& name) {
  for (const auto& c : summary["report"]["claims"]) {
    if (c.value("name", "") == name) return c;
  }
  ADD_FAILURE() << "no claim " << name;
  static const nlohmann::json none = {{"holds", ""}, {"measured", ""}};
  return none;
}

using Row = std::map<std::string, std::string>;

double cell(const Row& r, const std::string& column) {
  return std::stod(r.at(column));
}

// the quick run's checks.csv, checked for what holds of every row
std::vector<Row> quick_checks() {
  const auto rows = read_csv(quick_dir() + "/checks.csv");
  for (const auto& r : rows) {
    SCOPED_TRACE(r.at("rig"));
    // every rig ran both its scenes and solved both
    EXPECT_EQ(r.at("runs"), "2");
    EXPECT_EQ(r.at("solves"), "2");
    EXPECT_LE(std::stoi(r.at("open_overlaps")), std::stoi(r.at("rest_overlaps")));
    EXPECT_GT(cell(r, "radius_min"), 0.0);
    EXPECT_LE(cell(r, "radius_min"), cell(r, "radius_max"));
  }
  return rows;
}

TEST(OutsideRigs, TheQuickRunsBodyClaimsFollowItsChecks) {
  const nlohmann::json s = read_json_file(quick_dir() + "/summary.json");
  const auto rows = quick_checks();
  const std::size_t nrigs = kQuickFiles.size() - 1;
  ASSERT_EQ(rows.size(), nrigs + 2);  // the samples, arm26 with a free root, the BVH skeleton
  ASSERT_EQ(s["checks"].size(), rows.size());
  double turn = 0.0, ke = 0.0;
  int open = 0, welded = 0;
  for (const auto& r : rows) {
    if (r.at("source") != "mjcf") continue;
    turn = std::max({turn, cell(r, "run_weld_turn"), cell(r, "solve_weld_turn")});
    ke = std::max({ke, cell(r, "rest_ke_gauss_seidel"), cell(r, "rest_ke_exact"),
                   cell(r, "rest_ke_implicit")});
    open += std::stoi(r.at("open_overlaps"));
    welded += std::stoi(r.at("welded"));
  }
  EXPECT_GT(welded, 0);  // the humanoid's and the mug's bodies are welded groups
  EXPECT_EQ(named_claim(s, "welds-rigid")["holds"], turn <= 1e-9 ? "yes" : "no");
  EXPECT_NE(named_claim(s, "welds-rigid")["measured"].get<std::string>().find(
                std::to_string(welded) + " welded bones"),
            std::string::npos);
  EXPECT_EQ(named_claim(s, "rest-stays-rest")["holds"], ke == 0.0 ? "yes" : "no");
  EXPECT_EQ(named_claim(s, "no-rest-overlap")["holds"], open == 0 ? "yes" : "no");
}

TEST(OutsideRigs, TheQuickRunsArm26AndSkeletonClaimsFollowItsChecks) {
  const nlohmann::json s = read_json_file(quick_dir() + "/summary.json");
  const auto rows = quick_checks();
  const Row *arm = nullptr, *free = nullptr, *mocap = nullptr;
  for (const auto& r : rows) {
    if (r.at("rig") == kArm26) arm = &r;
    if (r.at("source") == "mjcf-free-root") free = &r;
    if (r.at("source") == "bvh") mocap = &r;
  }
  // arm26: its root pinned; made free, the same pull moves it (the measure sees a drift)
  ASSERT_TRUE(arm && free && mocap);
  EXPECT_EQ(arm->at("root"), "pinned");
  EXPECT_EQ(free->at("root"), "free");
  const double drift = std::max(cell(*arm, "run_root_drift"), cell(*arm, "solve_root_drift"));
  const double size = rig_size(load_rig(quick_dir() + "/rigs/" + kArm26 + ".json"));
  EXPECT_EQ(named_claim(s, "arm26-root-fixed")["holds"], drift <= 1e-12 * size ? "yes" : "no");
  EXPECT_GT(cell(*free, "run_root_drift"), 0.01 * size);
  EXPECT_GT(cell(*free, "solve_root_drift"), 0.01 * size);

  // the BVH skeleton: the file the experiment wrote is the skeleton, converted in metres
  std::ifstream in(quick_dir() + "/bvh/mocap.bvh");
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_EQ(text.str(), mocap_bvh());
  EXPECT_NEAR(rig_size(load_rig(quick_dir() + "/rigs/mocap-bvh.json")), 1.83, 0.05);
  EXPECT_GT(std::stoi(mocap->at("welded")), 0);
  const double mocap_turn =
      std::max({cell(*mocap, "run_weld_turn"), cell(*mocap, "solve_weld_turn"),
                cell(*mocap, "run_root_turn")});
  const nlohmann::json& claim = named_claim(s, "mocap-skeleton");
  EXPECT_NE(claim["measured"].get<std::string>().find("one body"), std::string::npos);
  if (claim["holds"] == "yes") {
    EXPECT_LE(mocap_turn, 1e-9);
    EXPECT_EQ(mocap->at("open_overlaps"), "0");
  }
  if (mocap_turn > 1e-9 || mocap->at("open_overlaps") != "0") {
    EXPECT_EQ(claim["holds"], "no");
  }
}

TEST(OutsideRigs, TheBvhSkeletonsPelvisIsItsRootsSegmentsInOneBody) {
  const std::string dir = fresh_dir("mocap");
  const MocapRig m = convert_mocap(dir + "/bvh/mocap.bvh");
  // the root's segments: to Spine, LeftUpLeg and RightUpLeg (and the synthetic root, if any)
  EXPECT_GE(m.pelvis.size(), 3u);
  EXPECT_TRUE(m.pelvis_one_body);
  for (int b : m.pelvis) EXPECT_EQ(m.rig.bone_body[b], m.rig.bone_body[m.pelvis[0]]);
  // as `rig from-bvh --scale 0.01` converts it
  BvhImportOptions o;
  o.scale = 0.01;
  const Rig direct = bvh_to_rig(parse_bvh(mocap_bvh(), "mocap.bvh"), "mocap.bvh", o).rig();
  EXPECT_EQ(direct.nbone, m.rig.nbone);
  EXPECT_EQ(direct.bone_body, m.rig.bone_body);
  EXPECT_EQ(direct.bone_rest_head_world, m.rig.bone_rest_head_world);
}

}  // namespace
}  // namespace physik::experiments::outside_rigs
