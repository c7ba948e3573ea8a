// The implicit step (docs/engine.md "The implicit scheme"): linearised backward Euler
// over the exact articulated solve, in O(n), with no allocation per step.
//
// Sources: D. Baraff and A. Witkin, "Large steps in cloth simulation", SIGGRAPH 1998, eq. 6-7
// (one Newton step of backward Euler, forces linearised about the start of the step); MuJoCo's
// `implicit` integrator does the same for damping (mj_implicit: M - h dqfrc/dqvel); R.
// Featherstone, Rigid Body Dynamics Algorithms, 2008, ch. 7 (the articulated-body algorithm, here
// articulated_body.h).
//
// Derivation. Joint space as scheme exact: qvel v (root v_com world, root w local, ball u
// local), M(q) v' + C(q, v) = tau(q, v). Backward Euler, v+ = v + h a, q+ = q (+) h v+, with tau
// taken at the end of the step and linearised (K = -d tau/dq, D = -d tau/dv, both at the start):
//   tau(q+, v+) ~ tau - K h (v + h a) - D h a
// gives
//   (M + h D + h^2 K) a = tau - C - h K v                                            (1)
// then the same Euler update as the explicit exact step (integrate_joint_space.h): v += h a,
// positions from the new v. Velocity products C and the gyroscopic term stay explicit.
//
// Every PhysIK force is an element whose D and K are known in closed form (Gauss-Newton: the
// curvature of the attachment point p(q), and the turn of a torsion torque's frame with the pose,
// are dropped; both are multiplied by the element's force, so they vanish where it does). The
// point elements give a symmetric positive semi-definite K; the paper's torsion torque gives a
// joint block that is not symmetric on a bent joint (below), so M + h D + h^2 K is then a general
// matrix, solved by the same recursion with general articulated inertias (articulated_body.h).
// Every block keeps a positive semi-definite symmetric part, so the symmetric part of
// M + h D + h^2 K is positive definite: the matrix, and every pivot of the recursion (Schur
// complements keep that property), is invertible at every h.
//   point element with 3x3 matrix A at a point p of body b: J_p^T A J_p, J_p the point's velocity
//     Jacobian. With J_p = Phi J_b, Phi = [-[r]x, 1] on b's spatial velocity (w; v_o) about o_b,
//     r = p - o_b, this is body b's spatial inertia plus Phi^T A Phi = [[r]x A [r]x^T, [r]x A;
//     A [r]x^T, A] (a "point mass" A at r): the augmented inertia. Elements:
//       end damper        A = h c 1                     (head and tail of every bone)
//       control spring    A = h^2 K_c, K_c = spring_step_stiffness (control_springs.h): the
//                         tangent, and beyond the cap the secant k c / |d| along the pull,
//                         where the tangent has none (a majoriser of the capped potential: a
//                         long step lands at most on the target instead of past it)
//   angular-velocity factor f: the explicit torque I (f - 1) w / dt (as the exact step) is a
//     rotational damper D = (1 - f) / dt I_com, so h D = (1 - f) I_com on the body's angular
//     block at h = dt (zero when f = 1, "off"; (h / dt) (1 - f) I_com over a substep h)
//   torsion spring at bone i (joint element): tau_world = T tau_local(theta), T the torque frame
//     (torsion_torque_frame: R_pr = R_p R_rest for the paper's torque `axes`, R_pr J_l^-T for
//     torsion_torque gradient), theta the rotation vector of the ball. With the parent held, a
//     relative turn dphi (world axes) moves theta by J_l(theta)^-1 R_pr^T dphi, so on the ball's
//     world-axes rate (w_i - w_p) = R_i u the block is
//       K_j = R_pr B R_pr^T,  B = torsion_step_block_local (torsion_springs.h), per-axis k from
//             torsion_step_stiffness_local (the capped law beyond its cap at its secant):
//       gradient: B = J_l^-T diag(k) J_l^-1, symmetric, the potential's Hessian where the torque
//                 vanishes;
//       axes:     B = diag(k) J_l^-1, the exact tangent of the paper's torque in theta, its
//                 symmetric part's negative eigenvalues clipped (they occur where an axis that
//                 is not engaged couples to an engaged one, or the engaged axes' k differ:
//                 torsion_springs.h; they can make the step's matrix singular on a rig posed at
//                 random from h ~ 1 s; tests/implicit_step_test.cpp checks every pivot on 300
//                 random pinhead poses).
//     The tangent's antisymmetric part (-R_pr diag(k) (W / 2) R_pr^T where diag(k) commutes with
//     W = [theta]x; norm sqrt(2) k |theta_x| / 2 on an elbow bent by theta_x with locked y and z)
//     is what a symmetric block drops: long steps then converge only as a quasi-Newton iteration
//     (linearly, on a bent elbow at long steps); with the tangent, as Newton's method
//     (tests/tune/implicit_equilibrium_test.cpp). h^2 K_j is the joint's 3x3 block
//     (articulated_body.h joint_block: D_i = A_i + J_i)
//       contact           A = h^2 K + h D at the contact point (ground_contacts.h, self_contacts.h:
//       K = k n n^T, D the
//                         normal damper and the friction's viscous share); a ground contact on
//                         its bone exactly; a self-contact's spring as 2 h^2 K on each of its
//                         two bones, the coupling block between them left out (block Jacobi),
//                         its damper and friction explicit and capped (self_contacts.h)
// Right-hand side of (1): the start-of-step forces (force stages unchanged), plus -h K v per
// stiffness element: the force -h K_c v_p at each control point, the torque pair -h K_j (w_i - w_p)
// at each torsion spring, -h K (v_a - v_b) at each contact (on a; its opposite on b).
// The augmented inertia also multiplies the velocity-product part of the body's spatial
// acceleration (a_b = J_b a + a0_b, a0_b the accelerations at a = 0): the element force is
// -A Phi (a_b - a0_b), so each body's bias force gets -Phi^T A Phi a0_b as well; then the
// recursion solves (1) exactly (tests/implicit_step_test.cpp: against a dense M + h D + h^2 K
// from finite differences).
// Large h: (1) tends to K (v + h a) = tau / h, i.e. q+ - q = K^-1 tau, a Gauss-Newton step on the
// force balance tau(q) = 0 (on the spring and torsion potential, with the gradient torque): large
// steps are the static solve (tune/equilibrium.h).
// implicit_linearisation full (implicit_pose_terms.h) adds the pose terms to (1): Newton's step
// on the backward Euler equations at the rest accelerations. They are not positive semi-definite
// (a spring's geometric stiffness under load, the torque frame's turn, dM/dq), so a pivot can lose
// its sign, and Newton's step can head for a saddle of the potential. A step whose recursion meets
// a pivot, or a root 6x6, whose symmetric part is not positive definite is taken again with the
// Gauss-Newton system (the forces restored from state.implicit.step_force_world), counted in
// state.implicit.gauss_newton_steps; for a symmetric system, pivots positive definite is the
// matrix positive definite. Without the retake a long full step can end non-finite, and a retake
// only on a pivot of non-positive determinant can settle on a saddle; with this rule every
// reachable target of ik_comparison is met (CHANGELOG.md has the measurements;
// tests/experiments/pose_terms_test.cpp checks the rule).
// The energy statement below holds for the symmetric elements; the paper's torsion torque is the
// gradient of no potential, and implicit_advance.h guards every step's energy.
// One DOF (mass m, damper c, spring k): x+ = ((m + h c) x + h m v) / S, v+ = (m v - h k x) / S,
// S = m + h c + h^2 k; det = m / S < 1, both eigenvalues inside the unit circle for all h, c, k >
// 0, and E = (m v^2 + k x^2) / 2 never grows: E+ - E = -h c v+^2 - m (v+ - v)^2 / 2 - k (x+ - x)^2
// / 2. Units: s, kg, N, N m, rig units, rad.
#pragma once

