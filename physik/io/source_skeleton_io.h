// The rig file's "source_skeleton" (models/README.md "BVH and qBVH"; source_skeleton.h):
//
//   "source_skeleton": {
//     "format": "bvh", "axes": "y-up" | "z-up", "scale": 0.01,   rig units per file unit
//     "joints": [
//       {"name": "Hips",                              the root: no parent; the others
//        "parent": 0,                                 an earlier joint's index
//        "offset": [0, 95, 0],                        file units and axes, in the parent's frame
//        "channels": ["Xposition", ..., "Yrotation"], in file order
//        "end_sites": [[0, -6, 14]],                  optional, file units, this joint's frame
//        "bones": ["Hips", "Hips>Spine"]}             the rig bones turning with it, the first
//     ]}                                              carrying it (optional: none)
#pragma once

#include <string>

#include "physik/io/json_fields.h"
#include "physik/model/rig.h"

namespace physik {

// Reads doc["source_skeleton"] into rig.source_skeleton (absent: left empty) and checks it
// against the rig (check_source_skeleton); InputError naming `source` and the field.
void read_source_skeleton(const Json& doc, const std::string& source, Rig& rig);

// The rig's source skeleton as JSON (the rig must have one).
Json source_skeleton_to_json(const Rig& rig);

}  // namespace physik
