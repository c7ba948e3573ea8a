// Generated rigs for tests and scaling studies (no file involved).
#pragma once

#include "physik/model/rig.h"

namespace physik {

// A straight chain of n bones of the given length along world +Z from the origin, all free.
// Mass per length 1 (kg per rig unit), cylinders of `radius` (rig units), as the original code.
Rig make_chain_rig(int nbone, double bone_length = 1.0, double radius = 0.5);

// A balanced tree of n bones: bone k's children are bones B k + 1 .. B k + B (breadth-first
// numbering, so every level is full but the last) and their heads meet at its tail, giving
// depth ceil(log_B((B - 1) n + 1)). The root runs along world +Z from the origin; each child
// leans 30 deg away from its parent's direction, the B children spread evenly around it.
// Mass per length 1, cylinders of `radius`, all free. B = 1 is the chain.
Rig make_tree_rig(int nbone, int branching, double bone_length = 1.0, double radius = 0.5);

}  // namespace physik
