// Linearised modes at a pose, and damping_auto: the damping that critically damps the slowest one
// (docs/engine.md "The implicit scheme"; the paper's discussion asks for "a way to automatically
// compute the ideal damping coefficient").
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
// The modes solve K phi = w^2 M phi (Eigen's GeneralizedSelfAdjointEigenSolver, phi^T M phi = 1).
// Zero modes (free motions: a bone's twist about its own axis, unconstrained DOF) are skipped:
// w^2 below 1e-9 of the largest. A mode is critically damped when phi^T D phi = 2 w, so mode i
// needs c_i = (2 w_i - phi_i^T Dr phi_i) / (phi_i^T D1 phi_i). damping_auto takes the slowest
// constrained mode (smallest w^2, phi^T D1 phi > 0) that the factor alone leaves underdamped
// (c_i > 0); modes the factor already overdamps are skipped (on fig5_running the slowest ones
// are such rotations, and c = 0 from them left the translation undamped). 0 if there is none.
// Dense, O(n^3): for rigs up to kMaxModeBones bones; called at the start and when targets change,
// not per step (it allocates).
// Units: kg, N/m, N s/m, rad/s.
#pragma once

#include <vector>

#include "physik/engine/state.h"
#include "physik/model/scene.h"

namespace physik {

constexpr int kMaxModeBones = 400;

struct LinearModes {
  std::vector<double> omega;           // rad/s, every mode's angular frequency, ascending
  int first_constrained = -1;          // index of the first mode above the zero-mode threshold
  int slowest = -1;                    // index of the slowest constrained mode; -1 if none
  double slowest_d1 = 0.0;             // phi^T D1 phi of that mode (N s/m per unit c)
  double slowest_dr = 0.0;             // phi^T Dr phi (N s/m)
  double critical_damping = 0.0;       // N s/m, c of damping_auto (0 if no mode is constrained)
};

// The modes at the state's pose (frames, com, pose) with the springs pulling toward
// `targets_world` (one per control point). Throws InputError for rigs over kMaxModeBones bones.
LinearModes linear_modes(const Scene& scene, const SimState& state,
                         const std::vector<Vec3>& targets_world);

// damping_auto: set state.damping_auto_value from the modes at the state's pose with the springs'
// settling stiffness (d = 0: k 1 for both laws; beyond the cap a capped spring has no stiffness
// along its pull, which would leave the whole-body translation a zero mode); counts
// state.damping_auto_updates. At the start and whenever the targets change (the pose then).
void update_auto_damping(const Scene& scene, SimState& state);

}  // namespace physik
