// Linearised modes at a pose, and damping_auto: the damping that critically damps the slowest one
// (DESIGN.md "Beyond the paper"; the paper's discussion asks for "a way to automatically compute the
// ideal damping coefficient").
//
// About a pose at rest, PhysIK's dynamics linearise to M a + (c D1 + Dr) v + K dq = 0 in the
// exact solve's joint coordinates (root 6 DOF, a ball at every other head; integrate_joint_space.h):
//   M  = sum_b J_b^T diag(I_b, m_b) J_b                                   (the rigid mass matrix)
//   K  = sum_control J_p^T K_c J_p + sum_torsion J_rel^T K_j J_rel        (Gauss-Newton, as the
//        implicit step: K_c the spring's tangent; K_j = T diag(k) T^T, T the torque frame
//        (torsion_torque_frame): within the caps the step's block for the gradient torque, and
//        for the paper's torque R_pr diag(k) R_pr^T, its step block's value at theta = 0 (on a
//        bent joint the step's block is not symmetric, implicit_step.h; the modes need a
//        symmetric K))
//   D1 = sum_bones (J_head^T J_head + J_tail^T J_tail)                   (the end dampers per unit c)
//   Dr = sum_b J_w^T ((1 - f) / dt) I_b J_w                               (the angular-velocity factor)
// The modes solve K phi = w^2 M phi, phi^T M phi = 1.
//
// The rule. Zero modes (free motions: a bone's twist about its own axis, unconstrained DOF) are
// skipped: w^2 below 1e-9 of the largest. A mode is critically damped when phi^T D phi = 2 w, so
// mode i needs c_i = (2 w_i - phi_i^T Dr phi_i) / (phi_i^T D1 phi_i). damping_auto takes the
// slowest constrained mode (smallest w^2 above the threshold) that the end dampers reach
// (phi^T D1 phi above 1e-12 of D1's largest diagonal entry in the dense path's coordinates) and
// that the factor alone leaves underdamped (c_i > 0); modes the factor already overdamps are
// skipped (on fig5_running the slowest ones are such rotations, and c = 0 from them left the
// translation undamped). 0 if there is none.
//
// The solver: Lanczos on the spectral transformation F = (K + s M)^-1 K, s > 0, in O(n) per
// step. No dense matrix is formed: K x, M x, D1 x, Dr x are tree passes and (K + s M)^-1 the
// articulated-body recursion with augmented inertias (mode_operators.h).
//   Why F. Every mode phi_i of K phi = w^2 M phi is an eigenvector of F with the eigenvalue
//   mu_i = w_i^2 / (w_i^2 + s), in [0, 1); F is self-adjoint in the M inner product
//   (M F = M Phi diag(mu) Phi^T M is symmetric). The zero modes, null(K), have mu = 0 exactly,
//   and F x has no component along them for any x (F x = (K + sM)^-1 K x, and
//   phi_0^T M F x = mu_0 phi_0^T M x = 0): range(F) is the M-orthogonal complement of null(K).
//   So Lanczos started from F r never meets the zero modes, however many (thousands on a long
//   free chain: every twist and every DOF no spring touches), and round-off cannot feed them:
//   each step applies F again, which annihilates what the last one left there (relative
//   size ~ eps w^2_max / s per step, never amplified). The lowest constrained modes are then
//   the low end of F's spectrum on range(F), an extreme one, where Lanczos converges first;
//   on a rig with r constrained modes the Krylov space is range(F) after r steps, exactly (a
//   chain with one control point: 3).
//   Alternatives. Shift-and-invert (K - sigma M)^-1 M (inverse iteration, Spectra's or ARPACK's
//   shift-invert mode) puts null(K) at 1 / -sigma, a large eigenvalue of the wrong sign that
//   round-off keeps feeding, and K - sigma M is indefinite, which the recursion's pivots do not
//   allow. (K + s M)^-1 M puts null(K) at the top, 1 / s: the end Lanczos and LOBPCG find first.
//   LOBPCG minimises the Rayleigh quotient, whose minimum is 0 on null(K): it would need a
//   projection onto range(K) every step, which is F again. Spectra is not used: its modes are
//   these transformations, and its restarts with F would filter toward 0 (the wanted end).
//   The shift. Lanczos converges on mu_1 at a rate set by (mu_2 - mu_1) / (mu_max - mu_1) =
//   (w_2^2 - w_1^2) (w_max^2 + s) / ((w_2^2 + s) (w_max^2 - w_1^2)) ~ (w_2^2 - w_1^2) /
//   (w_2^2 + s): within 2x of the best for any s <= w_1^2, and slow for s >> w_1^2. Round-off
//   left on null(K) grows as 1 / s. So s starts at the Rayleigh quotient of a random vector,
//   and after 12 steps is moved to half the lowest constrained Ritz value if it lies outside
//   [w_1^2 / 64, 2 w_1^2] (a restart from the lowest Ritz vectors).
//   Full reorthogonalisation (classical Gram-Schmidt twice, M inner product) keeps the basis
//   orthogonal, so Ritz values neither repeat nor go missing. A breakdown (the next vector
//   below 1e-9 of F q) means an invariant subspace: the run continues from a fresh F r
//   orthogonalised against the basis, and ends, with every constrained mode found, when that
//   has less than 1e-6 of its norm left.
//   Convergence. A Ritz pair (theta, y = Q s) has the residual ||F y - theta y||_M =
//   beta_m |s_m|; it is accepted when that is below 1e-10 of its distance to the other Ritz
//   values (the vector's error angle is at most residual / gap), or below 1e-13. The pairs are
//   taken in ascending order, as the rule walks the modes: w^2 and the quadratic forms from the
//   Ritz vector's Rayleigh quotients (y^T K y / y^T M y, y^T D1 y / y^T M y, ...). The answer
//   is final once every Ritz value below it is converged (or a zero mode). w^2_max for the
//   zero-mode threshold is the top Ritz value (a lower bound that only matters for a mode
//   within a factor of it of 1e-9 w^2_max).
//   Repeated modes. One Krylov vector sees one vector of each eigenspace. A mode repeated by a
//   symmetry of the rig (a straight chain's two bending planes) has, by that symmetry, the same
//   phi^T D phi over its eigenspace, so one vector gives the rule's answer; an accidentally
//   repeated pair with different quadratic forms leaves the rule's answer depending on the
//   basis chosen inside the eigenspace (for the dense path too).
// Cost: per step one K product, one solve, three M products (reorthogonalisation, norm), O(n),
// and O(m n) for reorthogonalisation against m vectors; memory m n. The basis is capped (at
// most 400 vectors and about 32 MB); past it the run restarts from the lowest Ritz vectors.
// Called at the start and when targets change, not per step: it allocates (the operators'
// per-bone buffers and the Krylov basis).
// The dense path, O(n^3), stays as the reference (linear_modes_dense.h).
// Units: kg, N/m, N s/m, rad/s.
#pragma once

