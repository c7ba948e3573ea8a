#include "physik/model/rig_generators.h"

#include <string>
#include <vector>

#include "physik/model/errors.h"

namespace physik {

Rig make_chain_rig(int nbone, double bone_length, double radius) {
  if (nbone < 1) throw_input_error("chain", "", "N", "a chain needs at least one bone");
  if (!(bone_length > 0.0)) throw_input_error("chain", "", "length", "must be positive");
  if (!(radius > 0.0)) throw_input_error("chain", "", "radius", "must be positive");
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

}  // namespace physik
