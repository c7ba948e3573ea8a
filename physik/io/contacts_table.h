// The contacts table of a run folder (contacts.csv): the contacts the engine's force stage found
// (SimState::contact, contact_data.h; detection collision.h), one row per contact per recorded row
// of trajectory.csv. Written only for a scene with a ground or self-collision; a recorded row
// without a contact has no row here.
//
//   step,time,bone,other_bone,point_x,point_y,point_z,normal_x,normal_y,normal_z,depth,
//   normal_force
//
//   step, time      the trajectory row's step and time (s)
//   bone            body a: the bone's index in the rig (scene.json's bones, in order)
//   other_bone      body b: a bone's index, or -1 for the ground
//   point_*         world, rig units: midway between the two surfaces
//   normal_*        world, unit, from body b toward body a
//   depth           rig units, > 0: how far the two shapes overlap
//   normal_force    N: F_n = max(0, k d - c v_n) of the force stage (0 while the damper holds it)
// The contacts of a row are those of the last force stage of the step that ended there (found at
// that step's start, or its last substep's under the implicit scheme's energy guard): the ones
// that acted on the motion into that row. Step 0, before any step, has none. 9 significant
// digits.
#pragma once

#include <ostream>

#include "physik/engine/state.h"

namespace physik {

// The file's name in a run folder.
inline constexpr const char* kContactsFile = "contacts.csv";

// The table's columns, in order.
inline constexpr const char* kContactsColumns[] = {
    "step",    "time",     "bone",     "other_bone", "point_x", "point_y",
    "point_z", "normal_x", "normal_y", "normal_z",   "depth",   "normal_force"};

class ContactsCsv {
 public:
  // Writes the header to `out`, which must outlive the writer.
  explicit ContactsCsv(std::ostream& out);
  // The rows of the state's contacts (none when it has none); a contact with a value that is not
  // finite is left out. Returns the rows written.
  int write_rows(const SimState& state);

 private:
  std::ostream& out_;
};

}  // namespace physik
