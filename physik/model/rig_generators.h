// Generated rigs for tests and scaling studies (no file involved).
#pragma once

#include "physik/model/rig.h"

namespace physik {

// A straight chain of n bones of the given length along world +Z from the origin, all free.
// Mass per length 1 (kg per rig unit), cylinders of `radius` (rig units), as the original code.
Rig make_chain_rig(int nbone, double bone_length = 1.0, double radius = 0.5);

}  // namespace physik
