// Bone capsules that overlap each other in a pose: the self-contacts a rig starts with. Under
// `self_collision` every such pair is a contact spring compressed by its depth d from the first
// step (self_contacts.h: potential k d^2 / 2), so a rig whose capsules overlap at rest does not
// stay at rest. Converters exclude the pairs that overlap at rest (as Unreal's physics assets and
// PhysX articulations disable collision between overlapping bodies), `rig info` lists them and
// `physik simulate` warns about the ones a scene starts in (start_contacts.h).
//
// A pair is two bones whose capsules (segment head-tail, radius Rig::bone_collision_radius)
// are closer than the sum of their radii, measured by the engine's own detection
// (collision.h: FCL's capsule-capsule distance), depth d = r_a + r_b - |closest points| > 0.
// Bones that share a joint (Rig::bones_share_joint) never collide and are never listed.
// Units: rig units.
#pragma once

#include <utility>
#include <vector>

#include "physik/model/kinematics.h"
#include "physik/model/rig.h"

namespace physik {

struct BoneOverlap {
  int a = -1, b = -1;     // bones, a < b
  double depth = 0.0;     // rig units, > 0: the deepest contact between the two capsules
  bool excluded = false;  // in the rig's collision_exclude or the given scene exclusions
};

// Every overlapping pair at `frames` (bones sharing a joint left out), in order of (a, b).
// `scene_excluded`: further pairs (lower, higher index) to mark as excluded.
std::vector<BoneOverlap> bone_overlaps(const Rig& rig, const BoneFrames& frames,
                                       const std::vector<std::pair<int, int>>& scene_excluded = {});

// The same at the rig's rest pose.
std::vector<BoneOverlap> rest_overlaps(const Rig& rig);

// Adds every pair that overlaps at rest to rig.collision_exclude and returns those pairs (the
// ones it was not already excluding).
std::vector<BoneOverlap> exclude_rest_overlaps(Rig& rig);

}  // namespace physik
