#include "physik/engine/implicit_advance.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "physik/engine/forces.h"
#include "physik/engine/implicit_step.h"
#include "physik/engine/integrate_joint_space.h"
#include "physik/engine/measures.h"
#include "physik/engine/newton_euler.h"
#include "physik/engine/potential.h"

namespace physik {

double mechanical_energy(const Scene& scene, SimState& s) {
  return kinetic_energy(scene.rig, s) + potential_energy(scene, s);
}

void save_joint_state(const SimState& s, JointStateSnapshot& snap) {
  const JointSpaceState& js = s.joint_space;
  snap.root_com_world = js.root_com_world;
  snap.root_vel_world = js.root_vel_world;
  snap.root_orient_world = js.root_orient_world;
  std::copy(js.joint_vel_local.begin(), js.joint_vel_local.end(), snap.joint_vel_local.begin());
  std::copy(js.hinge_angle.begin(), js.hinge_angle.end(), snap.hinge_angle.begin());
  std::copy(s.pose.bone_local_rotation.begin(), s.pose.bone_local_rotation.end(),
            snap.bone_local_rotation.begin());
  snap.friction_anchors = s.contact.anchors;  // keeps its capacity: no allocation once grown
}

void restore_joint_state(const Rig& rig, const JointStateSnapshot& snap, SimState& s) {
  JointSpaceState& js = s.joint_space;
  js.root_com_world = snap.root_com_world;
  js.root_vel_world = snap.root_vel_world;
  js.root_orient_world = snap.root_orient_world;
  std::copy(snap.joint_vel_local.begin(), snap.joint_vel_local.end(), js.joint_vel_local.begin());
  std::copy(snap.hinge_angle.begin(), snap.hinge_angle.end(), js.hinge_angle.begin());
  std::copy(snap.bone_local_rotation.begin(), snap.bone_local_rotation.end(),
            s.pose.bone_local_rotation.begin());
  s.contact.anchors = snap.friction_anchors;
  world_from_joint_space(rig, s);
}

namespace {

// the largest joint rotation of a step of h just taken, rad: h |u| of every ball and of the root's
// w (their new velocities, which the step turned them by); a hinge's or universal's |t'| is its
// relative turn's rate too (its axes are orthonormal)
double largest_rotation(const SimState& s, double h) {
  double w = 0.0;
  for (const Vec3& u : s.joint_space.joint_vel_local) w = std::max(w, u.squaredNorm());
  return h * std::sqrt(w);
}

// E_round, J: what the rig's own round-off can change in E (implicit_advance.h)
double roundoff_energy(const Scene& scene, const SimState& s, double e0) {
  double coordinate = 0.0;  // rig units, the largest |coordinate| of a bone's end
  for (int i = 0; i < scene.rig.nbone; ++i) {
    coordinate = std::max({coordinate, s.frames.head_world[i].cwiseAbs().maxCoeff(),
                           s.frames.tail_world[i].cwiseAbs().maxCoeff()});
  }
  const double r = coordinate + scene.rig.reference_length();
  return kRoundoffGrowth * std::numeric_limits<double>::epsilon() *
         (std::abs(e0) + scene.rig.total_mass() * scene.gravity_world.norm() * r);
}

// the guard's bounds for one step
struct Guard {
  BareStep bare;
  const void* context;
  int max_depth;         // halvings
  double floor;          // J, E_floor
  int checks_left;       // attempts this step may still check (kImplicitMaxChecks)
  bool deepest = false;  // a substep of this step was taken unchecked (max_depth, or no checks
                         // left)
  // the state's KE and U as the last check measured them (J), while the state is the one it
  // measured (every change of the state below clears it): a substep that starts there, and the
  // step's caller, take them instead of measuring the same state again
  MeasuredEnergy measured;
};

// The check of a (sub)step of h just taken from energy e0 (J): its joints turned at most
// kMaxStepRotation and its energy grew at most the tolerance. `growth` gets E_1 - e0 (J).
bool step_holds(const Scene& scene, SimState& s, double h, double e0, Guard& g, double& growth) {
  g.measured = {true, kinetic_energy(scene.rig, s), potential_energy(scene, s)};
  growth = (g.measured.kinetic + g.measured.potential) - e0;
  if (largest_rotation(s, h) > kMaxStepRotation) return false;
  // E_round >= 0 is measured (a pass over the bones) only for a growth past the rest of the bound
  const double bound = kEnergyGrowthTolerance * (std::max(e0, 0.0) + g.floor);
  return growth <= bound || growth <= bound + roundoff_energy(scene, s, e0);
}

// The ground and obstacle contacts of the state's frames (mechanical_energy has just detected them
// into the contact data's at_frames) into its reached, each point bone-local and its depth stored
// as d + n . p: from the step's start, d_0 = depth - n . p_0 (first order: the depth grows as the
// point moves against n). True when there are any.
bool keep_reached_contacts(SimState& s) {
  s.contact.reached.clear();
  for (const Contact& c : s.contact.at_frames) {
    if (c.other_bone >= 0) continue;  // a self-contact is split between its bones (self_contacts.h)
    Contact r = c;
    r.depth = c.depth + c.normal_world.dot(c.point_world);
    r.point_world =
        s.frames.orient_world[c.bone].conjugate() * (c.point_world - s.com_world[c.bone]);
    s.contact.reached.push_back(r);
  }
  return !s.contact.reached.empty();
}

// whether the force stage at the step's start pushes at the contact `c` (the same bone, obstacle
// and feature: collision.h Contact), so that it is in the step already
bool pushed_at_start(const SimState& s, const Contact& c) {
  for (const Contact& a : s.contact.found) {
    if (a.bone == c.bone && a.other_bone < 0 && a.obstacle == c.obstacle &&
        a.feature == c.feature && a.normal_force > 0.0) {
      return true;
    }
  }
  return false;
}

// The shipped bare step with the reached contacts that its start's force stage does not push at
// linearised from the start as well: each a spring k along n of depth d_0 (<= 0 where the start
// does not touch, to round-off otherwise), force k d_0 n (pulling where d_0 < 0: the spring's
// first-order force at the depth the step meets), an element like a ground contact's
// (ground_contacts.h).
void take_step_with_reached(const Scene& scene, SimState& s, double h) {
  ForceStage stage;
  stage.step = h;
  apply_forces(scene, s, stage);
  const double k = scene.params.contact_k;
  for (const Contact& c : s.contact.reached) {
    if (pushed_at_start(s, c)) continue;  // in the step already
    const Vec3& n = c.normal_world;
    const Vec3 p0 = s.com_world[c.bone] + s.frames.orient_world[c.bone] * c.point_world;
    const double d0 = c.depth - n.dot(p0);
    apply_force_at(s, c.bone, k * d0 * n, p0);
    ContactElement e;
    e.bone = c.bone;
    e.point_world = p0;
    e.stiffness = k * n * n.transpose();
    s.contact.elements.push_back(e);
  }
  solve_implicit(scene, s, h);
  integrate_joint_space(scene.rig, h, s);
}

// One attempt at a (sub)step of h from energy e0 (J), the state saved at `depth`: the bare step,
// and where the check rejects it, the shipped bare step again with the contacts it reached. True
// when the last attempt holds; `energy` gets its E (J).
bool attempt(const Scene& scene, SimState& s, double h, int depth, Guard& g, double e0,
             double& energy) {
  g.measured.known = false;
  g.bare(scene, s, h, g.context);
  double growth = 0.0;
  bool held = step_holds(scene, s, h, e0, g, growth);
  if (!held && g.bare == take_implicit_step && scene.collision.any() && keep_reached_contacts(s)) {
    restore_joint_state(scene.rig, s.implicit.snapshots[depth], s);
    g.measured.known = false;
    take_step_with_reached(scene, s, h);
    held = step_holds(scene, s, h, e0, g, growth);
    if (held) ++s.implicit.retaken_steps;
  }
  energy = e0 + growth;
  return held;
}

constexpr int kNoLower = -1;  // substep's answer: halving did not help this half

// What a rejected attempt ended in, the measure a half of it is held to.
struct Rejected {
  double energy;    // J, E at its end
  double rotation;  // rad, its largest joint rotation
};

// One substep of h at `depth`; returns the substeps taken, or kNoLower. A substep the check
// rejects (attempt) is split in two, each checked in turn, below max_depth and while the step
// has checks left. A first half that halving did not help answers kNoLower, and the whole step,
// retaken as it was, is kept: one whose energy ends no lower than its whole step's
// (`whole.energy`), or that turns a joint too far and at least as far as its whole step did
// (`whole.rotation`: a contact so stiff that every step pushes the overlap out at once turns the
// bones as far at any step length). A second half starts elsewhere and is held to neither. A
// substep that starts from a state that is not finite is taken as it is: no step length helps it,
// and the run monitor ends the run.
int substep(const Scene& scene, SimState& s, double h, int depth, Guard& g, Rejected whole) {
  ImplicitWorkspace& im = s.implicit;
  // the deepest split (or implicit_max_splits 0), or the step's checks spent: taken unchecked
  if (depth >= g.max_depth || g.checks_left <= 0) {
    g.deepest = g.max_depth > 0;
    g.measured.known = false;
    g.bare(scene, s, h, g.context);
    return 1;
  }
  save_joint_state(s, im.snapshots[depth]);
  // the second half of a split starts where its first half's check measured E
  const double e0 =
      g.measured.known ? g.measured.kinetic + g.measured.potential : mechanical_energy(scene, s);
  if (!std::isfinite(e0)) {
    g.measured.known = false;
    g.bare(scene, s, h, g.context);
    return 1;
  }
  double energy = 0.0;
  --g.checks_left;
  if (attempt(scene, s, h, depth, g, e0, energy)) return 1;
  const double rotation = largest_rotation(s, h);
  if (rotation > kMaxStepRotation ? rotation >= whole.rotation : energy >= whole.energy) {
    return kNoLower;
  }
  restore_joint_state(scene.rig, im.snapshots[depth], s);
  g.measured.known = false;
  int taken = substep(scene, s, 0.5 * h, depth + 1, g, {energy, rotation});
  if (taken != kNoLower) {
    // the second half starts where the first ended, not where its whole did: neither how far it
    // turns nor where its energy ends says whether halving helps it (in the contacts
    // experiment's dropped coil a bone met in a second half turns it 2.85 rad where its whole
    // step turned 2.72, and one that ends higher than its whole is resolved by its own halves),
    // so it is judged as a step of its own
    const double inf = std::numeric_limits<double>::infinity();
    const int second = substep(scene, s, 0.5 * h, depth + 1, g, {inf, inf});
    taken = second == kNoLower ? kNoLower : taken + second;
  }
  if (taken != kNoLower) return taken;
  // halving does not lower the energy: this (sub)step as its attempt took it
  --g.checks_left;
  restore_joint_state(scene.rig, im.snapshots[depth], s);
  attempt(scene, s, h, depth, g, e0, energy);
  ++im.unresolved_steps;
  return 1;
}

}  // namespace

void take_implicit_step(const Scene& scene, SimState& s, double h, const void* /*context*/) {
  ForceStage stage;
  stage.step =
      h;  // a self-contact's damper and friction are capped for this step (self_contacts.h)
  apply_forces(scene, s, stage);
  solve_implicit(scene, s, h);
  integrate_joint_space(scene.rig, h, s);
}

int advance_implicit(const Scene& scene, SimState& s, double h, BareStep bare, const void* context,
                     MeasuredEnergy* end) {
  ImplicitWorkspace& im = s.implicit;
  const double v = scene.speed_tol();
  // size_state sized one snapshot per depth; the bound guards a state sized for other params
  Guard g{bare,
          context,
          std::min(scene.params.implicit_max_splits, static_cast<int>(im.snapshots.size()) - 1),
          0.5 * scene.rig.total_mass() * v * v,
          kImplicitMaxChecks,
          false,
          MeasuredEnergy{}};
  const double inf = std::numeric_limits<double>::infinity();
  const int substeps = substep(scene, s, h, 0, g, {inf, inf});
  if (substeps > 1) ++im.split_steps;
  if (g.deepest) ++im.deepest_steps;
  im.max_substeps = std::max(im.max_substeps, substeps);
  if (end) *end = g.measured;
  return substeps;
}

}  // namespace physik
