// Semi-implicit (symplectic) Euler: velocities first, then positions with the new velocities.
//
// Angular velocity, with the per-step factor f (0.5 in the original):
//   w <- f w + alpha dt
// which is the same as a torque tau_f = I (f - 1) w / dt (how the MuJoCo reference applies it).
// Orientation: R <- exp([w dt]x) R  (each bone turns by its own world angular velocity).
//
// Two forms of the gauss-seidel scheme (params.free_rods):
//  articulated (the original code's; free_rods false): only the root translates,
//     v_root <- v_root + a_root dt,  cm_root <- cm_root + v_root dt;
//     every bone turns by its own w; positions are rebuilt by forward kinematics from the root
//     (each child's head is put at its parent's tail), so joints cannot separate; the linear
//     velocities of the other bones follow from the chain: v_head(child) = v_tail(parent).
//     (The original composes each bone's turn into its parent-relative rotation; we integrate
//     world orientations, which does not count a parent's turn twice.)
//  free rods (the paper's text; free_rods true): every bone integrates its own v, cm, w and R;
//  joints may drift
//     apart, and the drift is measured (engine.h: joint separation).
// Welded groups (rig.h "Welds") move as one body each (prepare_welded_bodies, newton_euler.h): its
// composite w <- f w + alpha dt turns its first bone, the others keep their rest frames in their
// welds'; a free root's body moves its centre of mass by F / m and turns about it, as a root rod
// does, its bones riding on it; free rods move every body as a rigid body of its own.
// With params.factor_in_joint_solve the joint solve took the factor as a torque
// (apply_factor_torque, newton_euler.h), and the integration takes f = 1.
// An anchored root (rig.h: pinned or fixed) does not translate: a pinned root turns about its
// head, held at its rest position, a fixed one not at all.
// Two choices the paper does not state (docs/engine.md "The paper's scheme"): the root moves its
// centre of mass and turns about it (the original turns it about its head: a difference of about
// (|w| dt)^2 L / 2 per step), and the gyroscopic term w x I w of alpha uses the start-of-step w,
// before the factor f scales it.
// Units: s, rig units, rad.
#pragma once

#include "physik/engine/state.h"
#include "physik/model/params.h"
#include "physik/model/rig.h"

namespace physik {

// One step of length h (s; the scheme's step is params.dt: the factor f is per step).
void integrate_articulated(const Rig& rig, const EngineParams& params, double h, SimState& state);
void integrate_free_rods(const Rig& rig, const EngineParams& params, double h, SimState& state);

// The factor f the integration applies: params.angular_velocity_factor, or 1 where the joint
// solve already took it as a torque (params.factor_in_joint_solve, newton_euler.h).
double integrated_factor(const EngineParams& params);

// Rotate an orientation by a world angular velocity over dt.
Quat rotate_by(const Quat& orient_world, const Vec3& omega_world, double dt);

}  // namespace physik
