// The JSON rig format (documented in models/README.md):
//
// {
//   "name": "pinhead",                              optional
//   "root": "free" | "pinned" | "fixed",            optional (free): the root's joint to the world
//   "comment": "...", "units": "...",                optional free text, kept
//   "source": "..." | ["...", ...],                 optional notes (a converter's), kept
//   "defaults": {"mass_per_length": 1.0, "radius": 0.5,    optional, for every bone that
//                "collision_radius": 0.05},                names no value of its own
//   "bones": [
//     {"name": "torso", "parent": "head" | null,     required; exactly one null (the root)
//      "head": [x, y, z], "tail": [x, y, z],        world rest positions, rig units
//      "rest_frame": [[xx,xy,xz],[yx,yy,yz],[zx,zy,zz]]  bone x, y, z axes in world, or
//      "roll_deg": 0.0,                             Blender roll about the bone (default 0)
//      "limits_deg": {"x": [min, max], "z": [..]},  absent axis = free, min == max = locked
//      "mass_per_length": 1.0 | "mass": 1.36,       kg per rig unit, or kg in total
//      "radius": 0.5,                               rig units, for the cylinder inertia
//      "inertia_local": [Ixx, Iyy, Izz],            optional kg m^2 about the bone's centre,
//                                                   bone-local axes; replaces the cylinder's
//      "collision_radius": 0.05,                    optional rig units, the contact capsule's
//                                                   (default 0.06 x the bone's length)
//      "weld": "torso"}                             optional: welded to its parent or to a
//                                                   sibling listed before it (no limits then)
//   ],
//   "collision_exclude": [["a", "b"], ...]          optional bone pairs that never collide
//   "source_skeleton": {...}                         optional: the skeleton a converter read
//                                                    (source_skeleton_io.h)
// }
#pragma once

#include <string>

#include "physik/io/json_fields.h"
#include "physik/model/rig.h"

namespace physik {

Rig load_rig(const std::string& path);
Rig rig_from_json(const Json& doc, const std::string& source);
Rig rig_from_json_text(const std::string& text, const std::string& source);

// Writes the rig back in the same format (explicit rest frames, total masses, limits in deg): the
// radius most bones share, and a collision radius most bones share, once in "defaults" (each
// bone names only the values that differ), the notes and the exclusions; reading it back gives
// the same rig.
Json rig_to_json(const Rig& rig);

}  // namespace physik
