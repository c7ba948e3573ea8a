// Contacts (physik/engine/ground_contacts.h, self_contacts.h): a floor and self-collision on the
// paper's rig, against
// MuJoCo's own contacts on the same capsules (reference/compare.h, same-forces mode: MuJoCo
// resolves gravity and the contacts itself, the engine's damping is given to both).
//   drop  pinhead dropped on a floor under gravity, lying flat and turned 60 degrees from
//         standing, its lowest capsule 0.1 rig units above the floor (a bone started through
//         the floor is thrown out by the contact spring: start_contacts.h), run 30 s (both engines
//         at rest, KE about 5e-5 J; at 6 s the limbs still sag): the gap between PhysIK's resting
//         pose and MuJoCo's over the rig's height (the target: within 2%), and the deepest
//         penetration at rest (the target: 5% of the thinner touching capsule's radius); and each
//         engine against itself at dt / 2: a rig lying on a floor with friction rests in a family
//         of poses, and which one the path picks, so the gap to MuJoCo is read against that
//   hand  pinhead's left hand pulled through its torso to the far side, the torso held, with and
//         without self-collision: the deepest bone-bone overlap over the run (does the arm go
//         through the torso or round it), against MuJoCo's (its solref's penetration)
// The experiment's studies, one file each: drop and hand here, coil (contacts_coil.cpp), sit
// (contacts_sit.cpp) and cannon (contacts_cannon.cpp); contacts.h shares what they use.
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "experiments/coil.h"
#include "experiments/common.h"
#include "experiments/contacts.h"
#include "experiments/contacts_scenes.h"
#include "experiments/report.h"
#include "physik/engine/contact_data.h"
#include "physik/engine/engine.h"
#include "physik/engine/start_contacts.h"
#include "physik/io/recorder.h"
#include "physik/io/scene_io.h"
#include "reference/compare.h"

