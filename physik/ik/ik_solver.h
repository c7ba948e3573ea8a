// The common interface of the classic IK solvers (the baselines PhysIK is measured against).
//
// Every solver works on the same Rig and Pose as the engine (physik/kinematics.h):
//   - the root's head is an anchor (it does not translate); the root's rotation is three
//     rotational DOF, every other bone rotates relative to its parent; a pinned root's limits
//     (against its rest frame in the world: two locked axes make a hinge) are respected like any
//     bone's, and a fixed root, with the bones welded into its body, never turns
//     (held_by_world);
//   - a bone's rotation q_i (rest-relative, in the bone's rest frame) is changed by rotations
//     about the axes of that rest frame, i.e. q_i <- exp(theta e_k) q_i. In the world this is a
//     rotation by theta about a_k = R_parent R_rest_in_parent e_k through the bone's head. For a
//     hinge (one free axis) this adds theta to the joint angle exactly;
//   - joint limits are the rig's per-axis intervals on the rotation vector of q_i; a solver that
//     respects them clamps the rotation vector component-wise after each change
//     (clamp_to_limits), locked axes never move.
//
// Goals (effectors): a point at fraction alpha along a bone (0 = head, 1 = tail) pulled onto a
// world target, and/or the bone's frame turned onto a target orientation (world<-bone, as
// BoneFrames::orient_world). They are sorted into DFS order of their bones before solving, as
// the IK guide (seed 001, "Advice") recommends, so effectors earlier in the hierarchy are served
// first. Only the Jacobian solvers (jacobian.cpp: DLS, the transpose) take orientations; the
// others refuse a goal that carries one (InputError).
//
// Residual: the largest distance of any effector from its target (rig units). A solve converges
// when it is below the tolerance, by default 1e-4 of the chain's reach (the longest
// root-to-effector path over the goals). It stops early when the residual has stalled (an
// unreachable target, a limit) and then reports converged = false.
// Orientation residual: the largest angle |phi|, phi = log(q_target q^-1) (world axes, rad), of
// any goal's frame from its target orientation. Its tolerance is the position tolerance over the
// orientation length L (by default the reach): a turn of the whole chain by the tolerance in rad
// moves its far end by the position tolerance. Converged = both under their tolerances.
//
// Degenerate states: a joint whose bone is colinear with its parent's bone is a degenerate state
// for angle-adjusting solvers (guide, "Advice"); before solving, every such joint on an
// effector's path gets a small bend (colinear_bump) within its limits.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "physik/model/kinematics.h"

namespace physik {

struct IkGoal {
  int bone = -1;                     // bone index
  double alpha = 1.0;                // 0 = head, 1 = tail
  Vec3 target_world = Vec3::Zero();  // rig units
  bool has_position = true;          // false: an orientation-only goal (alpha, target unread)
  bool has_orientation = false;      // true: also turn the bone's frame onto orientation_world
  Quat orientation_world = Quat::Identity();  // world<-bone, unit (as BoneFrames::orient_world)
};

enum class IkMethod {
  kFabrik,              // fabrik.cpp
  kCcd,                 // ccd.cpp
  kJacobianTranspose,   // jacobian.cpp
  kDampedLeastSquares,  // jacobian.cpp
  kMassSpring,          // mass_spring.cpp
  kRotation,            // rotation_method.cpp
};

enum class JacobianKind { kAnalytic, kFiniteDifference };
// How the rotation method picks the axis of a socket joint (seed 002, "Major stumble blocks").
enum class SocketMode {
  kVirtualBone,  // axis perpendicular to the goal vector and the virtual bone (as shipped)
  kTwistBend,    // twist about the bone's own axis, then bend: the author's unshipped fix
};
// Which limit shape the rotation method enforces on socket joints before the rig's box limits.
enum class ConeShape {
  kNone,        // box limits only
  kCircular,    // circular cone on the swing, radius = the smaller half-range (seed 002 Fig 3)
  kElliptical,  // elliptical cone with the x and z half-ranges as semi-axes (seed 002)
};

struct IkOptions {
  int max_iterations = 1000;
  double tolerance = 0.0;            // rig units; 0 = tolerance_fraction * reach
  double tolerance_fraction = 1e-4;  // 1, of the chain's reach
  int stall_window = 30;             // iterations; stop when the residual improved by less than
  double stall_fraction = 1e-7;      //   stall_fraction * reach over that many iterations
  bool respect_limits = true;        // clamp to the rig's joint limits
  double colinear_bump = 1e-2;       // rad, bend given to colinear joints (0 = off)

