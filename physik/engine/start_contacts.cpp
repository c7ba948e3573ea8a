// The contacts a scene starts in (start_contacts.h): the initial pose's ground and obstacle
// contacts (contact_data.h contacts_at_pose), measured by its penetration().
#include "physik/engine/start_contacts.h"

#include <algorithm>
#include <vector>

#include "physik/engine/bone_overlaps.h"
#include "physik/engine/contact_data.h"
#include "physik/engine/ground_contacts.h"
#include "physik/model/errors.h"
#include "physik/model/message_number.h"

namespace physik {

namespace {

// "the ground" or "obstacle 'seat'"
std::string surface_name(const Scene& scene, const StartContact& c) {
  if (c.obstacle < 0) return "the ground";
  return "obstacle '" + scene.collision.obstacles[c.obstacle].name + "'";
}

// what to change to start clear of the surface
std::string surface_fix(const StartContact& c) {
  if (c.obstacle < 0)
    return "raise the rig (initial_pose.root_head) or lower the ground (ground.height)";
  return "move the rig (initial_pose.root_head) or the box (obstacles[" +
         std::to_string(c.obstacle) + "] box center) apart";
}

}  // namespace

StartContact deepest_start_contact(const Scene& scene) {
  StartContact out;
  if (!scene.collision.ground && scene.collision.obstacles.empty()) return out;
  std::vector<Contact> contacts =
      contacts_at_pose(scene, forward_kinematics(scene.rig, scene.initial_pose));
  // the static surfaces only: bones touching each other at the start are left alone
  contacts.erase(std::remove_if(contacts.begin(), contacts.end(),
                                [](const Contact& c) { return c.other_bone >= 0; }),
                 contacts.end());
  const Penetration pen = penetration(scene, contacts);
  out.contacts = pen.contacts;
  out.energy = ground_contact_potential(scene, contacts);
  for (const Contact& c : contacts) {
    const double fraction = c.depth / scene.rig.bone_collision_radius[c.bone];
    if (fraction < pen.max_depth_fraction) continue;  // the deepest, first in detection order
    out.bone = c.bone;
    out.obstacle = c.obstacle;
    out.depth = c.depth;
    out.fraction = fraction;
    break;
  }
  return out;
}

std::vector<BoneOverlap> start_bone_overlaps(const Scene& scene) {
  if (!scene.collision.self_collision) return {};
  std::vector<BoneOverlap> all = bone_overlaps(
      scene.rig, forward_kinematics(scene.rig, scene.initial_pose), scene.collision.excluded_pairs);
  all.erase(std::remove_if(all.begin(), all.end(), [](const BoneOverlap& o) { return o.excluded; }),
            all.end());
  return all;
}

std::string check_start_bone_overlaps(const Scene& scene) {
  const std::vector<BoneOverlap> overlaps = start_bone_overlaps(scene);
  if (overlaps.empty()) return "";
  std::string list;
  const std::size_t shown = std::min<std::size_t>(overlaps.size(), kStartOverlapsNamed);
  for (std::size_t i = 0; i < shown; ++i) {
    const BoneOverlap& o = overlaps[i];
    list += (i ? ", [\"" : "[\"") + scene.rig.bone_name[o.a] + "\", \"" + scene.rig.bone_name[o.b] +
            "\"] (" + message_number(o.depth) + ")";
  }
  if (shown < overlaps.size()) {
    list +=
        " and " + std::to_string(overlaps.size() - shown) + " more (`physik rig info` lists all)";
  }
  return std::to_string(overlaps.size()) +
         (overlaps.size() == 1 ? " bone pair overlaps" : " bone pairs overlap") +
         " at the start under self_collision (depth in rig units): " + list +
         "; their contact springs push them apart from the first step, so the rig moves with no "
         "target pulling it: add the pairs to collision_exclude (the scene's, or the rig's for "
         "every scene)";
}

std::string check_start_contacts(const Scene& scene) {
  const std::string surface = check_start_surface_contacts(scene);
  const std::string bones = check_start_bone_overlaps(scene);
  if (surface.empty() || bones.empty()) return surface + bones;
  return surface + "; and " + bones;
}

std::string check_start_surface_contacts(const Scene& scene) {
  const StartContact c = deepest_start_contact(scene);
  if (c.bone < 0 || c.fraction <= kStartContactWarnFraction) return "";
  const double radius = scene.rig.bone_collision_radius[c.bone];
  const std::string what = "bone '" + scene.rig.bone_name[c.bone] + "' starts " +
                           message_number(c.depth) + " rig units into " + surface_name(scene, c) +
                           ", " + message_number(c.fraction) + " times its collision radius " +
                           message_number(radius);
  // a small tolerance: a root joint placed exactly on the ground is d = r up to round-off
  if (c.fraction > 1.0 + 1e-9) {
    throw_input_error(scene.file,
                      c.obstacle < 0 ? "ground" : "obstacles[" + std::to_string(c.obstacle) + "]",
                      c.obstacle < 0 ? "height" : "box",
                      what +
                          ": its centre line is past the surface, and the contact spring would "
                          "throw the rig out with " +
                          message_number(c.energy) + " J; " + surface_fix(c));
  }
  return what + " (more than " + message_number(kStartContactWarnFraction) +
         " times, the contacts' target depth at rest): the contact springs start with " +
         message_number(c.energy) + " J (k d^2 / 2), which push the rig out in the first steps; " +
         surface_fix(c);
}

}  // namespace physik