#include <vector>

#include "physik/engine/mode_operators.h"
#include "physik/engine/state.h"
#include "physik/model/scene.h"

namespace physik {

struct LinearModes {
  double first_constrained_omega = 0.0;  // rad/s, the slowest constrained mode (0 if none)
  double slowest_omega = 0.0;     // rad/s, the mode damping_auto damps (0 if none)
  bool found = false;             // is there such a mode
  double slowest_d1 = 0.0;        // phi^T D1 phi of that mode (N s/m per unit c)
  double slowest_dr = 0.0;        // phi^T Dr phi (N s/m)
  double critical_damping = 0.0;  // N s/m, c of damping_auto (0 if no mode is found)
  double omega2_max = 0.0;        // rad^2/s^2, the largest w^2 (the zero-mode threshold's scale)
  int skipped = 0;                // constrained modes below it that the rule skipped
  int iterations = 0;             // iterative path: Lanczos steps (shifted solves), all runs
  int runs = 0;                   // iterative path: Lanczos runs (1 + restarts)
};

// The modes at the state's pose (frames, com, pose) with the springs pulling toward
// `targets_world` (one per control point): the iterative path, O(n) per step, any size.
LinearModes linear_modes(const Scene& scene, const SimState& state,
                         const std::vector<Vec3>& targets_world);
// The same with the buffers of `workspace` (mode_operators.h), which a later call reuses.
LinearModes linear_modes(const Scene& scene, const SimState& state,
                         const std::vector<Vec3>& targets_world, ModeWorkspace& workspace);

// damping_auto: set state.damping_auto_value from the modes at the state's pose with the springs'
// settling stiffness (d = 0: k 1 for both laws; beyond the cap a capped spring has no stiffness
// along its pull, which would leave the whole-body translation a zero mode); counts
// state.damping_auto_updates. At the start and whenever the targets change (the pose then).
void update_auto_damping(const Scene& scene, SimState& state);

}  // namespace physik
