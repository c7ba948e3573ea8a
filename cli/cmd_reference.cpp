// physik export-mjcf RIG: the rig as MuJoCo MJCF (reference/mjcf_export.h), checked by compiling
// it with MuJoCo before printing.
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>

#include "cli/commands.h"
#include "physik/io/output_files.h"
#include "physik/io/rig_io.h"
#include "physik/io/scene_io.h"
#include "physik/model/errors.h"
#include "reference/mjcf_export.h"

namespace physik::cli {

namespace {

struct ExportMjcfOptions {
  std::string rig;
  std::string out;             // "" or "-" = stdout
  std::string joints = "rig";  // rig | hinge | ball
  double dt = 0.05;            // s
  std::string contacts;        // a scene file whose gravity, ground and self-collision to write
};

// the options with --contacts' gravity, ground and self-collision; its rig must be RIG's
MjcfOptions with_scene_contacts(const ExportMjcfOptions& opt, const Rig& rig, MjcfOptions o) {
  const Scene scene = load_scene(opt.contacts);
  if (scene.rig.bone_name != rig.bone_name) {
    throw_input_error(opt.contacts, "", "rig", "not the rig of " + opt.rig + " (its bones differ)");
  }
  return mjcf_contacts(scene, o);
}

}  // namespace

void add_reference_commands(CLI::App& app) {
  auto opt = std::make_shared<ExportMjcfOptions>();
  auto* cmd = app.add_subcommand(
      "export-mjcf",
      "Print the rig as MuJoCo MJCF: one body per bone with PhysIK's mass and inertia, a free "
      "root, ball/hinge/welded joints from the rig's limits (or balls everywhere), Euler "
      "integrator; no gravity and no contacts unless --contacts gives a scene. The MJCF is "
      "compiled by MuJoCo before it is printed.");
  cmd->add_option("RIG", opt->rig, "Rig file (JSON, see models/README.md)")->required();
  cmd->add_option(
      "--out", opt->out,
      "Write to this file instead of stdout; a rig nested deeper than " +
          std::to_string(kMjcfBodiesPerFile) +
          " bodies also gets include files STEM.partK.xml beside it (STEM = FILE without .xml)");
  cmd->add_option("--joints", opt->joints,
                  "rig: joint types and limits from the rig (exact-constraints mode); hinge: the "
                  "exact and implicit schemes' joints, a hinge or two where the rig locks axes, "
                  "no limits (their same-forces mode); ball: a ball at every bone, no limits "
                  "(the gauss-seidel scheme's same-forces mode)")
      ->check(CLI::IsMember({"rig", "hinge", "ball"}))
      ->capture_default_str();
  cmd->add_option("--dt", opt->dt, "Time step, s")->capture_default_str();
  cmd->add_option("--contacts", opt->contacts,
                  "A scene file on the same rig: write its gravity, ground plane and "
                  "self-collision (the bones' collision capsules, pairs sharing a joint and its "
                  "collision_exclude pairs left out) and its friction");
  cmd->callback([opt] {
    check_mjcf_timestep(opt->dt, "--dt");
    const Rig rig = load_rig(opt->rig);
    MjcfOptions o;
    o.joints = opt->joints == "ball"    ? JointModel::kBallJoints
               : opt->joints == "hinge" ? JointModel::kHingeJoints
                                        : JointModel::kRigJoints;
    o.dt = opt->dt;
    o.source = opt->rig;
    if (!opt->contacts.empty()) o = with_scene_contacts(*opt, rig, o);
    // deep rigs: the main file and include files beside it (MuJoCo's parser nests ~100 deep)
    const bool to_stdout = opt->out.empty() || opt->out == "-";
    const std::filesystem::path out(to_stdout ? "physik_rig.xml" : opt->out);
    const std::vector<MjcfFile> files = rig_to_mjcf_files(rig, o, out.filename().string());
    compile_rig_mjcf(rig, o, files);  // throws with MuJoCo's message if it does not load
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
