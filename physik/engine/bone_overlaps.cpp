// Overlapping bone capsules (bone_overlaps.h), found by the contacts' own detection
// (contact_data.h contacts_at_pose).
#include "physik/engine/bone_overlaps.h"

#include <algorithm>
#include <map>

#include "physik/engine/contact_data.h"
#include "physik/model/scene.h"

namespace physik {

std::vector<BoneOverlap> bone_overlaps(const Rig& rig, const BoneFrames& frames,
                                       const std::vector<std::pair<int, int>>& scene_excluded) {
  // every pair that is not joint-sharing: a scene of the rig without its exclusions
  Scene scene;
  scene.rig = rig;
  scene.rig.collision_exclude.clear();
  scene.collision.self_collision = true;
  const std::vector<Contact> contacts = contacts_at_pose(scene, frames);
  std::map<std::pair<int, int>, double> deepest;
  for (const Contact& c : contacts) {
    if (c.other_bone < 0) continue;
    const std::pair<int, int> key{std::min(c.bone, c.other_bone), std::max(c.bone, c.other_bone)};
    double& d = deepest[key];
    d = std::max(d, c.depth);
  }
  std::vector<BoneOverlap> out;
  out.reserve(deepest.size());
  for (const auto& [pair, depth] : deepest) {
    BoneOverlap o;
    o.a = pair.first;
    o.b = pair.second;
    o.depth = depth;
    o.excluded = rig.collision_excluded(o.a, o.b) ||
                 std::binary_search(scene_excluded.begin(), scene_excluded.end(), pair);
    out.push_back(o);
  }
  return out;
}

std::vector<BoneOverlap> rest_overlaps(const Rig& rig) {
  return bone_overlaps(rig, forward_kinematics(rig, rest_pose(rig)));
}

std::vector<BoneOverlap> exclude_rest_overlaps(Rig& rig) {
  std::vector<BoneOverlap> added;
  for (const BoneOverlap& o : rest_overlaps(rig)) {
    if (o.excluded) continue;
    added.push_back(o);
    rig.collision_exclude.emplace_back(o.a, o.b);
  }
  std::sort(rig.collision_exclude.begin(), rig.collision_exclude.end());
  return added;
}

}  // namespace physik
