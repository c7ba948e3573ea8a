#include "physik/engine/forces.h"

#include <iterator>

#include "physik/engine/aim_springs.h"
#include "physik/engine/contact_data.h"
#include "physik/engine/control_springs.h"
#include "physik/engine/damping.h"
#include "physik/engine/gravity.h"
#include "physik/engine/ground_contacts.h"
#include "physik/engine/newton_euler.h"
#include "physik/engine/orientation_springs.h"
#include "physik/engine/pins.h"
#include "physik/engine/self_contacts.h"
#include "physik/engine/torsion_springs.h"

namespace physik {

namespace {

// the stage functions of the elements whose own take other arguments
void damping_apply(const Scene& scene, SimState& s, const ForceStage&) {
  apply_damping(scene.rig, scene.params, s);
}
void control_apply(const Scene& scene, SimState& s, const ForceStage&) {
  apply_control_springs(scene, s);
}
void orientation_apply(const Scene& scene, SimState& s, const ForceStage&) {
  apply_orientation_springs(scene, s);
}
void aim_apply(const Scene& scene, SimState& s, const ForceStage&) {
  apply_aim_springs(scene, s);
}
void pins_apply(const Scene& scene, SimState& s, const ForceStage&) {
  apply_pins(scene, s);
}
void torsion_apply(const Scene& scene, SimState& s, const ForceStage&) {
  apply_torsion_springs(scene.rig, scene.params, s);
}
void gravity_apply(const Scene& scene, SimState& s, const ForceStage&) {
  apply_gravity(scene, s);
}
double gravity_state_potential(const Scene& scene, const SimState& s) {
  return gravity_potential(scene, s.frames);
}
// a self-contact's damper and friction are capped for the step the forces are taken over
double stage_step(const Scene& scene, const ForceStage& stage) {
  return stage.step > 0.0 ? stage.step : scene.params.dt;
}
void ground_apply(const Scene& scene, SimState& s, const ForceStage& stage) {
  apply_ground_contacts(scene, s, stage_step(scene, stage));
}
void self_apply(const Scene& scene, SimState& s, const ForceStage& stage) {
  apply_self_contacts(scene, s, stage_step(scene, stage));
}
void ground_rate(const Scene& scene, const ImplicitStage& stage, SimState& s) {
  ground_contacts_rate(scene, stage.h, s);
}
void ground_augment(const Scene& scene, const ImplicitStage& stage, SimState& s) {
  ground_contacts_augment(scene, stage.h, s);
}
void self_rate(const Scene& scene, const ImplicitStage& stage, SimState& s) {
  self_contacts_rate(scene, stage.h, s);
}
void self_augment(const Scene& scene, const ImplicitStage& stage, SimState& s) {
  self_contacts_augment(scene, stage.h, s);
}

// does `stage` apply element e (the MuJoCo reference applies only what MuJoCo does not)
bool applies(const ForceElement& e, const ForceStage& stage) {
  switch (stage.for_) {
    case ForceStage::For::kEngine:
      return true;
    case ForceStage::For::kMujocoSameForces:
      return e.mujoco != MujocoSide::kMujocosOwn;
    case ForceStage::For::kMujocoExactConstraints:
      return e.mujoco == MujocoSide::kApplied;
  }
  return true;
}

// The list: one row per element, its file the element's name (damping.h, control_springs.h, ...),
// a null entry a stage it leaves out:
//   damping          no potential (a damper only removes energy); in the modes its end dampers'
//                    unit matrix D1 and the angular-velocity factor's Dr are damping auto's own
//                    (mode_operators.h, linear_modes_dense.h), not a stiffness; no pose forces
//                    (the pose terms are taken at rest, where a damper pulls nothing)
//   gravity          a constant force at each centre of mass: no stiffness, no damping; no pose
//                    forces: implicit_linearisation full takes a free root only, and a uniform
//                    field moves a free rig's every body alike, so its share of the rest
//                    accelerations does not change with the pose (tests/experiments/
//                    pose_terms_test.cpp checks the step with gravity against the dense one)
//   ground contacts, self contacts
//                    no modes: contacts come and go between the target changes at which damping
//                    auto chooses c; a contact's own damper damps its normal motion
//                    (ground_contacts.h, self_contacts.h); no pose forces: a contact's point
//                    slides over its capsule as the pose moves, and contacts come and go within a
//                    step, so under full a contact keeps its Gauss-Newton element (augment) only
//   orientation springs, aim springs, pins
//                    not toward targets in the ledger's sense: their targets hold still through
//                    a run (a schedule moves control points only), so their potential at the
//                    start is energy the rig was given, as the torsion springs' is (a posing
//                    session that moves one restarts the ledger from its state at each solve)
// clang-format off
const ForceElement kForces[] = {
  // name              apply          potential                   rate                  augment
  //   modes (K)                        pose forces
  //   MuJoCo                         toward targets, rate first
  {"damping",         damping_apply, nullptr,                    nullptr,              damping_augment,
     nullptr,                        nullptr,
     MujocoSide::kApplied,           false, false},
  {"control springs", control_apply, control_springs_potential,  control_springs_rate, control_springs_augment,
     control_springs_mode_stiffness, control_springs_pose_forces,
     MujocoSide::kApplied,           true,  false},
  {"orientation springs", orientation_apply, orientation_springs_potential, orientation_springs_rate, orientation_springs_augment,
     orientation_springs_mode_stiffness, orientation_springs_pose_forces,
     MujocoSide::kApplied,           false, false},
  {"aim springs",     aim_apply,     aim_springs_potential,      aim_springs_rate,     aim_springs_augment,
     aim_springs_mode_stiffness,     aim_springs_pose_forces,
     MujocoSide::kApplied,           false, false},
  {"pins",            pins_apply,    pins_potential,             pins_rate,            pins_augment,
     pins_mode_stiffness,            pins_pose_forces,
     MujocoSide::kApplied,           false, false},
  {"torsion springs", torsion_apply, torsion_springs_potential,  torsion_springs_rate, torsion_springs_augment,
     torsion_springs_mode_stiffness, torsion_springs_pose_forces,
     MujocoSide::kSameForcesOnly,    false, false},
  {"gravity",         gravity_apply, gravity_state_potential,    nullptr,              nullptr,
     nullptr,                        nullptr,
     MujocoSide::kMujocosOwn,        false, false},
  {"ground contacts", ground_apply,  ground_contacts_potential,  ground_rate,          ground_augment,
     nullptr,                        nullptr,
     MujocoSide::kMujocosOwn,        false, true},
  {"self contacts",   self_apply,    self_contacts_potential,    self_rate,            self_augment,
     nullptr,                        nullptr,
     MujocoSide::kMujocosOwn,        false, true},
};
// clang-format on

}  // namespace

ForceList force_elements() {
  return {std::begin(kForces), std::end(kForces)};
}

void apply_forces(const Scene& scene, SimState& s, const ForceStage& stage) {
  // torsion reads s.pose, which init_state and the end of every step keep in sync with frames
  prepare_bodies(scene.rig, scene.params, s);
  const bool contacts = stage.for_ == ForceStage::For::kEngine;
  if (contacts) detect_step_contacts(scene, s.frames, s.contact);
  for (const ForceElement& e : force_elements()) {
    if (applies(e, stage)) e.apply(scene, s, stage);
  }
}

void pose_forces(const Scene& scene, const SimState& s, PoseForces& out) {
  for (const ForceElement& e : force_elements()) {
    if (e.pose_forces) e.pose_forces(scene, s, out);
  }
}

void implicit_rates(const Scene& scene, const ImplicitStage& stage, SimState& s) {
  // the contacts' terms (rate_first) first, then the others' in the list's order: the order the
  // step has always summed -h K v into the forces in (any order is the same sum up to round-off;
  // this one keeps every run's results bit for bit)
  for (const ForceElement& e : force_elements()) {
    if (e.rate && e.rate_first) e.rate(scene, stage, s);
  }
  for (const ForceElement& e : force_elements()) {
    if (e.rate && !e.rate_first) e.rate(scene, stage, s);
  }
}

void implicit_augment(const Scene& scene, const ImplicitStage& stage, SimState& s) {
  for (const ForceElement& e : force_elements()) {
    if (e.augment) e.augment(scene, stage, s);
  }
}

void mode_stiffness(const Scene& scene, const SimState& s, const std::vector<Vec3>& targets,
                    ModeStiffness& out) {
  out.points.clear();
  out.couples.clear();
  out.blocks.clear();
  for (const ForceElement& e : force_elements()) {
    if (e.mode_stiffness) e.mode_stiffness(scene, s, targets, out);
  }
}

}  // namespace physik
