#include "physik/engine/potential.h"

#include "physik/engine/contact_data.h"
#include "physik/engine/forces.h"
#include "physik/engine/measures.h"
#include "physik/model/kinematics.h"

namespace physik {

double potential_energy(const Scene& scene, SimState& s, PotentialOf which) {
  if (scene.collision.any()) {
    detect_contacts(scene, s.frames, s.contact, s.contact.at_frames);
  }
  double u = 0.0;
  for (const ForceElement& e : force_elements()) {
    if (!e.potential) continue;  // a damper: no potential
    if (which == PotentialOf::kAllButTargetSprings && e.toward_targets) continue;
    u += e.potential(scene, s);
  }
  return u;
}

SimState state_at_pose(const Scene& scene, const Pose& pose,
                       const std::vector<Vec3>& targets_world) {
  SimState s;
  size_state(scene, s);
  s.pose = pose;
  s.frames = forward_kinematics(scene.rig, pose);
  for (int i = 0; i < scene.rig.nbone; ++i) {
    s.com_world[i] = bone_centre_world(s.frames, i);
  }
  for (std::size_t c = 0; c < targets_world.size() && c < s.target_effective_world.size(); ++c) {
    s.target_effective_world[c] = targets_world[c];
  }
  return s;
}

double initial_potential_energy(const Scene& scene) {
  SimState s = state_at_pose(scene, scene.initial_pose, {});
  return potential_energy(scene, s, PotentialOf::kAllButTargetSprings);
}

}  // namespace physik
