#include "physik/engine/contact_data.h"

#include <algorithm>

namespace physik {

void prepare_contact_data(const Scene& scene, ContactData& d) {
  if (!scene.collision.any()) return;
  // the FCL objects and room for the contacts now, so the steps allocate nothing: two ends per
  // bone on the ground, three per bone and obstacle (the ends and an edge), and as many bone pairs
  // again as ground contacts (more only in a tangled rig)
  d.world.prepare(scene);
  const std::size_t room =
      (4 + 3 * scene.collision.obstacles.size()) * static_cast<std::size_t>(scene.rig.nbone);
  d.found.reserve(room);
  d.elements.reserve(room);
  d.at_frames.reserve(room);
  d.reached.reserve(room);
  d.anchors.reserve(room);
  d.anchors_next.reserve(room);
  d.self_count.assign(scene.rig.nbone, 0);
}

void detect_contacts(const Scene& scene, const BoneFrames& frames, ContactData& d,
                     std::vector<Contact>& out) {
  d.world.detect(scene, frames, out);
}

void detect_step_contacts(const Scene& scene, const BoneFrames& frames, ContactData& d) {
  d.elements.clear();
  d.found.clear();
  if (!scene.collision.any()) return;
  d.world.detect(scene, frames, d.found);
  if (!scene.collision.self_collision) return;
  // a state built otherwise than by init_state gets its counts sized here, once
  if (d.self_count.size() != static_cast<std::size_t>(scene.rig.nbone)) {
    d.self_count.assign(scene.rig.nbone, 0);
  }
  std::fill(d.self_count.begin(), d.self_count.end(), 0);
  for (const Contact& c : d.found) {
    if (c.other_bone < 0) continue;
    ++d.self_count[c.bone];
    ++d.self_count[c.other_bone];
  }
}

std::vector<Contact> contacts_at_pose(const Scene& scene, const BoneFrames& frames) {
  CollisionWorld world;
  std::vector<Contact> out;
  world.detect(scene, frames, out);
  return out;
}

Penetration penetration(const Scene& scene, const std::vector<Contact>& contacts) {
  Penetration out;
  const std::vector<double>& r = scene.rig.bone_collision_radius;
  for (const Contact& c : contacts) {
    ++out.contacts;
    const double radius = c.other_bone >= 0 ? std::min(r[c.bone], r[c.other_bone]) : r[c.bone];
    out.max_depth = std::max(out.max_depth, c.depth);
    out.max_depth_fraction = std::max(out.max_depth_fraction, c.depth / radius);
  }
  return out;
}

Penetration penetration(const Scene& scene, const BoneFrames& frames, ContactData& d) {
  detect_contacts(scene, frames, d, d.at_frames);
  return penetration(scene, d.at_frames);
}

}  // namespace physik