#include "physik/engine/joint_forces.h"
#include "physik/engine/state.h"
#include "physik/model/scene.h"

namespace physik {

// After the force stages (apply_forces): the implicit solve of (1).
// state.joint_space.articulated then holds the accelerations a for integrate_joint_space, as
// solve_articulated's would.
JointSolveStats solve_implicit(const Scene& scene, SimState& state);
// The same over a step h (s) other than params.dt, for the substeps of implicit_advance.h: the
// ODE is the scene's (the factor's damper stays (1 - f) / dt I_com), only the step changes.
// `terms`: which pose terms implicit_linearisation full keeps (all; a study drops some).
// `armature` (kg m^2, 0: none) adds that inertia about every axis of every ball joint (MuJoCo's
// dof armature: a rotor's inertia on the joint's own coordinate) to M: the equilibrium solve's
// metric (equilibrium_solve.h).
JointSolveStats solve_implicit(const Scene& scene, SimState& state, double h,
                               const PoseTermSelection& terms = {}, double armature = 0.0);

// Pieces, exposed for the tests and the linear modes:
// the stiffnesses of this step (each element's tangents): state.implicit.control_stiffness (per
// control point) and state.implicit.torsion_stiffness (per bone, local axes)
void element_tangents(const Scene& scene, SimState& state);
// K_j = R_pr B R_pr^T: bone i's torsion block on its world-axes relative rate, N m/rad
// (B = torsion_step_block_local; element_tangents). Symmetric only for the gradient torque; its
// symmetric part is positive semi-definite for both.
Mat3 torsion_block_world(const Rig& rig, const SimState& state, int bone);

}  // namespace physik
