// Linearised modes at a pose, and damping_auto: the damping that critically damps the slowest one
// (docs/engine.md "The implicit scheme"; the paper's discussion asks for "a way to automatically
// compute the ideal damping coefficient").
//
// About a pose at rest, PhysIK's dynamics linearise to M a + (c D1 + Dr) v + K dq = 0 in the
// exact solve's joint coordinates (root 6 DOF, a ball at every other head;
// integrate_joint_space.h):
//   M  = sum_b J_b^T diag(I_b, m_b) J_b                                   (the rigid mass matrix)
//   K  = sum_control J_p^T K_c J_p + sum_torsion J_rel^T K_j J_rel        (Gauss-Newton, as the
//        implicit step: K_c the spring's tangent; K_j = T diag(k) T^T, T the torque frame
//        (torsion_torque_frame): within the caps the step's block for the gradient torque, and
//        for the paper's torque R_pr diag(k) R_pr^T, its step block's value at theta = 0 (on a
//        bent joint the step's block is not symmetric, implicit_step.h; the modes need a
//        symmetric K))
//   D1 = sum_bones (J_head^T J_head + J_tail^T J_tail)                   (the end dampers per unit
//   c) Dr = sum_b J_w^T ((1 - f) / dt) I_b J_w                               (the angular-velocity
//   factor)
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
// The solver: Lanczos on the spectral transformation F = (K + s M)^-1 K, s > 0, O(n) per step,
// its answer certified by counting modes; no dense matrix is formed: K x, M x, D1 x, Dr x are
// tree passes and (K + s M)^-1 the articulated-body recursion with augmented inertias
// (mode_operators.h).
//   Why F. Every mode phi_i is an eigenvector of F with mu_i = w_i^2 / (w_i^2 + s) in [0, 1);
//   F is self-adjoint in the K (semi-)inner product (K F = K (K + s M)^-1 K is symmetric). The
//   zero modes, null(K), have mu = 0 and are invisible to K's inner product, and F x has no
//   part on them: Lanczos started from F r never meets them, however many (thousands on a long
//   free chain: every twist and every DOF no spring touches). The slowest constrained modes
//   are the low end of F's spectrum on range(F), an extreme one; on a rig with r constrained
//   modes range(F) is spanned after r steps (a chain with one control point: 3).
//   Alternatives. Shift-and-invert (K - sigma M)^-1 M (inverse iteration, Spectra's or ARPACK's
//   mode) puts null(K) at -1 / sigma, a large eigenvalue that round-off keeps feeding;
//   (K + s M)^-1 M puts it at the top, 1 / s, the end Lanczos and LOBPCG find first; LOBPCG's
//   Rayleigh quotient has its minimum 0 on null(K). Spectra is not used: its restarts would
//   filter toward 0, the wanted end of F.
//   Details (linear_modes.cpp): full reorthogonalisation (classical Gram-Schmidt twice); the
//   shift starts at a Rayleigh quotient in range(F) and moves to the next candidate's w^2 on a
//   restart; converged Ritz vectors the rule skipped are locked out of later runs; Ritz
//   vectors are purified (F y / theta, no part on null(K)); a Ritz pair is accepted when its
//   residual is below 1e-10 of its gap to the other Ritz values (1e-13, when it is the only one
//   and range(F) is not yet spanned: the start vector is F's image at a shift near the stiff end,
//   in which a slow mode's part can lie below 1e-10, as a long chain's translation along itself
//   does); w^2 and the quadratic forms are the Ritz vector's Rayleigh quotients
//   (y^T K y / y^T M y, ...). w^2_max for the zero-mode threshold is the top Ritz value (a lower
//   bound).
//   Certificate. The modes below any sigma > 0 are counted exactly in O(n) from the signs of
//   the recursion's pivots of K - sigma M (Sylvester's law of inertia, mode_operators.h). The
//   answer stands when the count between the count's floor (1e-6 w^2_max: below about 1e-8 the
//   zero modes' round-off makes the count unreliable) and the answer's w^2 equals the modes
//   Lanczos walked there. Otherwise (a mode Lanczos missed, a repeated mode, of which one
//   Krylov vector sees only one, or no convergence in 16 runs) the answer is the walk's: each
//   mode above the floor in ascending order, its w^2 by bisection on the count, its vector by
//   inverse iteration (K - sigma M)^-1 M just below it, until the rule finds one (about 50
//   counts per mode walked). Modes between the zero-mode threshold and the floor are walked
//   only by Lanczos.
//   Repeated modes. A mode repeated by a symmetry of the rig (a straight chain's two bending
//   planes) has by that symmetry the same phi^T D phi over its eigenspace, so one vector gives
//   the rule's answer, counted with its multiplicity.
// Cost: per Lanczos step one solve and two K products, O(n), and O(m n) for reorthogonalisation
// against m vectors (at most 300 and about 32 MB); per count one backward pass. Called at the
// start and when targets change, not per step; the buffers are the state's (SimState::modes),
// sized at the first call.
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
  double slowest_omega = 0.0;            // rad/s, the mode damping_auto damps (0 if none)
  bool found = false;                    // is there such a mode
  double slowest_d1 = 0.0;               // phi^T D1 phi of that mode (N s/m per unit c)
  double slowest_dr = 0.0;               // phi^T Dr phi (N s/m)
  double critical_damping = 0.0;         // N s/m, c of damping_auto (0 if no mode is found)
  double omega2_max = 0.0;  // rad^2/s^2, the largest w^2 (the zero-mode threshold's scale)
  int skipped = 0;          // constrained modes below it that the rule skipped
  int iterations = 0;       // iterative path: Lanczos steps (shifted solves), all runs
  int runs = 0;             // iterative path: Lanczos runs (1 + restarts)
  int counts = 0;           // iterative path: counts of the modes below a w^2
  bool walked = false;      // iterative path: the answer is the walk's (Lanczos's was not
                            // certified)
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
