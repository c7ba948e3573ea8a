// One implicit step of the scene's dt (scheme implicit), guarded by the rig's energy: where
// the linearisation adds energy, the step is taken again as two half steps (docs/engine.md "The
// implicit scheme"; stable for any coefficients).
//
// solve_implicit (implicit_step.h) is one Newton step of backward Euler with the forces
// linearised at the start of the step. On a linear spring and damper it never adds energy
// (implicit_step.h: E+ - E = -h c v+^2 - ... <= 0, for every h, c, k). On the rig it is linear
// only to first order in the step's rotations: a step can spin a bone about an axis where its
// inertia is tiny and gain energy the exact dynamics do not (tests/implicit_advance_test.cpp: the
// tuning study's 0.1x rig at c = 100). So every step is checked. With the targets held
// for the step, the mechanical energy
//   E = KE + U_control(this step's targets) + U_torsion + U_gravity + U_contact
//                                                   (J; potential.h potential_energy)
// may not grow by more than kEnergyGrowthTolerance (E + E_floor) + E_round, E_floor = M speed_tol^2
// / 2 (the run monitor's floor: the kinetic energy of the rig moving at its rest speed), E_round =
// kRoundoffGrowth eps (|E| + M |g| R) the growth the rig's own round-off can show (eps the double's
// epsilon, R the largest |coordinate| of a bone's end plus Rig::reference_length: gravity's
// potential is of the order M |g| R whatever its reference), and no joint may turn by more than
// kMaxStepRotation in it (1 rad: the step is linear in the rotations only to
// first order, and where it turns a joint this far the energy test can pass by chance: at
// dt = 25.6 s a solve of pinhead's hand turned it 5.6 rad about its own axis, a direction with
// almost no stiffness and no end damping; the substeps of a split that held energy alone then
// blew up to NaN; the shipped scenes turn a joint at most 0.48 rad in a step at dt 0.05). A step
// that does either is undone and:
//   1. retaken with the contacts it reached (scenes with a ground or obstacles): the linearised
//      step knows only the contacts its start touches, so a bone resting on a stiff floor, whose
//      rest depth W / k is below a coordinate's resolution (k = 1e20: 1e-19 against 7e-18 at
//      z = 0.06), starts each step just off it and falls freely into the spring (a 1 kg bone at
//      dt 0.05: 2.4 cm into 1e20 N/m, 6e16 J), which halving took 19 levels to land softly.
//      Each ground or obstacle contact of the rejected step's end that its start did not touch
//      enters the retaken step as a spring k along its normal n, linearised from the start
//      (depth d_0 = d - n . (p_0 - p) <= 0, force k d_0 n: the spring's first-order force, which
//      the solve balances where the step meets the surface), like a ground contact
//      (ground_contacts.h);
//   2. otherwise taken as two half steps, each checked in turn, at most
//      params.implicit_max_splits halvings deep (default 8: a substep of dt / 256 is accepted as
//      it is, and the step counts in implicit_deepest_steps, which the run reports once; 0: the
//      bare linearised step, never split). Where halving does not help, the whole step is kept
//      as it was taken (implicit_unresolved_steps) and the run monitor judges the energy
//      (run_monitor.h): a first half whose energy ends no lower than its whole step's, or that
//      turns a joint too far and at least as far as its whole step did. Both are contacts so
//      stiff that no step the guard can take resolves them: bones overlapping at the start
//      under contact_k 1e20 are pushed apart by a whole overlap in every step, whatever its
//      length, so a half turns them as far as its whole. A second half starts where the first
//      ended, not where its whole did, so neither measure of the whole says whether halving
//      helps it: it is judged as a step of its own (held to the whole's measures, the contacts
//      experiment's dropped coil diverged where a bone met in a second half turned it 2.85 rad
//      against its whole's 2.72, and halving it further resolved it). A step checks at most
//      kImplicitMaxChecks attempts (the retake of a whole step kept included; as many as a
//      whole tree checks at the default implicit_max_splits 8, so only a deeper setting meets
//      it); past that every substep still to take is taken unchecked, at the length it has
//      then, and the step counts in implicit_deepest_steps: bones overlapping under a
//      contact too stiff for any step length are otherwise halved to 2^implicit_max_splits
//      substeps of one step (2^20, 3.7 s, at implicit_max_splits 20). A substep
//      whose start is not finite is taken as it is (no step length helps it; the run monitor
//      ends the run). The substeps
// integrate the same equations of motion (damping c, the factor's damper (1 - f) / dt I_com,
// every spring); as h -> 0 the step tends to the exact dynamics, which add no energy with the
// targets held, so the halving ends. On every shipped scene no step is split (their largest
// growth in a step is 2.3e-7 of E, hand_tight), so their runs are as before, bit for bit.
// Summaries of implicit runs count implicit_split_steps, implicit_retaken_steps,
// implicit_unresolved_steps and implicit_deepest_steps.
// The world view, the ball state and the velocities are undone from a snapshot of the joint
// state (the joint-space state is the whole state: integrate_joint_space.h), held in
// state.implicit.snapshots (one per depth, sized by size_state): no allocation per step.
// Units: s, J.
#pragma once

