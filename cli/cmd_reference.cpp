// physik export-mjcf RIG: the rig as MuJoCo MJCF (reference/mjcf_export.h), checked by compiling
// it with MuJoCo before printing.
#include <fstream>
#include <iostream>
#include <memory>

#include "cli/commands.h"
#include "physik/model/errors.h"
#include "physik/io/rig_io.h"
#include "reference/mjcf_export.h"

namespace physik::cli {

namespace {

struct ExportMjcfOptions {
  std::string rig;
  std::string out;                       // "" or "-" = stdout
  std::string joints = "rig";            // rig | ball
  double dt = 0.05;                      // s
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
  cmd->add_option("--out", opt->out, "Write to this file instead of stdout");
  cmd->add_option("--joints", opt->joints,
                  "rig: joint types and limits from the rig (exact-constraints mode); ball: a "
                  "ball at every bone, no limits (same-forces mode)")
      ->check(CLI::IsMember({"rig", "ball"}))
      ->capture_default_str();
  cmd->add_option("--dt", opt->dt, "Time step, s")->capture_default_str();
  cmd->callback([opt] {
    if (!(opt->dt > 0.0)) throw_input_error("--dt", "", "", "must be positive");
    const Rig rig = load_rig(opt->rig);
    MjcfOptions o;
    o.joints = opt->joints == "ball" ? JointModel::kBallJoints : JointModel::kRigJoints;
    o.dt = opt->dt;
    o.source = opt->rig;
    const std::string xml = rig_to_mjcf(rig, o);
    compile_mjcf(xml);  // throws with MuJoCo's message if it does not load
    if (opt->out.empty() || opt->out == "-") {
      std::cout << xml;
      return;
    }
    std::ofstream f(opt->out);
    if (!f) throw_input_error(opt->out, "", "--out", "cannot write file");
    f << xml;
  });
}

}  // namespace physik::cli
