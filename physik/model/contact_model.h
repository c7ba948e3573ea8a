// The contact model: what a scene's bones touch, beside the Rig and the Scene (the contacts'
// data, what a run finds and carries, is physik/engine/contact_data.h). Its parts:
//   ground          an optional plane, bodies on the side its normal points to
//   obstacles       static boxes (a seat, a table), fixed in the world
//   self_collision  the bones' capsules against each other, but pairs that share a joint or a
//                   welded body (Rig::bones_share_joint), the scene's excluded pairs and the
//                   rig's (Rig::collision_exclude)
//   radii           each bone's capsule, Rig::bone_collision_radius
// The force laws and their coefficients (contact_k, contact_damping, friction, friction_speed,
// friction_stiffness: the parameter table, params.h) are the contact forces' own:
// physik/engine/ground_contacts.h and self_contacts.h. None of it by default: a scene without
// them runs exactly as before. Units: rig units.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "physik/model/types.h"

namespace physik {

struct GroundPlane {
  Vec3 normal_world = Vec3::UnitZ();  // unit; bodies belong on the side it points to
  double height = 0.0;                // rig units: the plane is {x : normal . x = height}
};

// A static box (a seat, a table): fixed in the world, it only pushes bones out (collision.h).
struct BoxObstacle {
  std::string name;                      // unique within the scene
  Vec3 center_world = Vec3::Zero();      // rig units
  Vec3 half_extents = Vec3::Ones();      // rig units, > 0, along the box's own x, y, z axes
  Quat orient_world = Quat::Identity();  // the box's axes in the world frame
};

struct ContactModel {
  std::optional<GroundPlane> ground;
  std::vector<BoxObstacle> obstacles;  // static boxes, in the order the scene lists them
  bool self_collision = false;  // bone capsules against each other (bones sharing a joint never)
  // further bone pairs that never collide, each (lower index, higher index), sorted, unique
  std::vector<std::pair<int, int>> excluded_pairs;
  // anything to touch: the contact stage runs at all
  bool any() const { return ground.has_value() || !obstacles.empty() || self_collision; }
};

}  // namespace physik
