// The rigs and targets of ik_comparison: see ik_cases.h.
#include "experiments/ik_cases.h"

#include <array>
#include <cmath>
#include <random>
#include <string>
#include <utility>

#include "experiments/common.h"
#include "physik/ik/ik_solver.h"
#include "physik/io/rig_io.h"
#include "physik/model/rig_generators.h"

namespace physik::experiments {

std::vector<RigCase> make_ik_rigs(const std::string& models_dir, bool without_chain50) {
  std::vector<RigCase> rigs;
  for (int n : {3, 10, 50}) {
    if (without_chain50 && n == 50) continue;
    RigCase rc;
    rc.rig = make_chain_rig(n);
    rc.name = "chain" + std::to_string(n);
    rc.bone = n - 1;
    rc.chain = true;
    rigs.push_back(rc);
  }
  RigCase pinhead;
  pinhead.rig = load_rig(models_dir + "/rigs/pinhead.json");
  pinhead.name = "pinhead";
  pinhead.bone = pinhead.rig.find_bone("hand.L");
  rigs.push_back(pinhead);
  for (RigCase& rc : rigs) rc.reach = chain_reach(rc.rig, {{rc.bone, 1.0, Vec3::Zero()}});
  return rigs;
}

namespace {

// one bone of the figure: its head at its parent's tail (the joint), its tail `to`, its limits
// per local axis x, y, z ({lo, hi} rad; lo == hi locks the axis; {1, -1}: free)
struct FigureBone {
  std::string name, parent;
  Vec3 to;
  std::array<std::pair<double, double>, 3> limit;
};

constexpr std::pair<double, double> kFree{1.0, -1.0};

void add_figure_bone(std::vector<BoneSpec>& specs, const FigureBone& b) {
  BoneSpec s;
  s.name = b.name;
  s.parent = b.parent;
  s.head_world = Vec3::Zero();
  for (const BoneSpec& p : specs) {
    if (p.name == b.parent) s.head_world = p.tail_world;
  }
  s.tail_world = b.to;
  s.rest_frame_world = rest_frame_from_roll(s.head_world, s.tail_world, 0.0);
  for (int a = 0; a < 3; ++a) {
    const auto [lo, hi] = b.limit[a];
    if (lo <= hi) s.limit[a] = AxisLimit{true, lo, hi};
  }
  s.mass = (s.tail_world - s.head_world).norm();  // 1 per unit length, as the original
  s.radius = 0.05;
  specs.push_back(s);
}

// a chain of bones from `parent` through the points, each with the same limits
void add_figure_chain(std::vector<BoneSpec>& specs, const std::string& prefix,
                      const std::string& parent, const std::vector<Vec3>& points,
                      const std::array<std::pair<double, double>, 3>& limit) {
  std::string up = parent;
  for (std::size_t k = 0; k < points.size(); ++k) {
    const std::string name = prefix + std::to_string(k + 1);
    add_figure_bone(specs, {name, up, points[k], limit});
    up = name;
  }
}

void add_figure_arm(std::vector<BoneSpec>& specs, const std::string& side, double x) {
  const std::pair<double, double> locked{0.0, 0.0};
  add_figure_bone(
      specs,
      {"clavicle" + side, "spine7", {0.17 * x, 0, 1.46}, {{{-0.2, 0.2}, locked, {-0.3, 0.3}}}});
  add_figure_bone(specs, {"upperarm" + side,
                          "clavicle" + side,
                          {0.19 * x, 0, 1.18},
                          {{{-2.5, 2.5}, {-1.5, 1.5}, {-2.5, 2.5}}}});
  add_figure_bone(
      specs,
      {"forearm" + side, "upperarm" + side, {0.19 * x, 0, 1.06}, {{{0.0, 2.5}, locked, locked}}});
  add_figure_bone(specs, {"forearm_twist" + side,
                          "forearm" + side,
                          {0.19 * x, 0, 0.94},
                          {{locked, {-1.3, 1.3}, locked}}});
  add_figure_bone(specs, {"hand" + side,
                          "forearm_twist" + side,
                          {0.19 * x, 0, 0.86},
                          {{{-1.0, 1.0}, locked, {-0.5, 0.5}}}});
  const char* fingers[5] = {"thumb", "index", "middle", "ring", "pinky"};
  for (int f = 0; f < 5; ++f) {
    const double fx = (0.19 + 0.012 * (f - 2)) * x, fy = f == 0 ? -0.03 : -0.01 * (2 - f) / 2.0;
    const Vec3 base(fx, fy, 0.86);
    add_figure_bone(specs, {std::string(fingers[f]) + "0" + side,
                            "hand" + side,
                            base + Vec3(0.004 * x, 0, -0.045),
                            {{{-0.2, 0.2}, locked, {-0.2, 0.2}}}});
    const Vec3 start = base + Vec3(0.004 * x, 0, -0.045);
    add_figure_chain(
        specs, std::string(fingers[f]) + side + ".", std::string(fingers[f]) + "0" + side,
        {start + Vec3(0, 0, -0.035), start + Vec3(0, 0, -0.060), start + Vec3(0, 0, -0.080)},
        {{{0.0, 1.5}, locked, locked}});
  }
}

void add_figure_leg(std::vector<BoneSpec>& specs, const std::string& side, double x) {
  const std::pair<double, double> locked{0.0, 0.0};
  add_figure_bone(
      specs,
      {"pelvis" + side, "hips", {0.1 * x, 0, 1.0}, {{{-0.1, 0.1}, {-0.1, 0.1}, {-0.1, 0.1}}}});
  add_figure_bone(specs, {"thigh" + side,
                          "pelvis" + side,
                          {0.1 * x, 0, 0.55},
                          {{{-1.6, 0.5}, {-0.7, 0.7}, {-0.7, 0.7}}}});
  add_figure_bone(
      specs, {"shin" + side, "thigh" + side, {0.1 * x, 0, 0.1}, {{{0.0, 2.4}, locked, locked}}});
  add_figure_bone(
      specs,
      {"foot" + side, "shin" + side, {0.1 * x, -0.12, 0.03}, {{{-0.7, 0.7}, locked, {-0.3, 0.3}}}});
  add_figure_bone(
      specs,
      {"toe" + side, "foot" + side, {0.1 * x, -0.18, 0.03}, {{{-0.6, 0.6}, locked, locked}}});
}

}  // namespace

Rig make_figure_rig() {
  std::vector<BoneSpec> specs;
  const std::pair<double, double> locked{0.0, 0.0}, spine{-0.2, 0.2}, neck{-0.4, 0.4};
  add_figure_bone(specs, {"hips", "", {0, 0, 1.1}, {{kFree, kFree, kFree}}});
  specs[0].head_world = Vec3(0, 0, 1.0);
  specs[0].rest_frame_world = rest_frame_from_roll(specs[0].head_world, specs[0].tail_world, 0.0);
  std::vector<Vec3> spine_points, neck_points;
  for (int k = 1; k <= 7; ++k) spine_points.push_back({0, 0, 1.1 + 0.05 * k});
  add_figure_chain(specs, "spine", "hips", spine_points, {{spine, spine, spine}});
  for (int k = 1; k <= 3; ++k) neck_points.push_back({0, 0, 1.45 + 0.05 * k});
  add_figure_chain(specs, "neck", "spine7", neck_points, {{neck, neck, neck}});
  add_figure_bone(specs,
                  {"head", "neck3", {0, 0, 1.85}, {{{-0.6, 0.6}, {-0.8, 0.8}, {-0.6, 0.6}}}});
  add_figure_bone(specs, {"jaw", "head", {0, -0.09, 1.78}, {{{0.0, 0.4}, locked, locked}}});
  add_figure_bone(specs,
                  {"eye.L", "head", {0.03, -0.1, 1.86}, {{{-0.5, 0.5}, locked, {-0.5, 0.5}}}});
  add_figure_bone(specs,
                  {"eye.R", "head", {-0.03, -0.1, 1.86}, {{{-0.5, 0.5}, locked, {-0.5, 0.5}}}});
  add_figure_arm(specs, ".L", 1.0);
  add_figure_arm(specs, ".R", -1.0);
  add_figure_leg(specs, ".L", 1.0);
  add_figure_leg(specs, ".R", -1.0);
  return build_rig(specs, "figure", "figure75");
}

Targets make_ik_targets(const RigCase& rc, int n_reach, int n_unreach, int n_cont) {
  std::mt19937 rng(20240607);
  Targets t;
  const Vec3 root = rc.rig.bone_rest_head_world[0];
  for (int k = 0; k < n_reach; ++k) {
    if (rc.chain) {
      const double r =
          0.95 * rc.reach * std::cbrt(std::uniform_real_distribution<double>(0, 1)(rng));
      t.reach.push_back(root + r * random_direction(rng));
    } else {
      t.reach.push_back(
          forward_kinematics(rc.rig, random_legal_pose(rc.rig, rng)).tail_world[rc.bone]);
    }
  }
  for (int k = 0; k < n_unreach; ++k) {
    const double r = rc.reach * std::uniform_real_distribution<double>(1.1, 2.0)(rng);
    t.unreach.push_back(root + r * random_direction(rng));
  }
  for (int k = 0; k < n_cont; ++k) t.moves.push_back(0.01 * rc.reach * random_direction(rng));
  return t;
}

}  // namespace physik::experiments
