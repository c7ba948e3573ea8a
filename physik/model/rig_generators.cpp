#include "physik/model/rig_generators.h"

#include <cmath>
#include <string>
#include <vector>

#include "physik/model/errors.h"

namespace physik {

Rig make_chain_rig(int nbone, double bone_length, double radius) {
  if (nbone < 1) throw_input_error("chain", "", "N", "a chain needs at least one bone");
  // checked before anything is allocated: 2^31 bones would ask for about 600 GB
  if (nbone > kMaxBones) {
    throw_input_error("chain", "", "N",
                      std::to_string(nbone) + " bones, more than the " + std::to_string(kMaxBones) +
                          " a rig may have (rig.h kMaxBones)");
  }
  if (!(bone_length > 0.0) || !std::isfinite(bone_length)) {
    throw_input_error("chain", "", "length", "must be a positive finite number");
  }
  if (nbone * bone_length > kMaxCoordinate) {
    throw_input_error("chain", "", "length",
                      "the chain would reach beyond " + std::to_string(kMaxCoordinate) +
                          " rig units (rig.h kMaxCoordinate)");
  }
  if (!(radius > 0.0) || !std::isfinite(radius)) {
    throw_input_error("chain", "", "radius", "must be a positive finite number");
  }
  std::vector<BoneSpec> specs(nbone);
  for (int i = 0; i < nbone; ++i) {
    BoneSpec& s = specs[i];
    s.name = "b" + std::to_string(i);
    s.parent = i == 0 ? "" : "b" + std::to_string(i - 1);
    s.head_world = Vec3(0, 0, i * bone_length);
    s.tail_world = Vec3(0, 0, (i + 1) * bone_length);
    s.rest_frame_world = rest_frame_from_roll(s.head_world, s.tail_world, 0.0);
    s.mass = 1.0 * bone_length;  // mass_per_length 1, as the original
    s.radius = radius;
  }
  return build_rig(specs, "chain", "chain" + std::to_string(nbone));
}

Rig make_tree_rig(int nbone, int branching, double bone_length, double radius) {
  if (nbone < 1) throw_input_error("tree", "", "N", "a tree needs at least one bone");
  if (branching < 1) throw_input_error("tree", "", "branching", "must be at least 1");
  if (!(bone_length > 0.0)) throw_input_error("tree", "", "length", "must be positive");
  if (!(radius > 0.0)) throw_input_error("tree", "", "radius", "must be positive");
  const double lean = deg2rad(30.0);
  std::vector<BoneSpec> specs(nbone);
  std::vector<Vec3> dir(nbone);  // unit direction of every bone, world
  for (int i = 0; i < nbone; ++i) {
    BoneSpec& s = specs[i];
    s.name = "b" + std::to_string(i);
    if (i == 0) {
      dir[i] = Vec3::UnitZ();
      s.head_world = Vec3::Zero();
    } else {
      const int p = (i - 1) / branching, k = (i - 1) % branching;
      s.parent = specs[p].name;
      s.head_world = specs[p].tail_world;
      // lean away from the parent's direction about an axis normal to it, turned by 2 pi k / B
      const Vec3 normal = dir[p].unitOrthogonal();
      const Vec3 axis = Eigen::AngleAxisd(2.0 * kPi * k / branching, dir[p]) * normal;
      dir[i] = branching == 1 ? dir[p] : Vec3(Eigen::AngleAxisd(lean, axis) * dir[p]);
    }
    s.tail_world = s.head_world + bone_length * dir[i];
    s.rest_frame_world = rest_frame_from_roll(s.head_world, s.tail_world, 0.0);
    s.mass = 1.0 * bone_length;  // mass_per_length 1, as the original
    s.radius = radius;
  }
  return build_rig(specs, "tree", "tree" + std::to_string(nbone) + "b" + std::to_string(branching));
}

}  // namespace physik
