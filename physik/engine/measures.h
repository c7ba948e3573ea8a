// Measures of a state, each written once: the step's stats, the run monitor, the posing session,
// the recorder and the experiments call these (as MuJoCo keeps mj_energyPos / mj_energyVel apart
// from mj_step).
//
//   kinetic energy      KE = sum_b 1/2 m_b |v_b|^2 + 1/2 w_b^T I_b w_b        (J; v at the centre
//                       of mass, I_b the world inertia about it)
//   control residual    r_c = |a_c - g_c|: control point c's attachment a_c (a point on its bone,
//                       world) to its goal target g_c (not the interpolated one), rig units
//   goal residual       the largest of the control residuals and the turning targets' arcs: an
//                       orientation target's |phi| and an aim's theta times the bone's length L
//                       (how far the turn leaves the bone's tail from where the target would lay
//                       it), rig units; pins hold a point rather than reach for one (a loaded pin
//                       gives way by |F| / k by design) and have none
//   joint separation    max over joints of |head_child - (head_parent + R_parent h_child)|: how far
//                       a child's head is from its joint on the parent, and an anchored root's
//                       head from its rest position, rig units (0 unless the scheme integrates
//                       free rods)
//   centre of mass      a bone's is its midpoint (a uniform rod), world, rig units
//   state hash          FNV-1a over the bit patterns of every head, tail and orientation
#pragma once

#include <cstdint>
#include <vector>

#include "physik/engine/run_summary.h"
#include "physik/engine/state.h"
#include "physik/model/scene.h"

namespace physik {

double kinetic_energy(const Rig& rig, const SimState& state);
double max_joint_separation(const Rig& rig, const BoneFrames& frames);

// r_c of one control point, against the state's goal target.
double control_residual(const Scene& scene, const SimState& state, int c);
// r_c of every control point (out sized to the scene's; no allocation once it is).
void control_residuals(const Scene& scene, const SimState& state, std::vector<double>& out);
// max_c r_c; 0 without control points; NaN when any residual is NaN.
double max_control_residual(const Scene& scene, const SimState& state);
// The goal residual: max_control_residual and every orientation target's and aim's arc (the
// step's max_residual, which the IK stop rule reads); NaN when any is NaN.
double max_goal_residual(const Scene& scene, const SimState& state);
// The orientation targets' and aims' largest arc at `frames`, rig units (0 without them).
double max_turning_arc(const Scene& scene, const BoneFrames& frames);

// The bone targets' residuals at `frames`: an orientation target's turn |phi| and an aim's theta
// (rad), a pin's point from its world point (rig units).
double orientation_residual(const BoneFrames& frames, const OrientationTarget& target);
double aim_residual(const BoneFrames& frames, const AimTarget& target);
double pin_residual(const BoneFrames& frames, const Pin& pin);

// A bone's centre of mass: its midpoint.
inline Vec3 bone_centre_world(const BoneFrames& frames, int bone) {
  return 0.5 * (frames.head_world[bone] + frames.tail_world[bone]);
}

// The stats of a state no step has produced yet (the initial one): its kinetic energy, residuals
// and joint separation; no passes, no mismatch.
StepStats initial_stats(const Scene& scene, const SimState& state);

// Equal hashes mean bit-identical frames (determinism made visible, as Jolt prints a state hash).
std::uint64_t state_hash(const BoneFrames& frames);

}  // namespace physik
