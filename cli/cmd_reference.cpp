// physik export-mjcf RIG: the rig as MuJoCo MJCF (reference/mjcf_export.h), checked by compiling
// it with MuJoCo before printing.
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>

#include "cli/commands.h"
#include "physik/io/output_files.h"
#include "physik/io/rig_io.h"
#include "physik/model/errors.h"
#include "reference/mjcf_export.h"

namespace physik::cli {

namespace {

struct ExportMjcfOptions {
  std::string rig;
  std::string out;             // "" or "-" = stdout
  std::string joints = "rig";  // rig | ball
  double dt = 0.05;            // s
};

}  // namespace

void add_reference_commands(CLI::App& app) {
  auto opt = std::make_shared<ExportMjcfOptions>();
  auto* cmd = app.add_subcommand(
      "export-mjcf",
      "Print the rig as MuJoCo MJCF: one body per bone with PhysIK's mass and inertia, a free "
      "root, ball/hinge/welded joints from the rig's limits (or balls everywhere), no gravity, no "
      "contacts, Euler integrator. The MJCF is compiled by MuJoCo before it is printed.");
  cmd->add_option("RIG", opt->rig, "Rig file (JSON, see models/README.md)")->required();
  cmd->add_option(
      "--out", opt->out,
      "Write to this file instead of stdout; a rig nested deeper than " +
          std::to_string(kMjcfBodiesPerFile) +
          " bodies also gets include files STEM.partK.xml beside it (STEM = FILE without .xml)");
  cmd->add_option("--joints", opt->joints,
                  "rig: joint types and limits from the rig (exact-constraints mode); ball: a "
                  "ball at every bone, no limits (same-forces mode)")
      ->check(CLI::IsMember({"rig", "ball"}))
      ->capture_default_str();
  cmd->add_option("--dt", opt->dt, "Time step, s")->capture_default_str();
  cmd->callback([opt] {
    check_mjcf_timestep(opt->dt, "--dt");
    const Rig rig = load_rig(opt->rig);
    MjcfOptions o;
    o.joints = opt->joints == "ball" ? JointModel::kBallJoints : JointModel::kRigJoints;
    o.dt = opt->dt;
    o.source = opt->rig;
    // deep rigs: the main file and include files beside it (MuJoCo's parser nests ~100 deep)
    const bool to_stdout = opt->out.empty() || opt->out == "-";
    const std::filesystem::path out(to_stdout ? "physik_rig.xml" : opt->out);
    const std::vector<MjcfFile> files = rig_to_mjcf_files(rig, o, out.filename().string());
    compile_mjcf(files);  // throws with MuJoCo's message if it does not load
    if (to_stdout) {
      if (files.size() > 1) {
        throw_input_error(opt->rig, "", "--out",
                          "the rig is too deep for one MJCF file (it needs " +
                              std::to_string(files.size() - 1) +
                              " include files): give --out FILE, they are written beside it");
      }
      std::cout << files[0].text;
      return;
    }
    for (const MjcfFile& file : files) {
      const std::filesystem::path path = out.parent_path() / file.name;
      std::ofstream f = open_output_file(path.string(), "--out");
      f << file.text;
    }
  });
}

}  // namespace physik::cli
