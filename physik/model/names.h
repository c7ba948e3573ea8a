// Names (bones, joints, control points) travel into every format the testbed writes: JSON (which
// must be valid UTF-8), BVH (one joint per line, names end at whitespace or a brace) and CSV
// (columns named after bones). A name is accepted at the edge where it is read when it is valid
// UTF-8 (RFC 3629: shortest form, no surrogates, at most U+10FFFF) and holds no control character
// (U+0000-U+001F, U+007F), so no writer can fail or split a line on it later. Characters that a
// format reserves (a quote in CSV, '<' in XML) are escaped by that format's writer.
#pragma once

#include <string>
#include <vector>

namespace physik {

struct Rig;

// "" when `name` is acceptable, else the reason, e.g. "byte 0xff at offset 3 is not UTF-8".
std::string name_problem(const std::string& name);

// True when `text` is valid UTF-8 (control characters allowed).
bool valid_utf8(const std::string& text);

// The name of `known` nearest to `name` by edit distance (Levenshtein, case-sensitive) when it is
// close enough to be a typo (at most a third of its letters, two at least), else "": the "did you
// mean" of a message. Ties go to the first in `known`.
std::string nearest_name(const std::string& name, const std::vector<std::string>& known);

// " (did you mean 'x'?)" for nearest_name's answer, or "" when none is close.
std::string did_you_mean(const std::string& name, const std::vector<std::string>& known);

// "unknown bone 'x'" with did_you_mean's hint among `bones` (a rig's bone_name): the reason every
// message gives for a bone name the rig does not have.
std::string unknown_bone(const std::string& name, const std::vector<std::string>& bones);

// The same for a name `rig` has no bone of, with a typo's "did you mean" among its bones; for a
// joint of its source skeleton that has no bone of its own (its children all sit at its origin,
// source_skeleton.h), which bones stand at that joint instead: the bone whose tail is its origin
// (alpha 1) and the bones that start there. (Defined in rig.cpp.)
std::string unknown_bone(const std::string& name, const Rig& rig);

}  // namespace physik
