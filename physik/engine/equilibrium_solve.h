// The equilibrium solve: the rest pose the solve mode is after, found as a minimisation of the
// potential U(q) of the force list (potential.h: control springs toward their goals, orientation
// targets, aims, pins, torsion springs, gravity, contacts), each trial one implicit step at rest.
//
// Sources: J. Nocedal and S. J. Wright, Numerical Optimization, 2nd ed., Springer 2006, ch. 4
// (trust-region methods, Algorithm 4.1: the ratio of the actual to the predicted reduction) and
// ch. 10.3 (Levenberg-Marquardt as a trust region on a quadratic model); K. Levenberg, Quart. Appl.
// Math. 2 (1944) 164-168 and D. Marquardt, SIAM J. Appl. Math. 11 (1963) 431-441 (the damped
// step); R. Featherstone, Rigid Body Dynamics Algorithms, Springer 2008, ch. 7 (the O(n)
// articulated-body recursion: articulated_body.h); D. Baraff and A. Witkin, SIGGRAPH 1998 (the
// implicit step: implicit_step.h).
//
// The step. At v = 0 the implicit step of length h (implicit_step.h (1), velocity products and
// the rates -h K v all zero at rest) solves (M + h D + h^2 K) a = tau(q), then v+ = h a and
// q+ = q (+) h v+, so dq = h^2 a solves
//   (K + D/h + M/h^2) dq = tau = -grad U                                                  (1)
// Levenberg-Marquardt's step on U with the damping matrix Lambda = M/h^2 + D/h: the rig's own
// inertia (with the joints' armature, below) and dampers (the end dampers c, the
// angular-velocity factor's (1 - f)/dt I_com) as the metric. Where U is flat (a dead zone, no
// gravity) the step is the one of least metric: it moves the least mass, as the rig's dynamics do.
// K is each element's tangent (implicit_step.h: the Gauss-Newton stiffness, the secant beyond a
// cap; under implicit_linearisation full also the pose terms, implicit_pose_terms.h). tau is
// exactly -grad U only with torsion_torque gradient: the paper's `axes` torque is the gradient in
// the rotation vector, not in the rotation, and does work around closed paths on a bent joint
// (torsion_springs.h), so the solve always takes the gradient torque (use_solve_mode,
// physik/posing/posing_session.h); where a scene's limits are engaged at large bends, the paper's
// scheme rests elsewhere than U's minimum, by what docs/engine.md "The equilibrium solve" says.
// An iteration is one O(n) recursion (solve_implicit) and the joint-space update
// (integrate_joint_space), with the velocities then set to zero: nothing carries from one
// iteration to the next but q and h.
//
// The armature. The rig's inertia alone makes a poor metric on a long chain: rotating a joint
// near the root moves every bone below it, turning one near the tip moves almost nothing, so the
// least-metric step curls the far end (a whip) and moves the effector little for a large turn;
// measured on ik_comparison's chains (another seed than the report's), the median iterations were
// 35 on chain10 and over 200 on chain50, where 6 of 10 solves stopped at a saddle half a reach
// short. A joint armature A (MuJoCo's dof armature: a rotor inertia on every axis of every ball)
// adds A/h^2 per joint coordinate to the metric, M -> M + A, which prices every joint's turn alike
// as DLS's step does. A = armature x rig_inertia_scale (the rig's inertia about its root's head):
// 0.2 by default, chosen on that seed for the fewest iterations that keep pinhead's secondary
// motion (ik_comparison's measure) at the time-stepping solve's: at 0.2 chain10 took 11 median
// iterations, chain50 26, pinhead 8; at 1, 8, 18 and 8 with pinhead's secondary motion lower.
// As h grows the metric vanishes against K, so the armature changes the path, and which member of
// a family of rest poses the solve ends on, not where U is least.
//
// The model and its predicted decrease. With m(dq) = U - tau^T dq + dq^T K dq / 2, (1) gives
// dq^T K dq = tau^T dq - dq^T Lambda dq for any K, so
//   pred = m(0) - m(dq) = (tau^T dq + dq^T Lambda dq) / 2                                   (2)
// which is positive whenever the step moves. Both terms come from the recursion's body
// accelerations at v = 0 (a_i about o_i: alpha_i, lin_i; a point x of body i moves by
// h^2 (lin_i + alpha_i x (x - o_i))), with F_i, n_i the force stage's force and torque about the
// centre of mass:
//   tau^T dq        = h^2 sum_i (F_i . a_com,i + n_i . alpha_i)
//   dq^T M dq / h^2 = h^2 sum_i (m_i |a_com,i|^2 + alpha_i^T I_i alpha_i)
//                     (+ the armature's h^2 A |alpha_i - alpha_parent|^2 per ball joint)
//   dq^T D dq / h   = h^3 sum_i (c (|a_head,i|^2 + |a_tail,i|^2)
//                               + (1 - f)/dt alpha_i^T I_i alpha_i)
// exact at q (the bodies' motion is linear in dq there), for every joint type the recursion takes.
//
// The trust region (Nocedal & Wright Algorithm 4.1, the step length h in place of the radius: the
// step grows with h, as h^2 M^-1 tau where the metric dominates and toward K^+ tau as h grows):
//   rho = (U(q) - U(q+)) / pred
//   rho < kAcceptRatio or a joint turned by more than kMaxTurn: refused, q restored, h /= 2
//   accepted: h /= 2 where rho < 1/4, h *= 2 where rho > 3/4 (not past max_step)
// U never rises, so the solve cannot diverge; a step the model mispredicts only shortens h.
//
// Piecewise smooth elements. The torsion springs' dead zone (U = 0 inside the band, k e^2 / 2
// beyond, C^1 at the band's edge) and the caps (linear beyond the cap) make U piecewise smooth;
// the model takes the piece at q: an axis inside its band has no stiffness in (1), one beyond its
// cap its secant k c / |e| (a majoriser of the capped potential, as the capped control springs',
// control_springs.h). A step that carries an axis from inside its band past its edge finds U
// above the model by the engaged part, k e_out^2 / 2 (e_out how far past the edge it ends);
// rho falls and h shortens until the step ends near the edge, where the next step's model has
// the axis engaged. Inside the band the minimum is not unique (a family of rest poses); which
// member the solve ends on depends on its path, as the time-stepping solve's does on its own.
//
// Contacts (a ground, obstacles, self-collision) enter by their springs (U_contact) and their
// elements in (1); their dampers are left out of (2)'s metric (pred is then a little low, which
// only makes h grow sooner). Their static friction does not: its anchors stretch with a contact's
// slip over time (ground_contacts.h), and here nothing moves in time, so the solve's rest pose on
// a floor is U's minimum without friction, where the time-stepping solve's anchors may hold
// another.
//
// The stop (goals by their own measure, measures.h): converged when every goal is within its
// tolerance; stalled when no goal short of its tolerance improved by stall_fraction over
// stall_iterations accepted iterations (GoalProgress), or when h falls below min_step (the
// model fails at every length); stationary when pred falls to U's round-off (a stationary point
// of U short of a goal: out of reach, against a limit). Then the goals short and by how much are
// the caller's to report.
//
// No allocation (the workspace is sized once: size_equilibrium). Units: s, J, rad, rig units.
#pragma once

