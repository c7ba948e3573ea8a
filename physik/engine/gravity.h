// Gravity: m_i g at every bone's centre of mass c_i (nothing when gravity is zero, as in the
// paper), and its potential
//   U_gravity = -sum m_i g . (c_i - x_0)
// x_0 the ground's point nearest the origin (U >= 0 above a ground that gravity points into) or,
// without a ground, the initial pose's root head. Constant in the pose's velocities and a
// constant force at each centre: no implicit term (its stiffness is 0; the implicit step takes
// it as it is), nothing for damping auto's modes. MuJoCo's reference applies its own
// (<option gravity>, mjcf_export.h). Units: N, rig units/s^2, J.
#pragma once

#include "physik/engine/state.h"
#include "physik/model/scene.h"

namespace physik {

void apply_gravity(const Scene& scene, SimState& state);

// x_0 of U_gravity (above).
Vec3 gravity_reference(const Scene& scene);
// U_gravity of a pose's frames (0 when gravity is zero), J.
double gravity_potential(const Scene& scene, const BoneFrames& frames);

}  // namespace physik