  // Jacobian transpose / DLS (jacobian.cpp)
  JacobianKind jacobian = JacobianKind::kAnalytic;
  double fd_step = 1e-4;            // rad, finite-difference step (the guide uses 0.01)
  double lambda = 0.0;              // rig units, DLS damping; 0 = lambda_fraction * reach
  double lambda_fraction = 0.02;    // 1
  double max_angle_step = 0.3;      // rad, largest joint change per iteration
  int max_step_halvings = 8;        // backtracking line search on the squared goal error (0 = off)
  double max_error_fraction = 0.1;  // 1, each goal's error is clamped to this fraction of the
                                    //    reach before a Jacobian step (Buss's D_max)
  double orientation_length = 0.0;  // rig units, L: orientation rows and errors are scaled by
                                    //   it into rig units (0 = the chain's reach)
  double orientation_tolerance = 0.0;  // rad; 0 = the position tolerance / L

  // mass-spring (mass_spring.cpp)
  Vec3 gravity_world = Vec3::Zero();  // rig units/s^2 (e.g. (0, 0, -9.81)); zero = off
  double dt = 1.0 / 60.0;             // s, Verlet time step
  double velocity_keep = 0.5;         // 1, fraction of the Verlet velocity kept per iteration
  int constraint_passes = 8;          // distance-constraint passes per iteration

