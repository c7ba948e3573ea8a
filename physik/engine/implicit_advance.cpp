#include "physik/engine/implicit_advance.h"

#include <algorithm>
#include <cmath>

#include "physik/engine/forces.h"
#include "physik/engine/implicit_step.h"
#include "physik/engine/integrate_joint_space.h"
#include "physik/engine/measures.h"
#include "physik/engine/potential.h"

namespace physik {

double mechanical_energy(const Scene& scene, const SimState& s) {
  return kinetic_energy(scene.rig, s) + potential_energy(scene, s);
}

namespace {

void save(const SimState& s, JointStateSnapshot& snap) {
  snap.root_com_world = s.root_com_world;
  snap.root_vel_world = s.root_vel_world;
  snap.root_orient_world = s.root_orient_world;
  std::copy(s.joint_vel_local.begin(), s.joint_vel_local.end(), snap.joint_vel_local.begin());
  std::copy(s.pose.bone_local_rotation.begin(), s.pose.bone_local_rotation.end(),
            snap.bone_local_rotation.begin());
  snap.friction_anchors = s.friction_anchors;  // keeps its capacity: no allocation once grown
}

void restore(const Rig& rig, const JointStateSnapshot& snap, SimState& s) {
  s.root_com_world = snap.root_com_world;
  s.root_vel_world = snap.root_vel_world;
  s.root_orient_world = snap.root_orient_world;
  std::copy(snap.joint_vel_local.begin(), snap.joint_vel_local.end(), s.joint_vel_local.begin());
  std::copy(snap.bone_local_rotation.begin(), snap.bone_local_rotation.end(),
            s.pose.bone_local_rotation.begin());
  s.friction_anchors = snap.friction_anchors;
  world_from_joint_space(rig, s);
}

// the largest joint rotation of a step of h just taken, rad: h |u| of every ball and of the root's
// w (their new velocities, which the step turned them by)
double largest_rotation(const SimState& s, double h) {
  double w = 0.0;
  for (const Vec3& u : s.joint_vel_local) w = std::max(w, u.squaredNorm());
  return h * std::sqrt(w);
}

// the guard's bounds for one step
struct Guard {
  BareStep bare;
  const void* context;
  int max_depth;  // halvings
  double floor;   // J, E_floor
};

// one substep of h at `depth`, split in two while it adds energy (below max_depth); returns the
// substeps taken
int substep(const Scene& scene, SimState& s, double h, int depth, const Guard& g) {
  const bool guarded = depth < g.max_depth;
  if (guarded) save(s, s.implicit_snapshots[depth]);
  const double e0 = guarded ? mechanical_energy(scene, s) : 0.0;
  g.bare(scene, s, h, g.context);
  if (!guarded || (largest_rotation(s, h) <= kMaxStepRotation &&
                   mechanical_energy(scene, s) <=
                       e0 + kEnergyGrowthTolerance * (std::max(e0, 0.0) + g.floor))) {
    return 1;
  }
  restore(scene.rig, s.implicit_snapshots[depth], s);
  const int first = substep(scene, s, 0.5 * h, depth + 1, g);
  return first + substep(scene, s, 0.5 * h, depth + 1, g);
}

}  // namespace

void take_implicit_step(const Scene& scene, SimState& s, double h, const void* /*context*/) {
  ForceSelection forces;
  forces.step = h;  // a self-contact's damper and friction are capped for this step (contacts.h)
  apply_forces(scene, s, forces);
  solve_implicit(scene, s, h);
  integrate_joint_space(scene.rig, h, s);
}

int advance_implicit(const Scene& scene, SimState& s, double h, BareStep bare,
                     const void* context) {
  const double v = scene.speed_tol();
  // init_state sized one snapshot per depth; the bound guards a state sized for other params
  const Guard g{
      bare, context,
      std::min(scene.params.implicit_max_splits, static_cast<int>(s.implicit_snapshots.size()) - 1),
      0.5 * scene.rig.total_mass() * v * v};
  const int substeps = substep(scene, s, h, 0, g);
  if (substeps > 1) ++s.implicit_split_steps;
  s.implicit_max_substeps = std::max(s.implicit_max_substeps, substeps);
  return substeps;
}

}  // namespace physik
