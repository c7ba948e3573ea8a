// The contacts a scene starts in: a rig whose initial pose already sinks into the ground or into
// an obstacle. The contact spring books such an overlap d as potential energy k d^2 / 2
// (ground_contacts.h), and the first steps turn it into kinetic energy: a rig started through the
// floor is thrown out of it. `physik simulate`, `physik solve --solver physik|physik-explicit` and
// `physik tune` check the start with this before they run, and so does the Python module
// (Simulation, run_scene, PosingSession, solve with an engine solver, tune: python/bind_common.h).
//
// Rule, with d the depth of the start's deepest contact with the ground or an obstacle (the
// deepest as a fraction of its bone's collision radius r; collision.h measures it):
//   d / r <= kStartContactWarnFraction   nothing: a bone resting on the floor sinks by W / k, and
//                                        the contacts experiment's target at rest is 5% of r,
//                                        so a start up to that is a start at rest
//   up to d / r = 1                      a warning: a legitimate start (a foot placed into the
//                                        floor, a rig whose root joint sits on it: d = r), but
//                                        the run begins by pushing the bone out
//   d / r > 1                            bad input (InputError, exit 2): the bone's centre line
//                                        is past the surface, inside the floor or the box; the
//                                        spring's k d^2 / 2 is then at least k r^2 / 2 per
//                                        contact (50 J at the default k and r = 0.1) and launches
//                                        the rig
// Bones overlapping each other at the start are checked under `self_collision` only: every pair
// whose capsules overlap (bone_overlaps.h) and that neither the scene's nor the rig's
// collision_exclude names is a contact spring compressed from the first step, so the rig moves
// with no target pulling it (a converted MuJoCo humanoid's torso and lower waist).
// Such a start is legitimate (a hand resting on a hip) but is named in a warning with what to
// change (collision_exclude), never refused.
// Units: rig units, J.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "physik/engine/bone_overlaps.h"
#include "physik/model/scene.h"

namespace physik {

inline constexpr double kStartContactWarnFraction = 0.05;  // 1, of the bone's collision radius

// The deepest contact of the initial pose with the ground or an obstacle.
struct StartContact {
  int contacts = 0;       // the start's contacts with the ground and the obstacles
  int bone = -1;          // the deepest one's bone (-1: no contact)
  int obstacle = -1;      // its obstacle's index, -1 for the ground
  double depth = 0.0;     // rig units
  double fraction = 0.0;  // 1, of the bone's collision radius
  double energy = 0.0;    // J, U_contact of all those contacts (ground_contacts.h)
};
StartContact deepest_start_contact(const Scene& scene);

// The rule above: "" for a start at rest (or a scene without a ground or obstacles), the warning
// (naming the bone, its depth, the surface and what to change) for a risky one; an InputError
// naming the scene file and the surface's field for a bone whose centre line is past it.
std::string check_start_surface_contacts(const Scene& scene);

// The bone pairs that overlap at the start under self_collision and that no collision_exclude
// names (none without self_collision), and the warning naming them ("" for none; the first
// kStartOverlapsNamed pairs are named, the count of the rest given).
inline constexpr std::size_t kStartOverlapsNamed = 10;
std::vector<BoneOverlap> start_bone_overlaps(const Scene& scene);
std::string check_start_bone_overlaps(const Scene& scene);

// Both checks: the surface's warning (or its InputError) and the bone pairs', joined by "; and ".
std::string check_start_contacts(const Scene& scene);

}  // namespace physik
