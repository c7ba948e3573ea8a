// The exact static pose of a scene (docs/engine.md "Ceres"): the minimum of the spring
// potential over the rig's configuration, found with Ceres, to measure PhysIK's final-pose error.
//
// Unknowns: the root head position x_0 (world, rig units) and every bone's local rotation q_i
// (unit quaternion, rest-relative, bone frame; Ceres' EigenQuaternionManifold keeps it unit), in
// the joint model of the scene's scheme (rig.h "Locked axes"): for exact and implicit a hinge's
// or universal joint's angles instead (q_i = L exp(t0 e_a) exp(t1 e_b), joint_coordinates.h; its
// springs on the angles, torsion_springs.h) and a weld by locks held at L; for gauss-seidel every
// bone a ball, its locked axes springs.
// Forward kinematics as physik/kinematics.h. The potential (J) is
//
//   U = sum_c U_c(|a_c - t_c|) + sum_{i>0} sum_{k in x,y,z, limited} U_t(d_ik)
//
//   control springs (physik/control_springs.h), d = |a - t|, k in N/m, cap c in rig units:
//     linear  U_c = k d^2 / 2;   capped  U_c = k d^2 / 2 (d <= c),  k c (d - c/2) (d > c)
//   torsion springs (physik/torsion_springs.h), theta = rotation vector of q_i, per limited axis
//   the dead-zone distance d_ik to [lo, hi] (the limit minus the engage band), k_t in N m/rad:
//     linear  U_t = k_t d^2 / 2; capped  U_t = k_t d^2 / 2 (|d| <= c_t), k_t c_t (|d| - c_t/2)
//
// Least-squares form: residual vectors whose squared norm is 2 U per term, so Ceres' cost
// (1/2 sum |r|^2) is U exactly:
//   r_c = sqrt(k) (a - t) s(d),  s = 1 (d <= c),  s = sqrt(c (2 d - c)) / d (d > c)   (3 per point)
//   r_ik = sqrt(k_t) d_ik  (linear),  sign(d) sqrt(k_t c_t (2|d| - c_t)) beyond the cap
// Derivatives by automatic differentiation (a templated copy of the FK chain and the dead zone).
// Levenberg-Marquardt from a start pose (the scene's initial pose unless given); with fewer
// constraints than DOF the minimum is a family and LM lands on a member near the start.
//
// Caveat, measured not assumed: PhysIK's control forces are the exact negative gradient of U_c,
// but its torsion torque tau = k_t d(theta) about the rest axes is the gradient of U_t with
// respect to theta, not with respect to a small rotation (the two differ by the inverse right
// Jacobian of SO(3), equal only for small or axis-aligned theta). With no limit engaged the
// equilibria coincide; with engaged limits at large angles they may differ slightly.
// Damping and the angular-velocity factor vanish at rest and do not enter.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "physik/engine/engine.h"
#include "physik/engine/potential.h"
#include "physik/model/scene.h"

namespace physik::tune {

struct EquilibriumOptions {
  const Pose* start = nullptr;  // start pose (nullptr: the scene's initial pose)
  int max_iterations = 500;     // Ceres iterations
  bool verbose = false;         // Ceres progress on stdout
};

struct EquilibriumResult {
  Pose pose;                             // the minimiser
  BoneFrames frames;                     // its FK (physik::forward_kinematics)
  std::vector<Vec3> targets_world;       // (ncontrol) the goal targets used (after the schedule)
  std::vector<double> control_distance;  // (ncontrol) |a - t| at the minimum, rig units
  std::vector<Vec3> torsion_excess;      // (nbone) dead-zone distance per local axis, rad
  double control_potential = 0.0;        // J
  double torsion_potential = 0.0;        // J
  double potential = 0.0;                // J, their sum (= Ceres' final cost)
  double gradient_max_norm = 0.0;        // Ceres' final gradient, max norm
  int iterations = 0;
  bool converged = false;  // Ceres reported CONVERGENCE
  std::string ceres_brief, ceres_full;
};

// Every control point's goal after the whole schedule has played (rig units, world).
std::vector<Vec3> final_targets(const Scene& scene);

// The potentials of one spring (J) and the torsion excess are the engine's
// (physik/engine/potential.h): control_spring_potential, torsion_spring_potential, torsion_excess.

// The total potential U of a pose (J): what the solver minimises.
double scene_potential(const Scene& scene, const Pose& pose);

EquilibriumResult solve_equilibrium(const Scene& scene, const EquilibriumOptions& options = {});

// The largest distance between corresponding heads and tails of two poses (rig units).
double max_pose_distance(const BoneFrames& a, const BoneFrames& b);

nlohmann::json equilibrium_to_json(const Scene& scene, const EquilibriumResult& e);

}  // namespace physik::tune