namespace physik::experiments {

namespace contacts_study {

// an experiment scene must start at rest against its ground and obstacles (start_contacts.h: a
// bone started into the floor is thrown out of it, and the run measures that instead)
const Scene& checked_start(const Scene& scene) {
  const std::string warning = check_start_contacts(scene);
  if (!warning.empty()) {
    throw std::runtime_error("contacts experiment: scene " + scene.file +
                             " starts in contact: " + warning);
  }
  return scene;
}

// the deepest overlap of a pose, as a fraction of the thinner touching capsule's radius
double penetration_fraction(const Scene& scene, const BoneFrames& frames) {
  return penetration(scene, contacts_at_pose(scene, frames)).max_depth_fraction;
}

}  // namespace contacts_study

namespace {

using namespace contacts_study;

// the drops' start: the lowest capsule this far above the floor, rig units
constexpr double kDropClearance = 0.1;

// pinhead turned `tilt_deg` about x at its root's head, raised so that its lowest capsule starts
// kDropClearance above the floor (start_contacts.h finds nothing to push out)
Scene drop_scene(const Context& ctx, double tilt_deg) {
  const auto at_height = [&](double height) {
    const nlohmann::json doc = {
        {"rig", ctx.models_dir + "/rigs/pinhead.json"},
        {"params", {{"preset", "robust"}, {"dt", 0.01}, {"damping", 1.0}}},
        {"steps", ctx.quick ? 100 : 3000},
        {"gravity", {0, 0, -9.81}},
        {"ground", {{"height", 0.0}, {"normal", {0, 0, 1}}}},
        {"initial_pose",
         {{"root_head", {0, 0, height}}, {"rotation_deg", {{"head", {tilt_deg, 0, 0}}}}}}};
    return scene_from_json(doc, "contacts_drop_" + std::to_string(static_cast<int>(tilt_deg)), ".");
  };
  const Scene level = at_height(0.0);
  const double lowest =
      lowest_capsule_point(level.rig, forward_kinematics(level.rig, level.initial_pose));
  return at_height(kDropClearance - lowest);
}

// the hand scene (contacts_scenes.h), 300 steps (60 quick)
Scene hand_scene(const Context& ctx, bool self_collision) {
  return contacts_hand_scene(ctx.models_dir, self_collision, ctx.quick ? 60 : 300);
}

struct Measured {
  double gap_fraction = 0.0;        // 1, final pose gap to MuJoCo over the rig's height
  double physik_penetration = 0.0;  // 1, of the radius, at PhysIK's final pose
  double mujoco_penetration = 0.0;  // 1, at MuJoCo's
  bool diverged = false;
  double hand_x = 0.0;  // rig units, the left hand's tip at PhysIK's final pose
  // 1, the deepest overlap of two bones over the whole run (self-collision measured even where
  // the run had it off), PhysIK's and MuJoCo's
  double physik_run_overlap = 0.0, mujoco_run_overlap = 0.0;
  // 1, each engine's final pose at dt against its own at dt / 2 (twice the steps), over the rig's
  // height: how far the resting pose depends on the path (drops only; -1: not measured)
  double physik_self_gap = -1.0, mujoco_self_gap = -1.0;
};

// the deepest bone-bone overlap over a run's frames, self-collision measured on
double deepest_over_run(Scene scene, const std::vector<BoneFrames>& frames) {
  scene.collision.self_collision = true;
  scene.collision.ground.reset();
  double deepest = 0.0;
  for (const BoneFrames& f : frames) deepest = std::max(deepest, penetration_fraction(scene, f));
  return deepest;
}

// the drop again at dt / 2: each engine against itself (Measured::physik_self_gap)
void measure_reproducibility(const Scene& scene, const Comparison& at_dt, Measured& m) {
  Scene half = scene;
  half.params.dt = 0.5 * scene.params.dt;
  half.steps = 2 * scene.steps;
  const Comparison c = compare_with_mujoco(half, ReferenceMode::kSameForces);
  if (!diverged_runs(c).empty()) {
    m.diverged = true;
    return;
  }
  const double height = scene.rig.height();
  m.physik_self_gap =
      pose_gap(at_dt.physik.summary.final_frames, c.physik.summary.final_frames) / height;
  m.mujoco_self_gap =
      pose_gap(at_dt.mujoco.summary.final_frames, c.mujoco.summary.final_frames) / height;
}

Measured against_mujoco(const Context& ctx, const std::string& name, const Scene& scene,
                        bool reproducibility = false) {
  const Comparison c = compare_with_mujoco(scene, ReferenceMode::kSameForces);
  write_run_folder(ctx, name, scene);  // for the viewer
  Measured m;
  m.diverged = !diverged_runs(c).empty();
  m.gap_fraction = c.gap.final_pose_gap / scene.rig.height();
  m.physik_penetration = penetration_fraction(scene, c.physik.summary.final_frames);
  m.mujoco_penetration = penetration_fraction(scene, c.mujoco.summary.final_frames);
  m.hand_x = c.physik.summary.final_frames.tail_world[scene.rig.find_bone("hand.L")].x();
  m.physik_run_overlap = deepest_over_run(scene, c.physik.frames);
  m.mujoco_run_overlap = deepest_over_run(scene, c.mujoco.frames);
  if (reproducibility) measure_reproducibility(scene, c, m);
  if (ctx.log) {
    *ctx.log << "  " << name << ": gap " << num(m.gap_fraction) << " of the height, penetration "
             << num(m.physik_penetration) << " (MuJoCo " << num(m.mujoco_penetration) << ")\n";
  }
  return m;
}

nlohmann::json to_json(const Measured& m) {
  return {{"final_pose_gap_over_height", m.gap_fraction},
          {"physik_penetration_over_radius", m.physik_penetration},
          {"mujoco_penetration_over_radius", m.mujoco_penetration},
          {"hand_tip_x", m.hand_x},
          {"physik_deepest_bone_overlap_over_radius", m.physik_run_overlap},
          {"mujoco_deepest_bone_overlap_over_radius", m.mujoco_run_overlap},
          {"physik_self_gap_half_dt_over_height", m.physik_self_gap},
          {"mujoco_self_gap_half_dt_over_height", m.mujoco_self_gap},
          {"diverged", m.diverged}};
}

void add_drop_claims(Report& report, const Measured& flat, const Measured& tilted) {
  const double worst = std::max(flat.gap_fraction, tilted.gap_fraction);
  report.claim(
      "A rig dropped on the floor comes to rest within 2% of the rig height of MuJoCo's "
      "resting pose",
      "final pose gap over the rig's height: lying flat " + num(flat.gap_fraction) +
          ", turned 60 deg " + num(tilted.gap_fraction),
      flat.diverged || tilted.diverged ? "no (a run diverged)"
      : worst <= 0.02                  ? "yes"
      : flat.gap_fraction <= 0.02      ? "partly (lying flat only)"
      : tilted.gap_fraction <= 0.02    ? "partly (turned 60 deg only)"
                                       : "no");
  report.named("drop-agrees");
  // A gap to MuJoCo can only be read against each engine's own: where the resting pose moves
  // by more than the target when an engine halves its step, the drop's path picks the pose
  const bool reproducible = std::max({flat.physik_self_gap, tilted.physik_self_gap,
                                      flat.mujoco_self_gap, tilted.mujoco_self_gap}) <= 0.02;
  report.claim(
      "Each engine's resting pose after a drop is reproducible within 2% of the rig height when "
      "it halves its time step",
      "final pose at dt against at dt / 2, over the height: PhysIK lying flat " +
          num(flat.physik_self_gap) + ", turned " + num(tilted.physik_self_gap) +
          "; MuJoCo lying flat " + num(flat.mujoco_self_gap) + ", turned " +
          num(tilted.mujoco_self_gap) +
          (reproducible ? ""
                        : ": a resting pose that moves by more than 2% when its engine halves "
                          "the step is picked by the path, and there a 2% agreement between "
                          "engines is not what the scene fixes"),
      flat.diverged || tilted.diverged ? "no (a run diverged)"
      : reproducible                   ? "yes"
                                       : "no");
  const double pen = std::max(flat.physik_penetration, tilted.physik_penetration);
  report.claim("At rest on the floor, no penetration deeper than 5% of a bone's radius",
               "deepest at rest: " + num(pen) + " of the radius (MuJoCo's poses: " +
                   num(std::max(flat.mujoco_penetration, tilted.mujoco_penetration)) + ")",
               pen <= 0.05 ? "yes" : "no");
}

void add_hand_claims(Report& report, const Measured& on, const Measured& off) {
  // an overlap of more than one radius of the thinner bone puts that bone's centre line inside
  // the other capsule: the arm went into the torso rather than against it
  report.claim(
      "A hand pulled through the torso passes through it without self-collision and "
      "not with it",
      "deepest bone-bone overlap over the run, over the thinner bone's radius: " +
          num(off.physik_run_overlap) + " without, " + num(on.physik_run_overlap) +
          " with (the hand's tip ends at x = " + num(off.hand_x) + " and " + num(on.hand_x) +
          ": with self-collision the arm reaches round the torso)",
      off.physik_run_overlap > 1.0 && on.physik_run_overlap < 1.0 ? "yes" : "no");
  report.claim(
      "The hand's penetration into the torso is of the order of MuJoCo's for its solref",
      "deepest overlap over the run with self-collision: PhysIK " + num(on.physik_run_overlap) +
          ", MuJoCo " + num(on.mujoco_run_overlap) + " of the thinner bone's radius",
      on.mujoco_run_overlap > 0.0 && on.physik_run_overlap < 10.0 * on.mujoco_run_overlap &&
              on.mujoco_run_overlap < 10.0 * on.physik_run_overlap
          ? "yes"
          : "no");
}

void run(const Context& ctx) {
  const Measured flat =
      against_mujoco(ctx, "drop_flat", checked_start(drop_scene(ctx, 90.0)), true);
  const Measured tilted =
      against_mujoco(ctx, "drop_tilted", checked_start(drop_scene(ctx, 60.0)), true);
  const Measured on = against_mujoco(ctx, "hand_self_collision", hand_scene(ctx, true));
  const Measured off = against_mujoco(ctx, "hand_no_self_collision", hand_scene(ctx, false));
  Report report("Contacts: a floor and self-collision against MuJoCo's contacts");
  add_drop_claims(report, flat, tilted);
  add_hand_claims(report, on, off);
  const nlohmann::json coils = coil_section(ctx, report);
  const nlohmann::json sit = sit_section(ctx, report);
  const nlohmann::json cannon = cannon_section(ctx, report);
  const EngineParams cp = drop_scene(ctx, 90.0).params;
  report.note("PhysIK's contacts are penalty springs (contact_k " + num(cp.contact_k) +
              " N/m, contact_damping " + num(cp.contact_damping) + " N s/m, friction " +
              num(cp.friction) + ", regularised below friction_speed " + num(cp.friction_speed) +
              " rig units/s, friction_stiffness " + num(cp.friction_stiffness) +
              " N/m: no static part, as MuJoCo's soft friction creeps too); MuJoCo's are its own "
              "soft contacts at its default solref (0.02 s, 1) on the "
              "same capsules (0.06 x each bone's length) and plane, with the same friction. "
              "Penetration is measured by PhysIK's detection on each engine's final pose.");
  report.note(
      "The coil: a chain of bones 0.1 rig units long and 0.025 in radius (experiments/coil.h), "
      "the implicit scheme at dt 0.01 s with damping " +
      num(kCoilDamping) +
      " N s/m at each bone end and the same contact law; PhysIK only (MuJoCo's step on a chain "
      "this long is the scaling experiment's). The step's cost beside the same scene without "
      "contacts is the experiment contacts_cost's.");
  report.figures({"contacts_poses.png", "contacts_coil.png"});
  nlohmann::json summary = {{"experiment", "contacts"},
                            {"drop_flat", to_json(flat)},
                            {"drop_tilted", to_json(tilted)},
                            {"hand_self_collision", to_json(on)},
                            {"hand_no_self_collision", to_json(off)},
                            {"sit", sit},
                            {"cannon", cannon}};
  summary.update(coils);  // coil, coil_laid, coil_static_friction
  write_summary(ctx, summary, report);
}

const Registration registered{
    290, {"contacts", "Contacts", "a floor and self-collision against MuJoCo's contacts", run}};

}  // namespace

}  // namespace physik::experiments
