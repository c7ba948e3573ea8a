// Pose tables as CSV, the one format every experiment and the analysis scripts share.
//
// A bones table has one row per bone: name, parent, head_x..z, tail_x..z (world, rig units).
// A trajectory table has one row per recorded step; bone columns are named
// "<bone>.head_x" ... "<bone>.tail_z" (world, rig units) after any leading columns.
// Names that hold a comma, a quote or a line break are quoted as RFC 4180 says ("a,b" ->
// "\"a,b\"", a quote doubled), so every row keeps its column count.
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "physik/model/kinematics.h"

namespace physik {

void write_bones_csv(const Rig& rig, const BoneFrames& frames, std::ostream& out);

// A CSV field: `text`, quoted when it needs to be (RFC 4180).
std::string csv_field(const std::string& text);

// The six column names of every bone, in bone order, for trajectory tables (CSV-quoted).
std::vector<std::string> bone_column_names(const Rig& rig);
// The six values of every bone (head then tail, x y z), in the order of bone_column_names.
void append_bone_values(const BoneFrames& frames, std::vector<double>& row);

}  // namespace physik
