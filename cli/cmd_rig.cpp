// physik rig info | chain | tree: inspect rigs and generate chains and balanced trees.
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>

#include "cli/commands.h"
#include "physik/io/json_fields.h"
#include "physik/io/rig_io.h"
#include "physik/model/errors.h"
#include "physik/model/kinematics.h"
#include "physik/model/rig_generators.h"

namespace physik::cli {

namespace {

nlohmann::json vec_json(const Vec3& v) {
  return {v.x(), v.y(), v.z()};
}

nlohmann::json rig_info_json(const Rig& rig, const std::string& path) {
  nlohmann::json bones = nlohmann::json::array();
  for (int i = 0; i < rig.nbone; ++i) {
    nlohmann::json limits = nlohmann::json::object();
    static const char* kAxis[3] = {"x", "y", "z"};
    for (int a = 0; a < 3; ++a) {
      const AxisLimit& l = rig.bone_limit[i][a];
      if (l.limited) limits[kAxis[a]] = {rad2deg(l.min), rad2deg(l.max)};
    }
    bones.push_back(
        {{"name", rig.bone_name[i]},
         {"parent", rig.bone_parent[i] < 0 ? nlohmann::json(nullptr)
                                           : nlohmann::json(rig.bone_name[rig.bone_parent[i]])},
         {"head", vec_json(rig.bone_rest_head_world[i])},
         {"tail", vec_json(rig.bone_rest_tail_world[i])},
         {"length", rig.bone_length[i]},
         {"mass", rig.bone_mass[i]},
         {"inertia_local", vec_json(rig.bone_inertia_local[i])},
         {"dof", rig.bone_parent[i] < 0 ? 6 : rig.bone_dof(i)},
         {"limits_deg", limits}});
  }
  nlohmann::json joints = nlohmann::json::array();
  for (const Joint& j : rig.joints) {
    nlohmann::json children = nlohmann::json::array();
    int dof = 0;
    for (int c : j.children) {
      children.push_back({{"bone", rig.bone_name[c]}, {"dof", rig.bone_dof(c)}});
      dof += rig.bone_dof(c);
    }
    joints.push_back({{"parent", rig.bone_name[j.parent]},
                      {"position", vec_json(rig.bone_rest_tail_world[j.parent])},
                      {"children", children},
                      {"nbone", j.nbone()},
                      {"dof", dof}});
  }
  return {{"file", path},
          {"name", rig.name},
          {"bones", rig.nbone},
          {"joints", static_cast<int>(rig.joints.size())},
          {"max_bones_per_joint", rig.max_bones_per_joint()},
          {"total_mass", rig.total_mass()},
          {"height", rig.height()},
          {"bone_list", bones},
          {"joint_list", joints}};
}

void print_rig_info(const Rig& rig, const std::string& path) {
  std::cout << "rig " << (rig.name.empty() ? "(unnamed)" : rig.name) << " from " << path << "\n"
            << "  bones: " << rig.nbone << "\n"
            << "  joints: " << rig.joints.size() << "\n"
            << "  max bones at one joint: " << rig.max_bones_per_joint() << "\n"
            << std::setprecision(4) << "  total mass: " << rig.total_mass() << " kg\n"
            << "  height: " << rig.height() << " rig units\n"
            << "  joints (at the parent's tail; DOF of each child relative to the parent):\n";
  for (std::size_t k = 0; k < rig.joints.size(); ++k) {
    const Joint& j = rig.joints[k];
    int dof = 0;
    std::ostringstream kids;
    for (int c : j.children) {
      kids << " " << rig.bone_name[c] << "(" << rig.bone_dof(c) << ")";
      dof += rig.bone_dof(c);
    }
    std::cout << "    [" << k << "] " << rig.bone_name[j.parent] << " ->" << kids.str() << "  "
              << j.nbone() << " bones, " << dof << " DOF\n";
  }
}

// options live as long as the app: each command owns its options through a shared_ptr
void add_info(CLI::App* rig) {
  struct InfoOptions {
    std::string path;
    bool json = false;
  };
  auto info_opt = std::make_shared<InfoOptions>();
  auto* info = rig->add_subcommand("info", "Bones, joints, DOF per joint and total mass of a rig");
  info->add_option("RIG", info_opt->path, "Rig file (JSON)")->required();
  info->add_flag("--json", info_opt->json, "Print JSON instead of text");
  info->callback([info_opt] {
    const Rig rig = load_rig(info_opt->path);
    if (info_opt->json) {
      std::cout << rig_info_json(rig, info_opt->path).dump(2) << "\n";
    } else {
      print_rig_info(rig, info_opt->path);
    }
  });
}

void add_chain(CLI::App* rig) {
  struct ChainOptions {
    int n = 3;
    double bone_length = 1.0;  // rig units
    double radius = 0.5;       // rig units (the original code's)
    std::string out;
  };
  auto chain_opt = std::make_shared<ChainOptions>();
  auto* chain = rig->add_subcommand("chain", "Generate a straight chain of N free bones along +Z");
  chain->add_option("N", chain_opt->n, "Number of bones")->required();
  chain->add_option("--bone-length", chain_opt->bone_length, "Length of each bone (rig units)")
      ->capture_default_str();
  chain->add_option("--radius", chain_opt->radius, "Cylinder radius for the inertia (rig units)")
      ->capture_default_str();
  chain->add_option("--out", chain_opt->out, "Write the rig JSON here instead of stdout");
  chain->callback([chain_opt] {
    write_json(rig_to_json(make_chain_rig(chain_opt->n, chain_opt->bone_length, chain_opt->radius)),
               chain_opt->out);
  });
}

void add_tree(CLI::App* rig) {
  struct TreeOptions {
    int n = 7;
    int branching = 2;
    double bone_length = 1.0;  // rig units
    double radius = 0.5;       // rig units (the original code's)
    std::string out;
  };
  auto tree_opt = std::make_shared<TreeOptions>();
  auto* tree = rig->add_subcommand(
      "tree",
      "Generate a balanced tree of N free bones: every bone has B children at its tail (the "
      "last level partly filled), each leaning 30 deg from its parent; the root along +Z");
  tree->add_option("N", tree_opt->n, "Number of bones")->required();
  tree->add_option("--branching", tree_opt->branching, "Children per bone (B; 1 = a chain)")
      ->capture_default_str();
  tree->add_option("--bone-length", tree_opt->bone_length, "Length of each bone (rig units)")
      ->capture_default_str();
  tree->add_option("--radius", tree_opt->radius, "Cylinder radius for the inertia (rig units)")
      ->capture_default_str();
  tree->add_option("--out", tree_opt->out, "Write the rig JSON here instead of stdout");
  tree->callback([tree_opt] {
    write_json(rig_to_json(make_tree_rig(tree_opt->n, tree_opt->branching, tree_opt->bone_length,
                                         tree_opt->radius)),
               tree_opt->out);
  });
}

}  // namespace

void add_rig_commands(CLI::App& app) {
  CLI::App* rig = app.add_subcommand("rig", "Inspect and generate rigs");
  rig->require_subcommand(1);
  add_info(rig);
  add_chain(rig);
  add_tree(rig);
}

}  // namespace physik::cli
