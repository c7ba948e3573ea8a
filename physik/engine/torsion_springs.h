// Torsion springs that enforce joint limits (paper Sec. 3.4; original fwik.py).
//
// For bone i with parent p, q_i is its rotation relative to its rest orientation in the parent's
// frame, and theta = log(q_i) its rotation vector; theta_k is the angle about local axis k
// (k = x, y, z of the rest frame carried by the parent, R_p R_rest_in_parent). For a limited axis
// with range [min, max], the spring engages `tolerance` x (max - min) inside each limit:
//   lo = min + tol (max - min),  hi = max - tol (max - min)
//   d  = lo - theta_k  if theta_k < lo;   d = hi - theta_k  if theta_k > hi;   else 0
//   linear  tau_k = k d              capped  tau_k = k min(|d|, c) sign(d)
// A locked axis (min == max) always pulls toward its value. The torque, turned to world axes
// (tau_world = R_p R_rest_in_parent tau_local), acts on the bone; its opposite acts on the parent.
// k in N m/rad, c in rad. A free root has no limits; a pinned root's hold it against the world
// (its parent frame is the world's, its opposite torque goes nowhere).
// A welded bone (rig.h "Welds") has no torsion spring: every scheme moves its group as one body.
//
// Locked axes (rig.h "Locked axes"). The above is the gauss-seidel scheme's (LockedAxes::kSprings:
// a locked axis is a spring pulling toward its value). The exact and implicit schemes remove the
// locked axes from a joint's coordinates (LockedAxes::kRemoved): a hinge or universal joint
// (joint_coordinates.h) has springs on its limited free axes only, on its angles t_k (the
// coordinates, read from q by hinge_coordinates), with the same dead zone and law:
//   Q_k = k d(t_k) (capped: k min(|d|, c) sign(d)),   U = sum_k U_t(d(t_k))
// a generalised force on coordinate k, applied as the torque tau = s0 Q_0 + s1 Q_1 on the bone
// and -tau on its parent (s_k its world axes: s_k . tau = Q_k, the axes being orthonormal). On
// the angles both torsion_torque variants are this one (-dU/dt exactly: no J_l). A weld by locks
// has none. A ball's springs (no locked axis) are as above. Its implicit block is
// S diag(k) S^T (world, on the relative rate: S^T of it is diag(k) on the angles), its modes'
// block the same.
//
// torsion_torque (params): `axes` is the above, the paper's (seed 000 Sec. 3.4, the original
// fwik.py). It is -dU/dtheta, the gradient in the rotation vector, not in the rotation: the
// relative angular velocity in the parent-rest frame w_pr = R_pr^T (w_i - w_p) turns theta at
// theta' = J_l(theta)^-1 w_pr (J_l the left Jacobian of SO(3)), so the torque that does the
// potential's work, tau.w_pr = -dU/dt, is
//   tau_pr = J_l(theta)^-T tau_local,  J_l^-T = 1 + [theta]x / 2 + b [theta]x^2,
//   b = 1/|theta|^2 - cot(|theta|/2) / (2 |theta|)   (1/12 at 0, 1/pi^2 at pi)
// (`gradient`). The two agree to first order in theta, and exactly where theta is along the
// excess (a joint locked on every axis, or one axis away from zero); on a bent 1-DOF joint (an
// elbow at 120 deg with its locked axes pulled) `axes` is not conservative: it does work around
// some closed paths. `gradient` is the force of the potential that `physik equilibrium`
// minimises (tune/equilibrium.h). The implicit step linearises `axes` by its tangent in theta
// (torsion_step_block_local below), which is not symmetric on a bent joint; a symmetric block in
// its place (R_pr diag(k) R_pr^T) makes long steps on bent joints stall: the solve mode then
// splits many more steps and leaves some unconverged (CHANGELOG.md has the measurements on
// ik_comparison's pinhead targets; tests/experiments/solve_mode_test.cpp). `gradient` enters by its
// Gauss-Newton block (the turn of J_l^-T with theta, times the torque, dropped): its tangent where
// the torque vanishes.
//
// Potential, per limited axis, of the dead-zone excess e (the d above, rad):
//   linear U = k e^2 / 2;  capped U = k e^2 / 2 (|e| <= c), k c (|e| - c/2) (|e| > c)
// The paper's torque `axes` is -dU/dtheta, the gradient in the rotation vector; `gradient` is
// the potential's own force (tune/equilibrium.h's caveat at large angles). Energies in J.
//
// The implicit step (implicit_step.h): a joint element, h^2 K_j on the ball's coordinates
// (torsion_step_block_local below, in world axes), and the torque pair -h K_j (w_i - w_p) on the
// right-hand side; with implicit_linearisation full also the torque's pose terms
// (implicit_pose_terms.h (5)), whose step reads the torques left in
// state.implicit.torsion_torque_world.
// Damping auto's modes: the block T diag(k) T^T (torsion_torque_frame, the tangent stiffness).
// MuJoCo's reference applies the same torques in same-forces mode; its own limits in
// exact-constraints mode.
#pragma once

