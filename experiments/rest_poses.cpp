// Paper Fig 4: the rest pose of every shipped rig (pinhead is the paper's rig), as bones tables
// for the analysis script to draw in front (x-z) and side (y-z) views.
#include <algorithm>
#include <filesystem>

#include "experiments/experiment.h"
#include "experiments/report.h"
#include "experiments/table.h"
#include "physik/io/pose_io.h"
#include "physik/io/rig_io.h"

namespace physik::experiments {

namespace {

void run(const Context& ctx) {
  nlohmann::json rigs = nlohmann::json::array();
  std::vector<std::filesystem::path> files;
  for (const auto& e : std::filesystem::directory_iterator(ctx.models_dir + "/rigs")) {
    if (e.path().extension() == ".json") files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  Report report("Fig 4: the rigs at rest");
  std::vector<std::string> figures;
  for (const auto& path : files) {
    const Rig rig = load_rig(path.string());
    const std::string name = path.stem().string();
    write_bones_table(ctx.out_dir + "/" + name + ".csv", rig,
                      forward_kinematics(rig, rest_pose(rig)));
    rigs.push_back({{"name", name},
                    {"file", path.filename().string()},
                    {"bones", rig.nbone},
                    {"joints", rig.joints.size()},
                    {"max_bones_per_joint", rig.max_bones_per_joint()},
                    {"total_mass", rig.total_mass()},
                    {"csv", name + ".csv"},
                    {"figure", name + ".png"}});
    figures.push_back(name + ".png");
    if (ctx.log) *ctx.log << "  rest pose of " << name << ": " << rig.nbone << " bones\n";
    if (name == "pinhead") {
      report.claim(
          "Fig 4 / Sec. 4: the test rig has 18 bones, 14 joints, at most 4 bones around "
          "one joint",
          std::to_string(rig.nbone) + " bones, " + std::to_string(rig.joints.size()) +
              " joints, at most " + std::to_string(rig.max_bones_per_joint()) +
              " bones at one joint",
          rig.nbone == 18 && rig.joints.size() == 14 && rig.max_bones_per_joint() == 4 ? "yes"
                                                                                       : "no");
    }
  }
  report.figures(figures);
  write_summary(ctx, {{"experiment", "rest_poses"}, {"rigs", rigs}}, report);
}

const Registration registered{
    40, {"rest_poses", "Fig 4", "rest pose of every shipped rig (front and side views)", run}};

}  // namespace

}  // namespace physik::experiments
