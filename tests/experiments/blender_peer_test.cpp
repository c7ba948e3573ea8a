// Blender's iTaSC as the fig9 experiment's peer (experiments/blender_peer.h): where Blender is
// looked for, every way a run can fail (each one line, nothing left for a figure, the experiment
// still complete), and, when Blender is installed, iTaSC's row in fig9's measures and report.
#include <sys/stat.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "experiments/blender_peer.h"
#include "experiments/experiment.h"
#include "physik/io/json_fields.h"
#include "physik/io/scene_io.h"
#include "tests/experiments/experiments_test_util.h"
#include "tests/test_util.h"

namespace physik::experiments {
namespace {

namespace fs = std::filesystem;

// PHYSIK_BLENDER set (or unset) for one test, restored after it.
class BlenderEnv {
 public:
  explicit BlenderEnv(const std::optional<std::string>& value) {
    if (const char* old = std::getenv("PHYSIK_BLENDER")) old_ = std::string(old);
    if (value) {
      ::setenv("PHYSIK_BLENDER", value->c_str(), 1);
    } else {
      ::unsetenv("PHYSIK_BLENDER");
    }
  }
  ~BlenderEnv() {
    if (old_) {
      ::setenv("PHYSIK_BLENDER", old_->c_str(), 1);
    } else {
      ::unsetenv("PHYSIK_BLENDER");
    }
  }