#include <vector>

#include "physik/engine/force_stages.h"
#include "physik/engine/state.h"
#include "physik/model/params.h"
#include "physik/model/rig.h"

namespace physik {

// Dead-zone excess of angle theta (rad) for one limited axis; templated for Ceres' Jets.
template <typename T>
T torsion_excess(const AxisLimit& l, double tolerance, const T& theta) {
  const double band = tolerance * (l.max - l.min);
  const double lo = l.min + band, hi = l.max - band;
  if (theta < T(lo)) return T(lo) - theta;
  if (theta > T(hi)) return T(hi) - theta;
  return T(0);
}

// Excess per local axis of a bone with local rotation q (0 on free axes), rad.
Vec3 torsion_excess(const std::array<AxisLimit, 3>& limits, double tolerance, const Quat& q);

// U of one axis' excess (rad), J.
double torsion_spring_potential(SpringLaw law, double k, double cap, double excess);

// U of the torsion springs of a pose (0 when torsion_k is 0), J.
double torsion_potential(const Rig& rig, const EngineParams& params, const Pose& pose);

// The local torque (N m, per rest axis) for joint angles theta of bone i.
Vec3 torsion_torque_local(const std::array<AxisLimit, 3>& limits, const Vec3& theta,
                          const EngineParams& params);

// Its stiffness per axis, -d tau_k / d theta_k (N m/rad): k on an engaged axis (linear, or capped
// within the cap), 0 outside the band or beyond the cap. For the implicit step and the modes.
Vec3 torsion_stiffness_local(const std::array<AxisLimit, 3>& limits, const Vec3& theta,
                             const EngineParams& params);

// The stiffness the implicit step uses: the same, but beyond the cap of a capped spring the
// secant k c / |d| instead of 0, a majoriser of the potential as for the capped control spring
// (spring_step_stiffness, control_springs.h).
Vec3 torsion_step_stiffness_local(const std::array<AxisLimit, 3>& limits, const Vec3& theta,
                                  const EngineParams& params);

// The matrix T that turns a local per-axis torque (torsion_torque_local) into the torque on the
// bone in world axes: R_pr for `axes`, R_pr J_l(theta)^-T for `gradient`.
Mat3 torsion_torque_frame(const Rig& rig, const EngineParams& params,
                          const Quat& parent_orient_world, int bone, const Vec3& theta);

// The implicit step's torsion block in the parent-rest frame (N m/rad; implicit_step.h), from the
// per-axis step stiffness k (torsion_step_stiffness_local) at joint angles theta. A relative turn
// dphi_pr moves theta by J_l^-1 dphi_pr, so the torque's tangent (its frame held) is
//   axes:      diag(k) J_l^-1                 (not symmetric on a bent joint)
//   gradient:  J_l^-T diag(k) J_l^-1          (symmetric, positive semi-definite)
// For `axes` the symmetric part loses its negative eigenvalues (clipped to 0), keeping the
// antisymmetric part. The symmetric part is positive semi-definite, and the block the tangent,
// where every axis is engaged with one k (it is then k (1 + b W^2), W = [theta]x, eigenvalues
// 1 - b |theta|^2 > 0 below pi) and on an elbow bent exactly about its free axis. It is
// indefinite where an axis that is not engaged couples to an engaged one (x alone engaged, bent
// about y: the x-z block is [k (1 - b theta^2), -k theta / 4; -k theta / 4, 0]; an elbow bent a
// little off its hinge, by a part second order in the off-hinge angle: -6.7e-6 k at theta =
// (-0.785, 0.01, 0)) or where the engaged axes' k differ (a capped spring at its secant), and
// with it the step's matrix could be singular at some step length. So the clip acts during
// many transients; at a converged elbow it removes nothing, and near it only that second-order
// part, so long steps still converge as Newton's method there.
Mat3 torsion_step_block_local(const Vec3& k, const Vec3& theta, TorsionTorque torque);

// J_l(theta)^-T (above).
Mat3 left_jacobian_inverse_transpose(const Vec3& theta);

// A bone's torsion spring acts: it has a limited axis (a root only when pinned).
inline bool has_torsion_spring(const Rig& rig, int bone) {
  const auto& l = rig.bone_limit[bone];
  return l[0].limited || l[1].limited || l[2].limited;
}

// How a bone's torsion spring acts in a joint model (LockedAxes): on the rotation vector (every
// limited axis under kSprings, a ball's under kRemoved), on a hinge's or universal's limited
// free angles (kRemoved), or not at all (no limited axis left: a weld, a free root).
enum class TorsionKind { kNone, kRotationVector, kHingeAngles };
TorsionKind torsion_kind(const Rig& rig, LockedAxes locked, int bone);

// The angles a bone's springs measure (rad, per local axis x, y, z) at local rotation q: the
// rotation vector of q, or for kHingeAngles the joint's angles on its free axes
// (hinge_coordinates) and the locked values on its locked axes, which are never engaged.
Vec3 torsion_angles(const Rig& rig, TorsionKind kind, int bone, const Quat& q);

// The world orientation a bone's torsion spring holds against: its parent's, the world's for the
// root.
inline Quat torsion_parent_orient(const Rig& rig, const BoneFrames& frames, int bone) {
  const int p = rig.bone_parent[bone];
  return p < 0 ? Quat::Identity() : frames.orient_world[p];
}

// N = d/dtheta (J_l(theta)^-T tau) at fixed tau (left_jacobian_inverse_transpose): the gradient
// torque's curvature term, 1/rad times tau's units.
Mat3 left_jacobian_inverse_transpose_derivative(const Vec3& theta, const Vec3& tau);

// The pose terms' share of bone i's torsion block (world axes on the relative rate, N m/rad):
// -[tau_world]x, and for the gradient torque -R_pr N(theta, tau_local) J_l^-1 R_pr^T.
Mat3 torsion_pose_block(const Mat3& R_pr, const Vec3& theta, const Vec3& tau_local,
                        TorsionTorque torque, const Vec3& tau_world);

// Requires state.pose to hold the current local rotations.
void apply_torsion_springs(const Rig& rig, const EngineParams& params, SimState& state);

// The element's stages (forces.h): U of the state's pose; the implicit step's blocks at the pose
// (state.implicit.torsion_stiffness, state.implicit.torsion_block_world; with `full` the pose
// terms' share and the torques, state.implicit.torsion_torque_world: tangents), then
// -h K_j (w_i - w_p) (rate); h^2 K_j as the balls' joint blocks (augment); damping auto's blocks.
double torsion_springs_potential(const Scene& scene, const SimState& state);
void torsion_springs_tangents(const Scene& scene, const ImplicitStage& stage, SimState& state);
void torsion_springs_rate(const Scene& scene, const ImplicitStage& stage, SimState& state);
void torsion_springs_augment(const Scene& scene, const ImplicitStage& stage, SimState& state);
void torsion_springs_mode_stiffness(const Scene& scene, const SimState& state,
                                    const std::vector<Vec3>& targets, ModeStiffness& out);
// The pose-terms step (implicit_pose_terms.h): each joint's torque, as torsion_springs_tangents
// left it (state.implicit.torsion_torque_world, world axes, turning with the parent).
void torsion_springs_pose_forces(const Scene& scene, const SimState& state, PoseForces& out);

}  // namespace physik
