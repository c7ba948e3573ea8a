// physik rig info | chain | tree: inspect rigs and generate chains and balanced trees.
#include <algorithm>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>

#include "cli/commands.h"
#include "physik/engine/bone_overlaps.h"
#include "physik/io/json_fields.h"
#include "physik/io/rig_io.h"
#include "physik/model/errors.h"
#include "physik/model/kinematics.h"
#include "physik/model/params.h"
#include "physik/model/rest_limits.h"
#include "physik/model/rig_generators.h"

namespace physik::cli {

namespace {

nlohmann::json vec_json(const Vec3& v) {
  return {v.x(), v.y(), v.z()};
}

const char* const kAxisName[3] = {"x", "y", "z"};

// what rig info says about the rest pose: the capsule pairs that overlap, and the limits whose
// torsion band holds the rest angle at the parameter table's torsion_tolerance
struct RestChecks {
  std::vector<BoneOverlap> overlaps;
  double tolerance = 0.0;
  std::vector<RestBandProblem> bands;
};

RestChecks rest_checks(const Rig& rig) {
  RestChecks c;
  c.overlaps = rest_overlaps(rig);
  c.tolerance = preset_params("robust").torsion_tolerance;
  c.bands = rest_band_problems(rig, c.tolerance);
  return c;
}

// "[-90, 0]", "free", "locked at 0" (deg)
std::string limit_text(const AxisLimit& l) {
  std::ostringstream s;
  s.precision(4);
  if (!l.limited) return "free";
  if (l.locked()) {
    s << "locked at " << rad2deg(l.min);
  } else {
    s << "[" << rad2deg(l.min) << ", " << rad2deg(l.max) << "]";
  }
  return s.str();
}

// a bone's degrees of freedom as rig info counts them: a free root's 6, else Rig::bone_dof (3
// minus locked axes for a ball, a pinned root's included; 0 for a weld or a fixed root)
int info_dof(const Rig& rig, int bone) {
  return bone == 0 && rig.root_joint == RootJoint::kFree ? 6 : rig.bone_dof(bone);
}

int total_dof(const Rig& rig) {
  int n = 0;
  for (int b = 0; b < rig.nbone; ++b) n += info_dof(rig, b);
  return n;
}

// how a bone hangs: "free" (the root's 6 DOF), "pinned", "fixed", "ball" or "weld"
// (rig.h "Locked axes": the exact and implicit schemes' joint, "hinge" or "universal" where
// locked axes leave 1 or 2, "weld" where all 3 are locked; the paper's scheme holds those axes
// with torsion springs instead)
const char* attachment(const Rig& rig, int bone) {
  if (bone == 0) return to_string(rig.root_joint);
  return to_string(rig.bone_joint_type[bone]);
}

// "a hinge: ", "two hinges in sequence (a universal joint): ", "welded by its locks (0 DOF): "
// before a bone's limits, or "" for a ball
std::string joint_kind_text(const Rig& rig, int bone) {
  switch (rig.bone_joint_type[bone]) {
    case JointType::kHinge:
      return "hinge, 1 DOF: ";
    case JointType::kUniversal:
      return "universal (two hinges), 2 DOF: ";
    case JointType::kWeld:
      return "welded by its locks, 0 DOF: ";
    case JointType::kBall:
    case JointType::kFree:
      break;
  }
  return "";
}

// "[-90, 0]" per limited axis of a bone ("x free  y [-90, 0]  z locked at 0")
std::string limits_text(const Rig& rig, int bone) {
  std::string out;
  for (int a = 0; a < 3; ++a) {
    out += std::string(a ? "  " : "") + kAxisName[a] + " " + limit_text(rig.bone_limit[bone][a]);
  }
  return out;
}

// the root's joint to the world, e.g. "pinned: a ball at its head, held in place, 2 DOF; limits
// against its rest frame in the world: x locked at 0  y [-30, 60]  z free"
std::string root_text(const Rig& rig) {
  switch (rig.root_joint) {
    case RootJoint::kPinned:
      return std::string("pinned: a ") + to_string(rig.bone_joint_type[0]) +
             " at its head, held in place, " + std::to_string(rig.bone_dof(0)) +
             " DOF; limits against its rest frame in the world: " + limits_text(rig, 0);
    case RootJoint::kFixed:
      return "fixed to the world: 0 DOF";
    case RootJoint::kFree:
      break;
  }
  return "free: 6 DOF, no limits";
}

// what rig info says of a bone's joint: the root's to the world, a weld, or a ball's limits
std::string joint_text(const Rig& rig, int bone) {
  if (bone == 0) return "root (" + root_text(rig) + ")";
  if (rig.welded(bone)) return "welded to " + rig.bone_name[rig.bone_weld[bone]] + " (0 DOF)";
  return joint_kind_text(rig, bone) + limits_text(rig, bone);
}

// a joint's parent: a bone, or the world (a pinned root's head)
std::string joint_parent_name(const Rig& rig, const Joint& j) {
  return j.parent >= 0 ? rig.bone_name[j.parent] : std::string("world");
}

// the rig's exclusions, its capsule pairs overlapping at rest and its limits whose torsion band
// holds the rest angle (with the converters' fix)
void add_rest_checks_json(const Rig& rig, const RestChecks& checks, nlohmann::json& out) {
  nlohmann::json overlaps = nlohmann::json::array();
  for (const BoneOverlap& o : checks.overlaps) {
    overlaps.push_back({{"bones", {rig.bone_name[o.a], rig.bone_name[o.b]}},
                        {"depth", o.depth},
                        {"excluded", o.excluded}});
  }
  nlohmann::json bands = nlohmann::json::array();
  for (const RestBandProblem& p : checks.bands) {
    bands.push_back(
        {{"bone", rig.bone_name[p.bone]},
         {"axis", kAxisName[p.axis]},
         {"limit_deg", {rad2deg(p.before.min), rad2deg(p.before.max)}},
         {"fix_deg", p.fixed() ? nlohmann::json({rad2deg(p.after.min), rad2deg(p.after.max)})
                               : nlohmann::json(nullptr)}});
  }
  nlohmann::json excluded = nlohmann::json::array();
  for (const auto& [a, b] : rig.collision_exclude) {
    excluded.push_back({rig.bone_name[a], rig.bone_name[b]});
  }
  out["collision_exclude"] = excluded;
  out["rest_overlaps"] = overlaps;
  out["torsion_tolerance"] = checks.tolerance;
  out["rest_inside_torsion_band"] = bands;
}

// the joint list: each joint's parent bone (or the world), position at rest, children and DOF
nlohmann::json joint_list_json(const Rig& rig) {
  nlohmann::json joints = nlohmann::json::array();
  for (const Joint& j : rig.joints) {
    nlohmann::json children = nlohmann::json::array();
    int dof = 0;
    for (int c : j.children) {
      children.push_back({{"bone", rig.bone_name[c]}, {"dof", info_dof(rig, c)}});
      dof += info_dof(rig, c);
    }
    const Vec3 at = j.parent >= 0 ? rig.bone_rest_tail_world[j.parent]
                                  : rig.bone_rest_head_world[j.children.at(0)];
    joints.push_back({{"parent", j.parent >= 0 ? nlohmann::json(rig.bone_name[j.parent])
                                               : nlohmann::json(nullptr)},
                      {"world", j.parent < 0},
                      {"anchored", j.anchored},
                      {"position", vec_json(at)},
                      {"children", children},
                      {"nbone", j.nbone()},
                      {"dof", dof}});
  }
  return joints;
}

nlohmann::json rig_info_json(const Rig& rig, const std::string& path) {
  const RestChecks checks = rest_checks(rig);
  nlohmann::json bones = nlohmann::json::array();
  for (int i = 0; i < rig.nbone; ++i) {
    nlohmann::json limits = nlohmann::json::object();
    nlohmann::json axes = nlohmann::json::object();
    const Mat3 frame = rig.bone_rest_orient_world[i].toRotationMatrix();
    for (int a = 0; a < 3; ++a) {
      const AxisLimit& l = rig.bone_limit[i][a];
      if (l.limited) limits[kAxisName[a]] = {rad2deg(l.min), rad2deg(l.max)};
      axes[kAxisName[a]] = vec_json(frame.col(a));
    }
    bones.push_back(
        {{"name", rig.bone_name[i]},
         {"parent", rig.bone_parent[i] < 0 ? nlohmann::json(nullptr)
                                           : nlohmann::json(rig.bone_name[rig.bone_parent[i]])},
         {"head", vec_json(rig.bone_rest_head_world[i])},
         {"tail", vec_json(rig.bone_rest_tail_world[i])},
         {"length", rig.bone_length[i]},
         {"axes_world", axes},
         {"radius", rig.bone_radius[i]},
         {"collision_radius", rig.bone_collision_radius[i]},
         {"mass", rig.bone_mass[i]},
         {"inertia_local", vec_json(rig.bone_inertia_local[i])},
         {"joint", attachment(rig, i)},
         {"welded_to", rig.welded(i) ? nlohmann::json(rig.bone_name[rig.bone_weld[i]])
                                     : nlohmann::json(nullptr)},
         {"dof", info_dof(rig, i)},
         {"limits_deg", limits}});
    // the human template's segment and forward axis (bone frame), where the rig has them
    if (!rig.bone_segment[i].empty()) bones.back()["segment"] = rig.bone_segment[i];
    if (!rig.bone_forward_local[i].isZero()) {
      bones.back()["forward"] = vec_json(rig.bone_forward_local[i]);
    }
  }
  nlohmann::json out = {{"file", path},
                        {"name", rig.name},
                        {"source", rig.source},
                        {"units", rig.units},
                        {"root", to_string(rig.root_joint)},
                        {"bones", rig.nbone},
                        {"dof", total_dof(rig)},
                        {"joints", static_cast<int>(rig.joints.size())},
                        {"max_bones_per_joint", rig.max_bones_per_joint()},
                        {"total_mass", rig.total_mass()},
                        {"height", rig.height()},
                        {"bone_list", bones},
                        {"joint_list", joint_list_json(rig)}};
  add_rest_checks_json(rig, checks, out);
  return out;
}

// the bone's human-template segment and forward axis (bone frame), where the rig has them
void print_body_of_bone(const Rig& rig, int i, std::ostringstream& s) {
  if (!rig.bone_segment[i].empty()) s << "  segment " << rig.bone_segment[i];
  const Vec3& f = rig.bone_forward_local[i];
  if (!f.isZero()) s << "  forward (" << f.x() << ", " << f.y() << ", " << f.z() << ")";
}

// the human template's segments and how many bones each has (rig info's "body" line)
std::string body_summary(const Rig& rig) {
  std::vector<std::string> order;
  std::vector<int> count;
  for (int i = 0; i < rig.nbone; ++i) {
    const std::string& seg = rig.bone_segment[i];
    if (seg.empty()) continue;
    const auto it = std::find(order.begin(), order.end(), seg);
    if (it == order.end()) {
      order.push_back(seg);
      count.push_back(1);
    } else {
      ++count[it - order.begin()];
    }
  }
  if (order.empty()) return "";
  std::string out;
  for (std::size_t k = 0; k < order.size(); ++k) {
    out += (k ? ", " : "") + order[k] + (count[k] > 1 ? " x" + std::to_string(count[k]) : "");
  }
  return out;
}

// each bone's local axes in world at rest, and its limits per local axis (deg)
void print_bone_frames(const Rig& rig) {
  std::cout << "  bones (local axes in world at rest; limits per local axis, deg, on the "
               "rotation from rest):\n";
  std::ostringstream s;
  s << std::fixed << std::setprecision(3);
  for (int i = 0; i < rig.nbone; ++i) {
    const Mat3 f = rig.bone_rest_orient_world[i].toRotationMatrix();
    s.str("");
    s << "    " << rig.bone_name[i] << ":";
    for (int a = 0; a < 3; ++a) {
      s << "  " << kAxisName[a] << " (" << f(0, a) << ", " << f(1, a) << ", " << f(2, a) << ")";
    }
    s << "  " << joint_text(rig, i);
    print_body_of_bone(rig, i, s);
    std::cout << s.str() << "\n";
  }
}

// the rest pose's overlapping capsules and the limits that push at rest
void print_rest_checks(const Rig& rig, const RestChecks& c) {
  int open = 0;
  for (const BoneOverlap& o : c.overlaps) open += o.excluded ? 0 : 1;
  std::cout << std::setprecision(4)
            << "  bone pairs whose capsules overlap at rest: " << c.overlaps.size();
  if (!c.overlaps.empty()) {
    std::cout << " (" << open << " not in collision_exclude: under self_collision they push "
              << "apart from the first step)";
  }
  std::cout << "\n";
  for (const BoneOverlap& o : c.overlaps) {
    std::cout << "    " << rig.bone_name[o.a] << " / " << rig.bone_name[o.b] << "  depth "
              << o.depth << " rig units" << (o.excluded ? "  (excluded)" : "  NOT excluded")
              << "\n";
  }
  std::cout << "  limits whose torsion band holds the rest angle (torsion_tolerance " << c.tolerance
            << "; they push at rest): " << c.bands.size() << "\n";
  for (const RestBandProblem& p : c.bands) {
    std::cout << "    " << describe(p, rig.bone_name[p.bone]) << "\n";
  }
}

void print_rig_info(const Rig& rig, const std::string& path) {
  std::cout << "rig " << (rig.name.empty() ? "(unnamed)" : rig.name) << " from " << path << "\n"
            << "  bones: " << rig.nbone << "\n"
            << "  joints: " << rig.joints.size() << "\n"
            << "  max bones at one joint: " << rig.max_bones_per_joint() << "\n"
            << "  degrees of freedom: " << total_dof(rig) << " (every bone's, the root's to the "
            << "world included)\n"
            << std::setprecision(4) << "  total mass: " << rig.total_mass() << " kg\n"
            << "  height: " << rig.height() << " rig units\n"
            << "  root '" << rig.bone_name[0] << "': " << root_text(rig) << "\n"
            << (body_summary(rig).empty()
                    ? std::string()
                    : "  body: human template (models/README.md \"A human body\"), segments: " +
                          body_summary(rig) + "\n")
            << "  joints (at the parent's tail, or the world's at a pinned root's head; DOF of "
               "each child relative to the parent):\n";
  for (std::size_t k = 0; k < rig.joints.size(); ++k) {
    const Joint& j = rig.joints[k];
    int dof = 0;
    std::ostringstream kids;
    for (int c : j.children) {
      kids << " " << rig.bone_name[c] << "(" << info_dof(rig, c) << ")";
      dof += info_dof(rig, c);
    }
    std::cout << "    [" << k << "] " << joint_parent_name(rig, j) << " ->" << kids.str() << "  "
              << j.nbone() << " bones, " << dof << " DOF\n";
  }
  print_bone_frames(rig);
  print_rest_checks(rig, rest_checks(rig));
}

// options live as long as the app: each command owns its options through a shared_ptr
void add_info(CLI::App* rig) {
  struct InfoOptions {
    std::string path;
    bool json = false;
  };
  auto info_opt = std::make_shared<InfoOptions>();
  auto* info = rig->add_subcommand(
      "info",
      "Bones, joints, DOF per joint and total mass of a rig; the root's joint to the world (free, "
      "pinned with its limits, fixed); each bone's local axes in world at rest and its limits per "
      "axis, or the bone it is welded to; the bone pairs whose capsules overlap at rest and the "
      "limits whose torsion band holds the rest angle");
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
