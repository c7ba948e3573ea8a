// What the implicit step's linearisation leaves out (why chain50 takes hundreds of steps), measured
// with a dense reference step: the solve mode's rule (physik/posing/posing_session.h) and energy
// guard (physik/engine/implicit_advance.h) around either the shipped O(n) implicit step or dense
// steps of backward Euler that linearise more of its terms (the variants below).
//
// The shipped step (physik/engine/implicit_step.h) solves (M + h D + h^2 K) a = tau - C - h K v:
// Gauss-Newton springs (the attachment's curvature dropped), M at the start of the step, and
// the velocity products C (Coriolis, centripetal, gyroscopic) explicit. MuJoCo's `implicitfast`
// integrator also skips the velocity products' derivative; its `implicit` includes it (MuJoCo
// 2.3.3 changelog, "Improvements to implicit integration").
//
// The dense step. The exact accelerations a(q, v) = M(q)^-1 (tau(q, v) - C(q, v)) are the
// articulated solve's (integrate_joint_space.h, solve_articulated) after the force stages;
// linearised about the start of the step, with q+ = q (+) h v+ and v+ = v + h a+ (the same Euler
// update as the shipped step):
//   a+ ~ a + A_q h (v + h a+) + A_v h a+   =>   (1 - h A_v - h^2 A_q) a+ = a + h A_q v     (L)
// A_q = da/dq, A_v = da/dv by central differences (eps 1e-5) in MuJoCo's qvel layout: root
// v_com world and w local, each ball's u local, each hinge's or universal's angle rates (the
// rig's joint model, rig.h "Locked axes"); a position perturbation turns a quaternion by its
// local axis (quat_integrate), as the Euler update does, or moves a hinge's angle. Dense, O(n^3),
// allocating: a measuring instrument, not an engine (the core stays O(n)). Variants of (L):
//   newton            A_q, A_v at the state: every term (velocity products, M(q), the springs'
//                     and the torsion's full tangents, the dampers)
//   newton_at_rest    A_q, A_v at the same pose with v = 0: the velocity products' derivatives
//                     dropped (C is quadratic in v, so its derivatives vanish at rest), and with
//                     them the pose derivatives of every velocity-dependent term (C, the dampers,
//                     the factor's torque); the pose terms of the forces and the inertia kept
//   newton_no_gyro    A_v from the scene with the gyroscopic torque off: the derivative of
//                     w x I w dropped, the rest of the velocity products kept
// At rest the pose terms are two: A_q(pose, 0) = M^-1 dtau/dq + (dM^-1/dq) tau, the forces'
// dependence on the pose (dtau/dq = -K + the curvature of the springs' attachments and of the
// torsion springs' log map, which Gauss-Newton drops) and the inertia's. Split:
//   pose_forces       A_q = M^-1 dtau/dq (M held at the start of the step), A_v at rest; dtau/dq
//                     from central differences of the applied wrench's generalised force
//                     (applied_generalised_force)
//   pose_inertia      A_q = -M^-1 K + (dM^-1/dq) tau (the shipped step's Gauss-Newton K, plus
//                     the inertia's term: newton_at_rest's A_q less pose_forces'), A_v at rest
//   shipped_dense     A_q = -M^-1 K, A_v at rest: the shipped step rebuilt densely (a check of
//                     the pieces: it takes the shipped step's steps). K = (P - M - h D) / h^2,
//                     with P, M as below and D = -M A_v(pose, 0)
// and the shipped step with the velocity products' derivative added, what an O(n) recursion with
// non-symmetric articulated inertias would solve
// (docs/engine.md "What the linearisation leaves out"):
//   shipped_dcdv      (P + h C_v) a+ = r, where P a_s = r is the shipped step's system
//                     (P = M + h D + h^2 K): (1 + h P^-1 M (M^-1 C_v)) a+ = a_s, with
//                     M^-1 C_v = A_v(pose, 0) - A_v(pose, v) (C is quadratic in v; the dampers
//                     are linear), and P^-1 and M^-1 column by column from the shipped implicit
//                     solve and the exact explicit solve, each with a unit generalised force
//                     added (both are linear in the applied forces)
// Units: s, rig units, kg, rad.
#pragma once

