// Orocos KDL as a solver of a scene's goals: `physik solve --solver kdl|kdl-nr` and
// physik.solve(scene, "kdl"), so that the comparison a user makes with an outside IK library needs
// no experiment. The layer above the core that has KDL (the core never sees it); the physik
// command and the Python module register its solvers with the core's solve_scene
// (physik/posing/scene_solve.h register_outside_solver) at their start.
//
// Source: Orocos Kinematics and Dynamics Library 1.5 (Debian liborocos-kdl-dev):
//   kdl     ChainIkSolverPos_LMA: Levenberg-Marquardt on the weighted pose error (its own
//           adaptive damping; no joint limits), weights L = (1, 1, 1, w, w, w)
//   kdl-nr  ChainIkSolverPos_NR_JL: Newton-Raphson whose velocity step is
//           ChainIkSolverVel_wdls (the SVD pseudo-inverse of the task-weighted Jacobian), each
//           iterate clamped to the joint limits (q_min, q_max)
//
// The chain. KDL solves one chain from a fixed base to one tip frame: the root bone's head held
// where the rig's rest puts it (as the classic solvers anchor it), then per bone from the root to
// the tip bone a fixed segment (its head in its parent's frame, its rest orientation) and one
// revolute joint per axis its joint turns about, x then y then z of its rest frame: the local
// rotation Rx(q_x) Ry(q_y) Rz(q_z). An axis locked at 0 (min == max == 0) has no joint, a welded
// bone none at all. The tip is the point at alpha along the tip bone (its frame the bone's).
// Limits: kdl-nr clamps each joint to its axis's [min, max] (--no-limits: none). The rig's limits
// are intervals of the rotation vector's components; the chain's joints are Euler angles, which
// agree with them on a joint that turns about one axis (a hinge) and to first order elsewhere.
// kdl (LMA) has no limits: its pose may pass them (the summary's max_limit_violation_deg).
//
// The goals KDL takes (else InputError naming the field and the reason: exit 2):
//   - the goals of one bone, the tip: a control point (the tip's position) and/or an orientation
//     target (its frame; "orientation rows", weighted w = tol / tol_angle so that the weighted
//     error meets tol exactly where the turn meets tol_angle);
//   - besides them, control points on the root bone's head (alpha 0) held at its rest position:
//     the chain's fixed base holds them (ik_comparison's scenes pin the root's head so);
//   - no aims, no pins, no second goal bone, and no ground, obstacles, self-collision or gravity
//     (the chain knows the rig's geometry and the goals only).
// Position-only or orientation-only tips: LMA weighs the other rows 0; NR_JL's stop test
// compares every component of the twist error with eps, so its forward kinematics reports the
// ignored part of the tip frame as the target's (PartialFk in the .cpp) and its velocity step
// weighs those rows 0.
// Iterations: LMA's lastNrOfIter; NR_JL's, the forward kinematics it asked for less its final
// check. Converged: every goal within its own tolerance (measures.h), whatever KDL's status.
// The time is CartToJnt's alone (the chain is built before the clock, as a tool holds it).
// Units: rig units, rad.
#pragma once

#include "physik/posing/scene_solve.h"

namespace physik::kdl {

// `--solver kdl` (LMA) or `kdl-nr` (NR_JL) on the scene's goals (above); InputError for what the
// chain cannot take.
SceneSolveResult solve_scene_kdl(const Scene& scene, const SceneSolveOptions& options);

// Register both with the core's solve_scene (idempotent).
void register_solvers();

}  // namespace physik::kdl
