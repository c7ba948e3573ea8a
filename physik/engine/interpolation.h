// Target interpolation after a target jump (paper Sec. 3.5, eq. 12).
//
// When a control point's target jumps from t_old to t_new, the spring pulls toward an effective
// target t_i that moves there over i_max steps; afterwards t = t_new.
//   linear:  t_{i+1} = t_i + alpha_i (t_new - t_i)                (constant speed)
//   polar about an origin o_i (the attached bone's head, or the rig's centre of mass, both taken
//   afresh every step):
//     t_{i+1} = o_i + r_i R(n_i, alpha_i theta_i) (t_i - o_i)/|t_i - o_i|
//     alpha_i = 1/(i_max - i),  r_i = (1 - alpha_i)|t_i - o_i| + alpha_i |t_new - o_i|
//   with theta_i the angle and n_i the normal between t_i - o_i and t_new - o_i. If either lies
//   within `fallback` of o_i it falls back to the linear step. The last step (alpha = 1) lands
//   exactly on t_new.
// A scene's initial targets count as a jump from each attachment point's starting position.
#pragma once

#include "physik/engine/state.h"
#include "physik/model/scene.h"

namespace physik {

// One step of eq. 12 (or the linear step) with fraction alpha in (0, 1].
Vec3 interpolate_step(Interpolation scheme, const Vec3& current, const Vec3& goal,
                      const Vec3& origin, double alpha, double fallback);

// Start of a step: apply scheduled target changes for state.step, then advance every
// interpolation in progress by one step.
void update_targets(const Scene& scene, SimState& state);

// Begin moving control point c's target to `goal` (interpolated per the scene's params).
void start_target_jump(const Scene& scene, SimState& state, int c, const Vec3& goal);

// The same from the control point's attachment on the state's frames (the effective target
// starts there): a scene's start (init_state), and a pose put into a posing session.
void start_pull_from_attachment(const Scene& scene, SimState& state, int c, const Vec3& goal);

}  // namespace physik