  // rotation method (rotation_method.cpp)
  double rotation_gain = 0.8;     // 1, fraction of the tangential error corrected per joint
  double rotation_damping = 0.8;  // 1, factor per joint up the hierarchy (0: only the
                                  //    effector's bone moves, 1: no damping)
  double springiness = 0.05;      // 1, fraction of the way to the natural (rest) position
                                  //    added to the goal vector
  SocketMode socket_mode = SocketMode::kTwistBend;
  ConeShape cone_shape = ConeShape::kElliptical;
};

struct IkReport {
  std::string solver;
  int iterations = 0;
  double residual = 0.0;              // rig units, the largest effector distance at the end
  std::vector<double> residuals;      // rig units, one per goal in the order given (0: no position)
  double orientation_residual = 0.0;  // rad, the largest |phi| at the end
  std::vector<double> orientation_residuals;  // rad, one per goal (0: no orientation)
  double orientation_tolerance = 0.0;         // rad, the one used
  double orientation_length = 0.0;            // rig units, L, the one used
  bool converged = false;
  bool stalled = false;    // stopped because the residual stopped improving
  double tolerance = 0.0;  // rig units, the one used
  double reach = 0.0;      // rig units
  double time_s = 0.0;     // wall time of the solve
};

const char* to_string(IkMethod m);
// "fabrik", "ccd", "jt", "dls", "mass-spring", "rotation"; false when unknown.
bool ik_method_from_string(const std::string& name, IkMethod& out);

// Solve: `pose` is the start on entry and the result (the last iterate) on exit. Goals with bad
// bone indices or non-finite targets throw InputError. Never returns NaN: a non-finite iterate
// restores the best pose seen and stops.
IkReport solve_ik(IkMethod method, const Rig& rig, const std::vector<IkGoal>& goals, Pose& pose,
                  const IkOptions& options = {});

// --- helpers shared by the solvers ------------------------------------------------------------

// Longest root-to-effector path length over the goals (rig units): sum of the bone lengths above
// the effector's bone plus alpha times its own length (Rig::chain_length).
double chain_reach(const Rig& rig, const std::vector<IkGoal>& goals);
// The goals sorted by bone in DFS order (stable), with their original indices.
std::vector<int> dfs_goal_order(const std::vector<IkGoal>& goals);
// Distance of every goal's point from its target (rig units), in the order given (0 for a goal
// without a position).
void goal_residuals(const BoneFrames& frames, const std::vector<IkGoal>& goals,
                    std::vector<double>& out);
// The turn phi = log(q_target q^-1) (world axes, rad, |phi| <= pi) from a goal's frame to its
// target orientation (the orientation targets' error, physik/engine/orientation_springs.h).
Vec3 goal_orientation_error(const BoneFrames& frames, const IkGoal& goal);
// |phi| of every goal (rad), in the order given (0 for a goal without an orientation).
void goal_orientation_residuals(const BoneFrames& frames, const std::vector<IkGoal>& goals,
                                std::vector<double>& out);
// Bones on a root-to-effector path (ancestors of a goal's bone, and that bone): the only ones
// the solvers move; a bone the world holds (held_by_world) is never among them.
std::vector<char> active_bones(const Rig& rig, const std::vector<IkGoal>& goals);
// The bone cannot move: a fixed root, or a bone welded into a fixed root's body (rig.h).
bool held_by_world(const Rig& rig, int bone);
// Unit quaternion of a rotation vector (exp map; inverse of rotation_vector).
Quat quat_from_rotation_vector(const Vec3& v);
// Project q onto the bone's box limits: clamp the rotation vector component-wise (the root's
// too: a pinned root's limits; a free or fixed root has none).
Quat clamp_to_limits(const Rig& rig, int bone, const Quat& q);
// World orientation of bone i's rest frame under its parent's current orientation:
// P_i = R_parent R_rest_in_parent (root: R_rest). Rotation axes of bone i are P_i e_k.
Quat rest_frame_world(const Rig& rig, const BoneFrames& frames, int bone);
// Apply a world rotation `delta_world` about bone i's head to its local rotation:
// q_i <- P_i^-1 delta P_i q_i.
Quat rotate_local(const Rig& rig, const BoneFrames& frames, int bone, const Quat& q_local,
                  const Quat& delta_world);
// Give every active joint colinear with its parent (angle < 1e-6 rad) a bend of `bump` rad
// about its first free axis other than y, within limits. Returns the number bumped.
int bump_colinear_joints(const Rig& rig, const std::vector<char>& active, double bump, Pose& pose);
// Recover local rotations from desired tail positions (FABRIK, mass-spring; guide "Fabrik
// Solver": rotations in local space). Bones are visited in DFS order; an active bone turns by the
// smallest rotation (in its rest frame) that aims its tail at tail_world[i] from its current
// head, which keeps its twist; inactive bones keep their local rotation.
void aim_bones_at(const Rig& rig, const std::vector<char>& active,
                  const std::vector<Vec3>& tail_world, bool respect_limits, Pose& pose,
                  BoneFrames& frames);

// --- the solvers, one file each (called through solve_ik) ----------------------------------------

// One iteration of a solver: `frames` are FK of `pose` on entry; it updates `pose` (the loop
// recomputes FK). `goals` are DFS-sorted, `active` marks the bones on effector paths.
struct IkProblem {
  const Rig* rig = nullptr;
  std::vector<IkGoal> goals;           // DFS-sorted
  std::vector<char> active;            // (nbone)
  double reach = 0.0;                  // rig units
  double tolerance = 0.0;              // rig units
  double orientation_length = 0.0;     // rig units, L (IkOptions)
  double orientation_tolerance = 0.0;  // rad
  bool any_orientation = false;        // some goal has an orientation
  IkOptions options;
};
IkReport solve_fabrik(const IkProblem& problem, Pose& pose);                 // fabrik.cpp
IkReport solve_ccd(const IkProblem& problem, Pose& pose);                    // ccd.cpp
IkReport solve_jacobian(const IkProblem& problem, bool damped, Pose& pose);  // jacobian.cpp
IkReport solve_mass_spring(const IkProblem& problem, Pose& pose);            // mass_spring.cpp
IkReport solve_rotation_method(const IkProblem& problem, Pose& pose);        // rotation_method.cpp

// The iteration loop every solver shares: residual, tolerance, stall detection, best-pose
// fallback on non-finite iterates, timing. `iterate` performs one iteration.
using IkIterate = std::function<void(Pose& pose, BoneFrames& frames)>;
IkReport run_ik_loop(const char* name, const IkProblem& problem, Pose& pose,
                     const IkIterate& iterate);

// The free rotation axes of the active bones (columns of the Jacobian): (bone, local axis),
// locked axes left out when limits are respected, welded bones (no joint of their own) left out.
void ik_dofs(const Rig& rig, const std::vector<char>& active, bool respect_limits,
             std::vector<int>& dof_bone, std::vector<int>& dof_axis);

// The Jacobian of the stacked goal points (3 per goal with a position, DFS-sorted goals of `pb`),
// then of the goals' orientations (3 per goal with one, the angular rows scaled by L), with
// respect to the listed rotation axes, analytic or by the guide's memoised finite difference
// (jacobian.cpp).
void goal_jacobian(const IkProblem& pb, const BoneFrames& frames, const std::vector<int>& dof_bone,
                   const std::vector<int>& dof_axis, JacobianKind kind, double fd_step,
                   Eigen::MatrixXd& J);
// The mass-spring solver's length constraint between two nodes of masses ma, mb (kg): both move
// along their line about the mass-weighted centre until |a - b| = L (mass_spring.cpp).
void mass_weighted_length(Vec3& a, Vec3& b, double ma, double mb, double L);
// Seed 002's cone limits on a socket joint (rotation_method.cpp): q = swing * twist (twist about
// the bone's y); the swing's rotation vector (x, z) is pulled radially into the cone around the
// centre of the rig's x and z ranges -- a circle of the smaller half-range or the ellipse of both
// half-ranges -- and the twist is clamped to the y range. Bones without limits on both x and z,
// or with one of them locked (a bend joint), are returned unchanged.
Quat clamp_to_cone(const Rig& rig, int bone, const Quat& q, ConeShape shape);

// The scale-target distributor of the guide ("Scale Target Solver"), scale_target.cpp.
//   constrained   (min/max given, one per node): spread goal^(1/N) from the root, clamp each
//                 node to [min, max] and redistribute what is left over the remaining nodes;
//   unconstrained (all goal components positive): every node gets goal^(1/N);
//   negative      (a component <= 0): node scales interpolate the global scale linearly from
//                 the root's current scale to the goal, converted to local scales.
// `scales` holds one local scale per node (only scales[0] is read in the negative branch).
enum class ScaleBranch { kConstrained, kUnconstrained, kNegative };
ScaleBranch distribute_scale(const Vec3& goal, std::vector<Vec3>& scales,
                             const std::vector<Vec3>& min_scale = {},
                             const std::vector<Vec3>& max_scale = {});

}  // namespace physik
