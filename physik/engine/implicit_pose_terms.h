// The implicit step's pose terms (implicit_linearisation full): the derivative of the rest
// dynamics in the pose, held in the O(n) articulated-body recursion.
//
// Sources: R. Featherstone, Rigid Body Dynamics Algorithms, Springer 2008 (spatial algebra,
// ch. 2; the articulated-body algorithm, ch. 7); D. Baraff and A. Witkin, "Large steps in cloth
// simulation", SIGGRAPH 1998 (one Newton step of backward Euler). The linearisation experiment
// (experiments/linearisation.h) measured what these terms are worth with dense steps.
//
// What is linearised. The shipped step (implicit_step.h) solves (M + h D + h^2 K) a = tau - C
// - h K v with K the Gauss-Newton stiffness of the elements. `full` takes instead
//   K = -d/dq [tau(q, 0) - M(q) a0],   a0 = M^-1 tau(q, 0)
// (the rest accelerations: the springs alone, as dampers, the factor and the velocity products
// vanish at v = 0), which is exactly the linearisation experiment's newton_at_rest step:
// M A_q(q, 0) = -K. Write R_j(q) = S_j^T W_j + Q_t,j(q_j), the generalised force of joint j at
// fixed qdd = a0, with W_j = sum over the bodies b of j's subtree of (F_b - I_b A_b) (F_b the
// world-held forces: the force list's pose forces, forces.h; I_b A_b the d'Alembert wrench at a0)
// and Q_t the torsion springs (a joint's own, a function of its own rotation only). Moving dof i (a
// twist xi = S_i dq of the subtree of i; a ball turns about its own local axes, so its own S turns
// too; the root's translation columns are world-fixed) gives, with H(W) xi = xi x* W:
//   (1) the axes of S_j turn for i at or above j:   +S_j^T H(W_j) S_i   (joint j's row only)
//   (2) a spring's point moves, its force held:     +S_j^T (-G_p) S_i,
//       G_p = [[f]x[r]x, -[f]x; 0, 0],
//       and its force follows (Gauss-Newton):         +S_j^T Phi^T K_c Phi S_i   (already shipped)
//   (3) the inertia turns with the body:            +S_j^T H(I_b A0_b) S_i
//   (4) the joint accelerations below i turn with i: +S_j^T I_b (A0_p(i) x S_i),  A0_p(i) the
//       acceleration of i's parent (of the root: its translation part (0; a_com))
//   (5) a torsion torque, held in its parent's rest frame, on the child's turning axes:
//       -[tau_world]x, and for the gradient torque the turn of J_l^-T with theta
// for every body b below both i and j. (2) and (3) are body-level 6x6 stiffnesses, general
// matrices added to the augmented inertias. (1) is a term of joint j's row alone (G_i in
// ArticulatedBodyData). (4) is not body-level: it depends on i through A0_p(i); summed over
// i it is I_b z_b with z_b = sum_{i at or above b} A0_p(i) x S_i qdd_i, a second motion vector
// carried root to leaves as a is (T_i = A0_p(i) x S_i; ArticulatedBodyData::inertia_z). So every
// term stays O(n): the recursion carries a second inertia I^Z (h^2 I_b at each body) beside I^A.
// The right-hand side gets -h K v the same way (each term applied to the velocities).
//
// Joints with locked axes (rig.h "Locked axes", joint_coordinates.h). A hinge's columns are its
// world axes S = [s0 (s1)] and the pass eliminates them with the projector S (S^T D S)^-1 S^T in
// place of D^-1 (articulated_body.h). A hinge's axis is fixed in its parent: its own coordinate
// turns nothing in (1) and (4) (s x s = 0), so every term is the ball's on its axis. A universal
// joint's s0 is fixed in the parent and s1 in the bone, so two of the ball's own-joint terms
// change, each because t1 does not turn s0:
//   (1) the row G_j a_j counts s0^T G s1 t1'' (and its rate share, G_j's -h V_j along s1) as a
//       ball would: taken back, -s0 g01 s1^T into the pivot (g01 = s0^T G_A s1) and
//       +s0 g01 t1' / h into the right-hand side;
//   (4) the accelerations below s1 turn about s1 as it stands after the first hinge's rest
//       acceleration: T's angular block on s1 uses alpha + s0 t0''_rest, i.e. gains
//       (t0''_rest s0 x s1) s1^T (ArticulatedBodyData::z_axis_turn), its rate likewise.
// (5) does not arise on the angles: a hinge's torsion torque S Q(t) gives S^T S Q = Q at every
// pose. A weld by locks hands I^A, I^Z and its bias to its parent whole. Checked against the
// dense step on random trees of hinges, universal joints and welds by locks
// (tests/experiments/pose_terms_test.cpp).
//
// The shared DESIGN.md sketch takes (1) over strict ancestors with the whole transmitted wrench,
// torsion torques included, and no (5). Measured against the dense step, that differs (the
// torsion torques turn with their parent: with them in W, (1) needs their own turning term for
// strict ancestors; without them, (1) reaches joint j itself and (5) follows), and (3) and (4)
// are needed beside the d'Alembert part of (1): tests/experiments/pose_terms_test.cpp.
//
// Which forces. Every element of the force list says what it applies at rest (forces.h
// pose_forces): a point force (the control springs, the pins, an aim's head), a couple held in the
// world (the orientation and aim targets: in W, with no (2)), or a joint's torque (the torsion
// springs: in a0, and (5)). Gravity, the dampers and the contacts supply none (forces.cpp says
// why). Left as the shipped step keeps them: each element's step stiffness (the secant beyond a
// cap, where the tangent has none; the orientation and aim targets' is their tangent under full,
// orientation_springs.cpp, aim_springs.cpp) and the paper's torque's clipped block
// (implicit_step.h). So with linear control springs, pins, orientation and aim targets and
// gravity, within the caps and no clip acting, the step is the dense newton_at_rest step to
// round-off (tests/experiments/pose_terms_test.cpp).
// No allocation per step (state.implicit.articulated_rest and the buffers of state.h, sized once).
// Units: s, kg, N, N m, rig units, rad.
#pragma once

#include "physik/engine/force_stages.h"
#include "physik/engine/state.h"
#include "physik/model/scene.h"

namespace physik {

// After articulated_velocity_pass (rigid inertias in state.joint_space.articulated) and the force
// stages: the rest accelerations a0 (state.implicit.articulated_rest.accel_spatial, about each
// o_i) under the force list's pose forces alone (forces.h), by a second articulated-body solve
// with the rigid inertias, and their world-held wrenches (state.implicit.rest_wrench). Reads what
// the force stage and element_tangents left in the state.
void rest_accelerations(const Scene& scene, const PoseTermSelection& terms, SimState& state);

// After augment_bodies (implicit_step.cpp): terms (1)-(4) above into
// state.joint_space.articulated (its inertias, their lower blocks, bias forces, the rows G, I^Z
// and T), and pose_terms on.
void add_pose_terms(const Scene& scene, const ImplicitStage& stage, SimState& state);

}  // namespace physik