 private:
  std::optional<std::string> old_;
};

std::string fresh_dir(const std::string& name) {
  const std::string d = ::testing::TempDir() + "/blender_peer_" + name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

// A stand-in for Blender: a shell script with the given body.
std::string fake_blender(const std::string& dir, const std::string& body) {
  const std::string path =
      dir + "/fake blender";  // a space: the run passes paths unquoted, no shell
  std::ofstream(path) << "#!/bin/sh\n" << body << "\n";
  ::chmod(path.c_str(), 0755);
  return path;
}

std::string models() {
  return std::string(PHYSIK_SOURCE_DIR) + "/models";
}
std::string script() {
  return std::string(PHYSIK_SOURCE_DIR) + "/blender/itasc_solve.py";
}
Scene fig9() {
  return load_scene(models() + "/scenes/fig9_outstretched.json");
}

TEST(BlenderPeer, PhysikBlenderOffOrNotExecutableIsAbsentWithWhy) {
  for (const char* off : {"none", "off", "0", ""}) {
    BlenderEnv env(std::string{off});
    const BlenderLocation where = find_blender();
    EXPECT_TRUE(where.path.empty()) << off;
    EXPECT_NE(where.why_not.find("turns the Blender peer off"), std::string::npos) << where.why_not;
  }
  BlenderEnv env(std::string("/no/such/blender"));
  const BlenderLocation where = find_blender();
  EXPECT_TRUE(where.path.empty());
  EXPECT_EQ(where.why_not, "PHYSIK_BLENDER='/no/such/blender' is not an executable file");
  const ItascRun run = run_itasc(fig9(), script(), fresh_dir("absent"));
  EXPECT_EQ(run.status, "absent");
  EXPECT_EQ(run.reason, where.why_not);
}

TEST(BlenderPeer, PhysikBlenderNamesTheBinary) {
  const std::string dir = fresh_dir("named");
  const std::string fake = fake_blender(dir, "exit 0");
  BlenderEnv env(fake);
  EXPECT_EQ(find_blender().path, fake);
}

TEST(BlenderPeer, AFailingBlenderIsOneLineAndLeavesNoPose) {
  const std::string dir = fresh_dir("fails");
  // it writes a bones file, then fails: the file must not survive for a figure to draw
  BlenderEnv env(
      fake_blender(dir,
                   "for a; do [ \"$prev\" = --out ] && echo junk > \"$a\"; prev=$a; done\n"
                   "echo 'itasc_solve.py: something broke' >&2\nexit 3"));
  const ItascRun run = run_itasc(fig9(), script(), dir);
  EXPECT_EQ(run.status, "failed");
  EXPECT_NE(run.reason.find("Blender exited 3 (itasc_solve.py: something broke); see "),
            std::string::npos)
      << run.reason;
  EXPECT_EQ(run.reason.find('\n'), std::string::npos);
  EXPECT_FALSE(fs::exists(dir + "/itasc_final.csv"));
  EXPECT_NE(test::read_file(dir + "/itasc_log.txt").find("something broke"), std::string::npos);
}

TEST(BlenderPeer, ABlenderThatWritesNothingIsReported) {
  const std::string dir = fresh_dir("silent");
  BlenderEnv env(fake_blender(dir, "exit 0"));
  const ItascRun run = run_itasc(fig9(), script(), dir);
  EXPECT_EQ(run.status, "failed");
  EXPECT_EQ(run.reason.rfind("reading Blender's output: ", 0), 0u) << run.reason;
  EXPECT_NE(run.reason.find("itasc_report.json"), std::string::npos) << run.reason;
}

TEST(BlenderPeer, AHangingBlenderIsStoppedAtTheTimeout) {
  const std::string dir = fresh_dir("hangs");
  BlenderEnv env(fake_blender(dir, "exec sleep 60"));
  const auto t0 = std::chrono::steady_clock::now();
  const ItascRun run = run_itasc(fig9(), script(), dir, 0.5);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_EQ(run.status, "failed");
  EXPECT_NE(run.reason.find("did not finish within 0.5 s"), std::string::npos) << run.reason;
  EXPECT_LT(seconds, 10.0);
}

// fig9_outstretched (quick) into its own folder; its summary
nlohmann::json run_fig9(const std::string& out_dir) {
  return test::run_quick_experiment("fig9_outstretched", out_dir);
}

const nlohmann::json* claim(const nlohmann::json& summary, const std::string& prefix) {
  for (const auto& c : summary["report"]["claims"]) {
    if (c["claim"].get<std::string>().rfind(prefix, 0) == 0) return &c;
  }
  return nullptr;
}

std::string methods(const std::string& measures_csv) {
  std::ifstream in(measures_csv);
  std::string line, out;
  std::getline(in, line);
  while (std::getline(in, line)) out += line.substr(0, line.find(',')) + " ";
  return out;
}

TEST(BlenderPeer, Fig9WithoutBlenderSaysSoAndKeepsItsRows) {
  BlenderEnv env(std::string("none"));
  const std::string dir = fresh_dir("fig9_none");
  const nlohmann::json s = run_fig9(dir);
  EXPECT_TRUE(s["itasc"].is_null());
  EXPECT_EQ(s["itasc_run"]["status"], "absent");
  EXPECT_EQ(methods(dir + "/measures.csv"), "physik dls mujoco_same_forces ");
  const nlohmann::json* meets = claim(s, "Fig 9: Blender's iTaSC meets");
  ASSERT_NE(meets, nullptr);
  EXPECT_EQ((*meets)["holds"], "n/a (absent: PHYSIK_BLENDER='none' turns the Blender peer off)");
  EXPECT_NE(s["report"]["notes"][0].get<std::string>().find("no row"), std::string::npos);
  EXPECT_FALSE(fs::exists(dir + "/itasc_final.csv"));
  EXPECT_TRUE(s["dls"]["max_residual"].get<double>() < 0.01);  // the rest is all there
}

TEST(BlenderPeer, Fig9WithAFailingBlenderStillCompletes) {
  const std::string dir = fresh_dir("fig9_false");
  BlenderEnv env(fake_blender(fresh_dir("fig9_false_bin"), "exit 1"));
  const nlohmann::json s = run_fig9(dir);
  EXPECT_EQ(s["itasc_run"]["status"], "failed");
  const nlohmann::json* meets = claim(s, "Fig 9: Blender's iTaSC meets");
  ASSERT_NE(meets, nullptr);
  EXPECT_EQ(
      (*meets)["holds"].get<std::string>().rfind("n/a (failed: Blender exited 1 (no output)", 0),
      0u)
      << (*meets)["holds"];
  EXPECT_EQ(methods(dir + "/measures.csv"), "physik dls mujoco_same_forces ");
}

TEST(BlenderPeer, Fig9WithBlenderAddsTheItascRow) {
  BlenderEnv env(std::nullopt);
  if (find_blender().path.empty()) GTEST_SKIP() << find_blender().why_not;
  const std::string dir = fresh_dir("fig9_blender");
  const nlohmann::json s = run_fig9(dir);
  const nlohmann::json& run = s["itasc_run"];
  ASSERT_EQ(run["status"], "ok") << run.dump();
  EXPECT_EQ(run["settings"]["mode"], "ANIMATION");
  EXPECT_EQ(run["settings"]["solver"], "SDLS");
  EXPECT_EQ(run["settings"]["chain"], "root");
  const Scene scene = fig9();
  EXPECT_LT(run["fk_gap"].get<double>(), kItascFkGapFraction * scene.rig.height());
  EXPECT_TRUE(run["meets_control_points"].get<bool>());
  // the row measured here meets the points within the scene's tolerance, as Blender's own check
  EXPECT_LE(s["itasc"]["max_residual"].get<double>(), scene.residual_tol());
  EXPECT_LT(s["itasc"]["max_limit_excess_deg"].get<double>(), 0.5);
  EXPECT_EQ(methods(dir + "/measures.csv"), "physik dls itasc mujoco_same_forces ");
  EXPECT_TRUE(fs::exists(dir + "/itasc_final.csv"));
  const nlohmann::json* meets = claim(s, "Fig 9: Blender's iTaSC meets");
  ASSERT_NE(meets, nullptr);
  EXPECT_EQ((*meets)["holds"], "yes");
  const nlohmann::json* stiff = claim(s, "Fig 9: PhysIK leans and tilts the head where iTaSC");
  ASSERT_NE(stiff, nullptr);
  EXPECT_NE((*stiff)["holds"].get<std::string>().substr(0, 3), "n/a");
  const nlohmann::json& rows = s["report"]["tables"][0]["rows"];
  ASSERT_EQ(rows.size(), 4u);
  EXPECT_EQ(rows[2][0], "Blender iTaSC");
}

}  // namespace
}  // namespace physik::experiments