#include <Eigen/Dense>

#include "physik/engine/state.h"
#include "physik/model/scene.h"

namespace physik::experiments::linearisation {

// The O(n) step with implicit_linearisation full (physik/engine/implicit_pose_terms.h) and its
// term selections (PoseTermSelection, state.h), each the O(n) twin of a dense variant:
//   full              every pose term: newton_at_rest's system
//   full_forces       the forces' pose terms only: pose_forces' system
//   full_inertia      the inertia's only, on the Gauss-Newton K: pose_inertia's system
//   full_no_z         full without the turn of the joint accelerations below a moving joint ((4),
//                     the second motion vector of the recursion)
//   full_sketch       the shared DESIGN.md sketch: the transmitted wrench with the torsion torques
//                     in it, no torque-frame turn, the inertia only through that wrench
enum class Variant {
  kShipped,
  kNewton,
  kNewtonAtRest,
  kNewtonNoGyro,
  kShippedDcdv,
  kPoseForces,
  kPoseInertia,
  kShippedDense,
  kFull,
  kFullForces,
  kFullInertia,
  kFullNoZ,
  kFullSketch
};
// is the variant one of the O(n) steps (the shipped step and the full ones)
bool is_recursive(Variant v);
const char* variant_name(Variant v);

// qvel (root v_com world, root w local, ball u local, a hinge's or universal's angle rates):
// Rig::nv entries (the rig's joint model, rig.h "Locked axes")
Eigen::VectorXd joint_velocity(const Rig& rig, const SimState& state);
// A_q and A_v of (L) for a dense variant (every one but kShipped and kShippedDcdv), at the state
// (h: the step; the variants built on the shipped step's K take its P^-1 at h)
void derivatives(const Scene& scene, const SimState& state, Variant v, Eigen::MatrixXd& A_q,
                 Eigen::MatrixXd& A_v, double h = 0.05);
// The generalised force of the applied wrench at the joint state (the force stages' force_world
// and torque_world, from apply_forces): Q = sum_b J_b^T (F_b; T_b), summed leaves to root, O(n)
Eigen::VectorXd applied_generalised_force(const Scene& scene, const SimState& state);
// The response of the shipped implicit solve of h (implicit) or of the exact explicit solve to a
// unit generalised force on each dof, column by column: P^-1 = (M + h D + h^2 K)^-1, or M^-1
// (with `terms`, the pose terms an O(n) full variant keeps)
Eigen::MatrixXd unit_force_response(const Scene& scene, const SimState& state, bool implicit,
                                    double h, const PoseTermSelection& terms = {});
// one unguarded step of h of the variant (kShipped: physik::step with no splits)
void bare_step(const Scene& scene, SimState& state, double h, Variant v);

struct SolveCount {
  bool converged = false;  // every control point within the tolerance of its goal
  bool diverged = false;   // the state went non-finite
  int steps = 0;           // steps of the rule
  int substeps = 0;        // bare steps taken, the guard's rejected ones included
  double residual = 0.0;   // rig units, the largest at the end
};

// The exact accelerations at the joint state (the force stages, then the exact explicit solve)
Eigen::VectorXd accelerations(const Scene& scene, const SimState& state);

// The solve mode's rule with the guard around bare_step: h starts at dt, doubles after a step
// whose kinetic energy fell, halves (not below dt) after a split step, at most kSolveMaxDt; a
// bare step that adds energy or turns a joint more than kMaxStepRotation is undone and taken as
// two halves, params.implicit_max_splits deep. Stops at `tolerance` or after max_steps. With
// kShipped this is PosingSession::solve's step sequence (tests/experiments/linearisation_test.cpp).
// The targets must hold still (the dense steps do not move them): std::invalid_argument for a
// scene with a schedule, an interpolation, or damping auto.
SolveCount solve(const Scene& scene, SimState& state, double tolerance, int max_steps, Variant v);

}  // namespace physik::experiments::linearisation