#include "physik/engine/implicit_workspace.h"
#include "physik/engine/measures.h"
#include "physik/engine/run_summary.h"
#include "physik/engine/state.h"
#include "physik/model/scene.h"

namespace physik {

constexpr double kAcceptRatio = 1e-4;  // 1, the least rho a step is accepted with
constexpr double kMaxTurn = 1.0;       // rad, the most a step may turn a joint (as the
                                       // implicit step's guard, implicit_advance.h)
constexpr int kMaxBacktracks = 6;      // halvings of a step along its direction, at most
constexpr double kGrowth = 2.0;        // 1, h's growth after a step the model predicted well
constexpr double kArmature = 0.2;      // 1, the joints' armature: of rig_inertia_scale (above)

struct EquilibriumRule {
  GoalTolerance tolerance;       // the goals' (measures.h)
  int max_iterations = 200;      // trials at most, accepted or refused
  int stall_iterations = 6;      // the stall rule's window, accepted iterations
  double stall_fraction = 0.01;  // 1
  double initial_step = 1.0;     // s, h of the first trial
  double max_step = 1e4;         // s, the longest h
  double min_step = 1e-6;        // s, below it the trust region gives up (stalled)
  double armature = kArmature;   // 1, every ball joint's armature in the metric, as a fraction
                                 // of rig_inertia_scale (0: the rig's inertia and dampers alone)
};

struct EquilibriumResult {
  bool converged = false;          // every goal within its tolerance
  bool stalled = false;            // the stall rule, or h below min_step
  bool stationary = false;         // pred at U's round-off short of a goal
  bool out_of_iterations = false;  // max_iterations short of a goal, still improving
  int iterations = 0;              // one O(n) recursion each
  int refused = 0;                 // of them, refused by the trust region
  int backtracks = 0;              // halvings along a step (forward kinematics and U, no
                                   // recursion)
  double potential = 0.0;          // J, U at the end
  double step = 0.0;               // s, h at the end
};

struct EquilibriumWorkspace {
  JointStateSnapshot before;   // where a refused step returns to
  GoalProgress progress;       // the stall rule
  double inertia_scale = 0.0;  // kg m^2, rig_inertia_scale of the rig
  double armature = 0.0;       // kg m^2, this solve's joint armature
};

// The rig's inertia about its root's head at rest, sum_b m_b |c_b - head_0|^2, kg m^2: the scale
// of the armature (EquilibriumRule::armature).
double rig_inertia_scale(const Rig& rig);

// Sized for the scene's rig and goals, with room for `anchor_capacity` friction anchors (the
// state's contact data's: contact_data.h), so that a solve allocates nothing (allocates).
void size_equilibrium(const Scene& scene, std::size_t anchor_capacity, EquilibriumWorkspace& ws);

// The goal targets into the springs: every control point pulls at its goal (the rest of the
// scene's schedule, from the state's step on, played at once), nothing interpolating.
void pull_at_goals(const Scene& scene, SimState& state);

// Minimise U from the state's pose (its velocities set to zero first). The scene must be in a
// joint-space scheme (the state carries the joint-space state: set_pose). `observer`, when given,
// sees the state after every accepted iteration (its StepStats: max_residual, potential_energy).
EquilibriumResult equilibrium_solve(const Scene& scene, SimState& state, EquilibriumWorkspace& ws,
                                    const EquilibriumRule& rule,
                                    const StepObserver& observer = nullptr);

// The model along the step after solve_implicit of length h at rest: its slope tau^T dq and its
// metric term dq^T Lambda dq (J, dq the whole step); the predicted fall of U for the share alpha
// of the step, alpha tau^T dq - alpha^2 dq^T K dq / 2 with dq^T K dq = slope - metric by (1).
struct StepModel {
  double slope = 0.0;   // J
  double metric = 0.0;  // J
  double decrease(double alpha) const {
    return alpha * slope - 0.5 * alpha * alpha * (slope - metric);
  }
};
// `armature`: the joints' armature in the step, kg m^2 (EquilibriumWorkspace::armature).
StepModel step_model(const Scene& scene, const SimState& state, double h, double armature = 0.0);
// (2): step_model's decrease of the whole step, J.
double predicted_decrease(const Scene& scene, const SimState& state, double h,
                          double armature = 0.0);

}  // namespace physik
