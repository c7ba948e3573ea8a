#include "physik/engine/implicit_advance.h"

#include <algorithm>
#include <cmath>

#include "physik/engine/engine.h"
#include "physik/engine/forces.h"
#include "physik/engine/implicit_step.h"
#include "physik/engine/integrate_joint_space.h"
#include "physik/engine/potential.h"

namespace physik {

double mechanical_energy(const Scene& scene, const SimState& s) {
  return kinetic_energy(scene.rig, s) + spring_potential(scene, s);
}

namespace {

void save(const SimState& s, JointStateSnapshot& snap) {
  snap.root_com_world = s.root_com_world;
  snap.root_vel_world = s.root_vel_world;
  snap.root_orient_world = s.root_orient_world;
  std::copy(s.joint_vel_local.begin(), s.joint_vel_local.end(), snap.joint_vel_local.begin());
  std::copy(s.pose.bone_local_rotation.begin(), s.pose.bone_local_rotation.end(),
            snap.bone_local_rotation.begin());
}

void restore(const Rig& rig, const JointStateSnapshot& snap, SimState& s) {
  s.root_com_world = snap.root_com_world;
  s.root_vel_world = snap.root_vel_world;
  s.root_orient_world = snap.root_orient_world;
  std::copy(snap.joint_vel_local.begin(), snap.joint_vel_local.end(), s.joint_vel_local.begin());
  std::copy(snap.bone_local_rotation.begin(), snap.bone_local_rotation.end(),
            s.pose.bone_local_rotation.begin());
  world_from_joint_space(rig, s);
}

// the largest joint rotation of a step of h just taken, rad: h |u| of every ball and of the root's
// w (their new velocities, which the step turned them by)
double largest_rotation(const SimState& s, double h) {
  double w = 0.0;
  for (const Vec3& u : s.joint_vel_local) w = std::max(w, u.squaredNorm());
  return h * std::sqrt(w);
}

// one substep of h at `depth`, split in two while it adds energy (below max_depth); returns the
// recursion sweeps taken
int substep(const Scene& scene, SimState& s, double h, int depth, int max_depth, double floor) {
  const bool guarded = depth < max_depth;
  if (guarded) save(s, s.implicit_snapshots[depth]);
  const double e0 = guarded ? mechanical_energy(scene, s) : 0.0;
  apply_forces(scene, s);
  solve_implicit(scene, s, h);
  integrate_joint_space(scene.rig, h, s);
  if (!guarded || (largest_rotation(s, h) <= kMaxStepRotation &&
                   mechanical_energy(scene, s) <= e0 + kEnergyGrowthTolerance * (std::max(e0, 0.0) + floor))) {
    return 1;
  }
  restore(scene.rig, s.implicit_snapshots[depth], s);
  const int first = substep(scene, s, 0.5 * h, depth + 1, max_depth, floor);
  return first + substep(scene, s, 0.5 * h, depth + 1, max_depth, floor);
}

}  // namespace

JointSolveStats advance_implicit(const Scene& scene, SimState& s, double h) {
  const double v = scene.speed_tol();
  const double floor = 0.5 * scene.rig.total_mass() * v * v;  // J, E_floor
  // init_state sized one snapshot per depth; the bound guards a state sized for other params
  const int max_depth = std::min(scene.params.implicit_max_splits,
                                 static_cast<int>(s.implicit_snapshots.size()) - 1);
  const int sweeps = substep(scene, s, h, 0, max_depth, floor);
  if (sweeps > 1) ++s.implicit_split_steps;
  s.implicit_max_substeps = std::max(s.implicit_max_substeps, sweeps);
  JointSolveStats stats;
  stats.passes = sweeps;
  stats.mismatch = 0.0;
  return stats;
}

}  // namespace physik