#include "physik/engine/state.h"
#include "physik/model/scene.h"

namespace physik {

// The checked attempts one implicit step may take (above): 2^8 - 1, the checks of a whole tree
// at the default implicit_max_splits 8 (whose substeps at depth 8 are taken unchecked).
constexpr int kImplicitMaxChecks = 255;

constexpr double kEnergyGrowthTolerance = 1e-6;  // 1, of E + E_floor
constexpr double kRoundoffGrowth = 64.0;         // 1, of eps (|E| + M |g| R): E_round
constexpr double kMaxStepRotation = 1.0;         // rad, the most a (sub)step may turn a joint

// The bare step the guard takes and checks: the forces, a solve and the joint-space update of
// length h (s), from the joint-space state (what the guard saves and restores). `context` is the
// caller's, passed through (the linearisation study plugs its dense steps in here).
using BareStep = void (*)(const Scene& scene, SimState& state, double h, const void* context);

// The shipped bare step: apply_forces, solve_implicit (implicit_step.h), integrate_joint_space.
void take_implicit_step(const Scene& scene, SimState& state, double h, const void* context);

// The energy of a state as the guard's check measured it (J): known when the (sub)step that ended
// in the state was checked (not one taken unchecked at the deepest split).
struct MeasuredEnergy {
  bool known = false;
  double kinetic = 0.0;    // J, kinetic_energy
  double potential = 0.0;  // J, potential_energy
};

// The step after update_targets: `bare` of length h, retaken and split as above (the retake only
// with the shipped bare step). Returns the substeps taken (1 unless split); counts a split step in
// state.implicit.split_steps, the most substeps of one step in state.implicit.max_substeps, and
// the retaken, unresolved and deepest (sub)steps above. `end`, when given, gets the energy of the
// state the step ended in as its last check measured it (the same values kinetic_energy and
// potential_energy give; known false when that (sub)step went unchecked), so the step's measures
// need not measure it again.
// h: the step's length, s (step() passes params.dt; a longer one integrates the same equations
// of motion, whose dampers are set by params.dt, with a longer step: the solve mode).
int advance_implicit(const Scene& scene, SimState& state, double h,
                     BareStep bare = take_implicit_step, const void* context = nullptr,
                     MeasuredEnergy* end = nullptr);

// The joint-space state (the whole state: integrate_joint_space.h) into a snapshot sized for the
// rig (size_joint_snapshot, implicit_workspace.h), and back with the world view rebuilt from it;
// the guard's undo, and the equilibrium solve's (equilibrium_solve.h). No allocation.
void save_joint_state(const SimState& state, JointStateSnapshot& snapshot);
void restore_joint_state(const Rig& rig, const JointStateSnapshot& snapshot, SimState& state);

// The mechanical energy the guard holds: KE + potential_energy (J; springs, gravity, contacts).
double mechanical_energy(const Scene& scene, SimState& state);

}  // namespace physik
