// Contacts (physik/engine/contacts.h): a floor and self-collision on the paper's rig, against
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
//   coil  a 1,000-bone chain (experiments/coil.h) with self-collision on, two ways: dropped in a
//         helix of 10 turns just above the floor (the turns fall onto one another and pile), and
//         laid in a flat spiral whose turns touch. The implicit scheme, run until at rest (or
//         30 s): does each come to rest without diverging, and the deepest penetration at rest,
//         into the floor and between bones, against 5% of the radius; and the dropped one
//         again with static friction against the floor (friction_stiffness = contact_k).
//         PhysIK only (MuJoCo's step grows ~N^2.7 on chains, experiment `scaling`). The quick
//         mode runs 100 bones (2 turns) for 1 s.
//   sit   Fig 11's sitting pose (the paper's scene run as shipped, no gravity) with a seat (a box
//         whose top is at the bottom of the thighs' capsules there, from behind the pelvis to
//         short of the knees) and a floor (at the feet's lowest point), gravity switched on, the
//         targets at their last values: do the pelvis, hips or thighs rest on the seat and the
//         feet on the floor, the deepest penetration at rest (the target: 5% of the radius),
//         and the gap to MuJoCo's resting pose over the rig's height. The implicit scheme at dt
//         0.01 (MuJoCo's Euler needs dt well under its solref of 0.02 s), run 30 s as the
//         drops (at 10 s the arms were still moving onto the floor). Starting from the
//         standing pose instead, the pelvis spring (k = 30) could not hold the rig's weight on
//         the way down: this asks only whether the rig stays seated.
//   cannon Fig 7's linear cannon (the torso's centre pulled 12 units away, linear spring):
//         the deepest bone-bone overlap over the run over the thinner radius (as the hand's),
//         in the paper's scheme as shipped (no contacts) and, with and without self-collision,
//         in the implicit scheme at the paper's dt 0.05 (the paper's explicit scheme at dt
//         0.05 is unstable at any contact stiffness that stops a bone)
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "experiments/coil.h"
#include "experiments/common.h"
#include "experiments/contacts_scenes.h"
#include "experiments/report.h"
#include "physik/engine/collision.h"
#include "physik/engine/contacts.h"
#include "physik/engine/engine.h"
#include "physik/engine/start_contacts.h"
#include "physik/io/recorder.h"
#include "physik/io/scene_io.h"
#include "reference/compare.h"

namespace physik::experiments {

namespace {

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

// the hand scene (contacts_scenes.h), 300 steps (60 quick)
Scene hand_scene(const Context& ctx, bool self_collision) {
  return contacts_hand_scene(ctx.models_dir, self_collision, ctx.quick ? 60 : 300);
}

// the deepest overlap of a pose, as a fraction of the thinner touching capsule's radius
double penetration_fraction(const Scene& scene, const BoneFrames& frames) {
  return penetration(scene, frames).max_depth_fraction;
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
  report.claim(
      "Each engine's resting pose after a drop is reproducible within 2% of the rig height when "
      "it halves its time step",
      "final pose at dt against at dt / 2, over the height: PhysIK lying flat " +
          num(flat.physik_self_gap) + ", turned " + num(tilted.physik_self_gap) +
          "; MuJoCo lying flat " + num(flat.mujoco_self_gap) + ", turned " +
          num(tilted.mujoco_self_gap),
      flat.diverged || tilted.diverged ? "no (a run diverged)"
      : std::max({flat.physik_self_gap, tilted.physik_self_gap, flat.mujoco_self_gap,
                  tilted.mujoco_self_gap}) <= 0.02
          ? "yes"
          : "no: a resting pose that moves by more than 2% when its engine halves the step is "
            "picked by the path, and there a 2% agreement between engines is not what the scene "
            "fixes");
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

// the coil's run and its resting pose (the section's header comment)
struct CoilMeasured {
  int nbone = 0;
  RunSummary run;
  Penetration ground, bones;     // at the final pose: into the floor, between bones
  double speed_tol = 0.0;        // rig units/s, the run's rest speed
  double final_rms_speed = 0.0;  // rig units/s, sqrt(2 KE / M) at the end
};

// one coil run into the run folder `name`, measured at its last pose
CoilMeasured coil(const Context& ctx, const std::string& name, Scene scene) {
  CoilMeasured m;
  m.nbone = scene.rig.nbone;
  scene.convergence.stop_when_converged = true;
  m.speed_tol = scene.speed_tol();
  m.run = write_run_folder(ctx, name, scene);
  m.final_rms_speed = std::sqrt(2.0 * m.run.final_kinetic_energy / scene.rig.total_mass());
  CollisionWorld world;
  std::vector<Contact> contacts, ground, bones;
  world.detect(scene, m.run.final_frames, contacts);
  for (const Contact& c : contacts) (c.other_bone < 0 ? ground : bones).push_back(c);
  m.ground = penetration(scene, ground);
  m.bones = penetration(scene, bones);
  if (ctx.log) {
    *ctx.log << "  " << name << " " << m.nbone << ": " << m.run.steps_run << " steps, "
             << (m.run.diverged    ? "diverged"
                 : m.run.converged ? "at rest"
                                   : "not at rest")
             << ", KE " << num(m.run.final_kinetic_energy) << " J, " << contacts.size()
             << " contacts, " << num(m.run.wall_time_s) << " s\n";
  }
  return m;
}

nlohmann::json to_json(const CoilMeasured& m) {
  return {{"nbone", m.nbone},
          {"steps_run", m.run.steps_run},
          {"converged", m.run.converged},
          {"steps_to_converge", m.run.steps_to_converge},
          {"diverged", m.run.diverged},
          {"final_kinetic_energy", m.run.final_kinetic_energy},
          {"peak_kinetic_energy", m.run.peak_kinetic_energy},
          {"speed_tol", m.speed_tol},
          {"final_rms_speed", m.final_rms_speed},
          {"ground_contacts", m.ground.contacts},
          {"bone_contacts", m.bones.contacts},
          {"ground_penetration_over_radius", m.ground.max_depth_fraction},
          {"bone_penetration_over_radius", m.bones.max_depth_fraction},
          {"implicit_split_steps", m.run.implicit_split_steps},
          {"wall_time_s", m.run.wall_time_s}};
}

// "at rest after ..." or "not at rest after ...", with what the run ended on
std::string coil_outcome(const CoilMeasured& m, double dt) {
  if (m.run.diverged) return "diverged (" + m.run.divergence_reason + ")";
  const std::string contacts = std::to_string(m.ground.contacts + m.bones.contacts) +
                               " contacts (" + std::to_string(m.bones.contacts) + " between bones)";
  if (!m.run.converged) {
    return "not at rest after " + num(m.run.steps_run * dt) + " s: rms speed " +
           num(m.final_rms_speed) + " rig units/s (at rest below " + num(m.speed_tol) +
           "), kinetic energy " + num(m.run.final_kinetic_energy) + " J, " + contacts;
  }
  return "at rest after " + num(m.run.steps_to_converge * dt) + " s (rms speed below " +
         num(m.speed_tol) + " rig units/s), " + contacts;
}

std::string rest_verdict(const CoilMeasured& m) {
  return m.run.diverged    ? "no (diverged)"
         : m.run.converged ? "yes"
                           : "partly (finite, still moving at the end)";
}

// the deepest penetration of a coil at its last pose, over the radius; "" when it diverged
std::string coil_depths(const std::string& label, const CoilMeasured& m) {
  return label + ": into the floor " + num(m.ground.max_depth_fraction) + ", between bones " +
         num(m.bones.max_depth_fraction) +
         (m.run.diverged    ? " (diverged)"
          : m.run.converged ? ""
                            : " (not at rest)");
}

void add_coil_claims(Report& report, const CoilMeasured& dropped, const CoilMeasured& laid,
                     const CoilMeasured& anchored, double dt) {
  const std::string bones = std::to_string(dropped.nbone) + "-bone chain";
  report.claim("A " + bones + " dropped in a coil onto the floor comes to rest without diverging",
               coil_outcome(dropped, dt), rest_verdict(dropped));
  report.named("coil-rests");
  report.claim(
      "With static friction against the floor (friction_stiffness = contact_k), the "
      "dropped coil comes to rest",
      coil_outcome(anchored, dt), rest_verdict(anchored));
  report.named("coil-rests-static-friction");
  report.claim("A " + bones + " laid in a flat coil on the floor comes to rest",
               coil_outcome(laid, dt), rest_verdict(laid));
  report.named("coil-laid-rests");
  // only a run at rest is judged
  double deepest = 0.0;
  bool any_at_rest = false;
  for (const CoilMeasured* m : {&dropped, &laid, &anchored}) {
    if (!m->run.converged) continue;
    any_at_rest = true;
    deepest = std::max({deepest, m->ground.max_depth_fraction, m->bones.max_depth_fraction});
  }
  report.claim("The coils at rest: no penetration deeper than 5% of a bone's radius",
               "deepest, over the radius, " + coil_depths("dropped", dropped) + "; " +
                   coil_depths("laid", laid) + "; " +
                   coil_depths("dropped with static friction", anchored),
               !any_at_rest     ? "n/a (no coil at rest)"
               : deepest > 0.05 ? "no"
               : dropped.run.converged && laid.run.converged && anchored.run.converged
                   ? "yes"
                   : "partly (only the coil at rest is judged)");
  report.named("coil-penetration");
}

// --- sit: Fig 11 with a seat and a floor ----------------------------------------------------

// the paper's Fig 11 run as shipped (no gravity, no contacts): its last pose, local rotations
Pose paper_sitting_pose(const Scene& paper) {
  SimState st;
  init_state(paper, st);
  for (int k = 0; k < paper.steps; ++k) step(paper, st);
  return st.pose;
}

// the seat under the sitting pose: its top at the lowest point of the thighs' capsules, from
// 0.5 behind the pelvis (+y is behind: the paper's pelvis moves to +y) to a thigh radius short
// of the knees (so the shins hang in front of it), 0.3 wider than the hips on each side, 0.4
// thick; the floor at the lowest point of the feet's capsules
void add_seat_and_floor(Scene& s, const BoneFrames& f) {
  const Rig& rig = s.rig;
  const int pelvis = rig.find_bone("torso"), thigh_l = rig.find_bone("thigh.L"),
            thigh_r = rig.find_bone("thigh.R");
  const double top = std::min(capsule_bottom(s.rig, f, thigh_l), capsule_bottom(s.rig, f, thigh_r));
  const double back = f.tail_world[pelvis].y() + 0.5;
  const double front = std::max(f.tail_world[thigh_l].y(), f.tail_world[thigh_r].y()) +
                       2.0 * rig.bone_collision_radius[thigh_l];
  const double half_x =
      std::max(std::abs(f.head_world[thigh_l].x()), std::abs(f.head_world[thigh_r].x())) + 0.3;
  BoxObstacle seat;
  seat.name = "seat";
  seat.half_extents = Vec3(half_x, 0.5 * (back - front), 0.2);
  seat.center_world = Vec3(0.0, 0.5 * (back + front), top - 0.2);
  s.collision.obstacles = {seat};
  const double floor = std::min(capsule_bottom(s.rig, f, rig.find_bone("foot.L")),
                                capsule_bottom(s.rig, f, rig.find_bone("foot.R")));
  s.collision.ground = GroundPlane{Vec3::UnitZ(), floor};
}

// Fig 11's scene from its sitting pose, targets at their last values, gravity on, with a seat
// and a floor; the implicit scheme at dt 0.01 with the original's damping (3 N s/m)
Scene sit_scene(const Context& ctx) {
  Scene s = scene_named(ctx, "fig11_sit");
  s.initial_pose = paper_sitting_pose(s);
  for (const TargetChange& t : s.schedule)
    s.control_points[t.control_point].target_world = t.target_world;
  s.schedule.clear();
  s.params.scheme = Scheme::kImplicit;
  s.params.dt = 0.01;
  s.params.damping_auto = false;
  s.params.damping = 3.0;
  s.params.interpolation = Interpolation::kNone;
  s.steps = ctx.quick ? 100 : 3000;  // 30 s, as the drops: at 10 s the arms still moved
  s.gravity_world = Vec3(0, 0, -9.81);
  add_seat_and_floor(s, forward_kinematics(s.rig, s.initial_pose));
  s.file = "contacts_sit";
  return s;
}

struct Seated {
  std::vector<std::string> on_seat, on_floor;  // the bones touching the seat, the floor
  bool feet_on_floor = false;                  // both feet's bones touch the floor
  bool hips_on_seat = false;                   // the pelvis, a hip or a thigh on the seat
  double penetration = 0.0;                    // 1, of the radius, the deepest contact
};

// which bones touch what at a pose (PhysIK's detection), and how deep
Seated seated(const Scene& s, const BoneFrames& f) {
  std::vector<Contact> contacts;
  CollisionWorld world;
  world.detect(s, f, contacts);
  Seated out;
  for (const Contact& c : contacts) {
    auto& list = c.obstacle >= 0 ? out.on_seat : out.on_floor;
    const std::string& name = s.rig.bone_name[c.bone];
    if (std::find(list.begin(), list.end(), name) == list.end()) list.push_back(name);
  }
  const auto has = [](const std::vector<std::string>& l, const char* n) {
    return std::find(l.begin(), l.end(), n) != l.end();
  };
  out.feet_on_floor = has(out.on_floor, "foot.L") && has(out.on_floor, "foot.R");
  for (const char* b : {"torso", "hip.L", "hip.R", "thigh.L", "thigh.R"}) {
    out.hips_on_seat = out.hips_on_seat || has(out.on_seat, b);
  }
  out.penetration = penetration(s, contacts).max_depth_fraction;
  return out;
}

nlohmann::json to_json(const Seated& m) {
  return {{"bones_on_seat", m.on_seat},
          {"bones_on_floor", m.on_floor},
          {"feet_on_floor", m.feet_on_floor},
          {"pelvis_or_thighs_on_seat", m.hips_on_seat},
          {"penetration_over_radius", m.penetration}};
}

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out.empty() ? "none" : out;
}

// the feet that do not touch the floor, named: "foot.L", "foot.L and foot.R" (or "none")
std::string feet_off_floor(const Seated& m) {
  std::vector<std::string> off;
  for (const char* foot : {"foot.L", "foot.R"}) {
    if (std::find(m.on_floor.begin(), m.on_floor.end(), foot) == m.on_floor.end()) {
      off.emplace_back(foot);
    }
  }
  return off.size() == 2 ? off[0] + " and " + off[1] : joined(off);
}

// the largest endpoint distance between two poses (reference/compare.h pose_gap) over the bones
// that are not an arm's (collar, upper_arm, forearm, hand), rig units
double gap_without_arms(const Rig& rig, const BoneFrames& a, const BoneFrames& b) {
  double g = 0.0;
  for (int i = 0; i < rig.nbone; ++i) {
    const std::string& name = rig.bone_name[i];
    bool arm = false;
    for (const char* prefix : {"collar", "upper_arm", "forearm", "hand"}) {
      arm = arm || name.rfind(prefix, 0) == 0;
    }
    if (arm) continue;
    g = std::max({g, (a.head_world[i] - b.head_world[i]).norm(),
                  (a.tail_world[i] - b.tail_world[i]).norm()});
  }
  return g;
}

// the report's note on the sit's floor: at the lower foot, the other foot above it
void sit_foot_note(const Scene& scene, Report& report) {
  const BoneFrames f0 = forward_kinematics(scene.rig, scene.initial_pose);
  const double foot_gap = std::abs(capsule_bottom(scene.rig, f0, scene.rig.find_bone("foot.L")) -
                                   capsule_bottom(scene.rig, f0, scene.rig.find_bone("foot.R")));
  report.note(
      "Sit: the floor is at the lower foot's lowest point in the paper's sitting pose; the "
      "other foot stands " +
      num(foot_gap) +
      " rig units higher there (the paper's heel and toe targets of the two feet differ), "
      "held by its springs.");
}

nlohmann::json sit_section(const Context& ctx, Report& report) {
  const Scene scene = checked_start(sit_scene(ctx));
  const Comparison c = compare_with_mujoco(scene, ReferenceMode::kSameForces);
  write_run_folder(ctx, "sit", scene);
  const bool physik_diverged = c.physik.summary.diverged, mujoco_ran = !c.mujoco.summary.diverged;
  const Seated p = seated(scene, c.physik.summary.final_frames);
  const Seated m = seated(scene, c.mujoco.summary.final_frames);
  const double ke = c.physik.summary.final_kinetic_energy;
  const double gap = c.gap.final_pose_gap / scene.rig.height();
  report.claim(
      "Fig 11 with a seat and a floor: the rig sits on the seat, with its feet on the floor",
      "after " + num(scene.steps * scene.params.dt) + " s under gravity: on the seat " +
          joined(p.on_seat) + "; on the floor " + joined(p.on_floor) + "; KE " + num(ke) +
          " J (MuJoCo: seat " + joined(m.on_seat) + "; floor " + joined(m.on_floor) + ")",
      physik_diverged                     ? "no (the run diverged)"
      : p.hips_on_seat && p.feet_on_floor ? "yes"
      : p.hips_on_seat ? "partly (on the seat; " + feet_off_floor(p) + " off the floor)"
                       : "no");
  report.named("sit-on-seat");
  report.claim("Seated, no penetration deeper than 5% of a bone's radius",
               "deepest at the end: " + num(p.penetration) +
                   " of the radius (MuJoCo's pose: " + num(m.penetration) + ")",
               p.penetration <= 0.05 ? "yes" : "no");
  const double body_gap =
      gap_without_arms(scene.rig, c.physik.summary.final_frames, c.mujoco.summary.final_frames) /
      scene.rig.height();
  report.claim("The seated pose is MuJoCo's within 2% of the rig height",
               "final pose gap over the rig's height: " + num(gap) +
                   "; without the arms (collars to hands: no control point holds them, and gravity "
                   "lays them on the floor or the seat): " +
                   num(body_gap),
               !mujoco_ran || physik_diverged ? "n/a (a run diverged)"
               : gap <= 0.02                  ? "yes"
                                              : "no");
  sit_foot_note(scene, report);
  const BoxObstacle& seat = scene.collision.obstacles[0];
  nlohmann::json out = {
      {"physik", to_json(p)},
      {"mujoco", to_json(m)},
      {"physik_kinetic_energy", ke},
      {"final_pose_gap_over_height", gap},
      {"final_pose_gap_without_arms_over_height", body_gap},
      {"diverged", physik_diverged},
      {"seat_center", {seat.center_world.x(), seat.center_world.y(), seat.center_world.z()}},
      {"seat_half_extents", {seat.half_extents.x(), seat.half_extents.y(), seat.half_extents.z()}},
      {"floor_height", scene.collision.ground->height}};
  if (ctx.log)
    *ctx.log << "  sit: seat " << joined(p.on_seat) << ", floor " << joined(p.on_floor) << ", gap "
             << num(gap) << "\n";
  return out;
}

// --- cannon: Fig 7's linear cannon with self-collision ----------------------------------------

struct CannonRun {
  double deepest = 0.0;  // 1, the deepest bone-bone overlap over the run over the thinner radius
  bool diverged = false;
};

// the scene run with its every step's deepest bone-bone overlap measured (self-collision on for
// the measure whatever the run has)
CannonRun cannon_run(const Context& ctx, const std::string& name, const Scene& scene) {
  Scene measure = scene;
  measure.collision.self_collision = true;
  CollisionWorld world;
  std::vector<Contact> contacts;
  contacts.reserve(8 * static_cast<std::size_t>(scene.rig.nbone));
  CannonRun out;
  const RecordedRun run =
      record_run(scene, RecordOptions{}, [&](const SimState& s, const StepStats&) {
        world.detect(measure, s.frames, contacts);
        out.deepest = std::max(out.deepest, penetration(measure, contacts).max_depth_fraction);
      });
  out.diverged = run.summary.diverged;
  write_run_folder(ctx, name, scene);
  if (ctx.log) *ctx.log << "  " << name << ": deepest overlap " << num(out.deepest) << "\n";
  return out;
}

nlohmann::json to_json(const CannonRun& r) {
  return {{"deepest_bone_overlap_over_radius", r.deepest}, {"diverged", r.diverged}};
}

nlohmann::json cannon_section(const Context& ctx, Report& report) {
  Scene paper = scene_named(ctx, "fig7_cannon_linear");
  if (ctx.quick) paper.steps = 100;
  const CannonRun as_shipped = cannon_run(ctx, "cannon_paper", paper);
  Scene implicit = paper;
  implicit.params.scheme = Scheme::kImplicit;
  const CannonRun off = cannon_run(ctx, "cannon_implicit_no_self_collision", implicit);
  implicit.collision.self_collision = true;
  const CannonRun on = cannon_run(ctx, "cannon_implicit_self_collision", implicit);
  // more than one radius of the thinner bone: a centre line inside another capsule, the rig
  // folded through itself
  const auto through = [](const CannonRun& r) { return r.diverged || r.deepest > 1.0; };
  report.claim(
      "Fig 7's linear cannon folds the rig through itself without self-collision and not with it",
      "deepest bone-bone overlap over the run, over the thinner bone's radius: paper's scheme " +
          num(as_shipped.deepest) + (as_shipped.diverged ? " (diverged)" : "") +
          "; implicit scheme " + num(off.deepest) + " without self-collision, " + num(on.deepest) +
          " with" + (on.diverged || off.diverged ? " (a run diverged)" : ""),
      on.diverged || off.diverged             ? "no (a run diverged)"
      : through(off) && !through(on)          ? "yes"
      : !through(off) && !through(as_shipped) ? "n/a (no fold through itself without it either)"
      : !through(off) ? "partly (the paper's scheme folds through itself; the implicit one does "
                        "not, with or without)"
                      : "no");
  report.named("cannon-self-collision");
  return {{"paper_scheme", to_json(as_shipped)},
          {"implicit_no_self_collision", to_json(off)},
          {"implicit_self_collision", to_json(on)}};
}

void run(const Context& ctx) {
  const Measured flat =
      against_mujoco(ctx, "drop_flat", checked_start(drop_scene(ctx, 90.0)), true);
  const Measured tilted =
      against_mujoco(ctx, "drop_tilted", checked_start(drop_scene(ctx, 60.0)), true);
  const Measured on = against_mujoco(ctx, "hand_self_collision", hand_scene(ctx, true));
  const Measured off = against_mujoco(ctx, "hand_no_self_collision", hand_scene(ctx, false));
  const int coil_bones = ctx.quick ? 100 : 1000, coil_steps = ctx.quick ? 100 : 3000;
  const CoilMeasured dropped =
      coil(ctx, "coil", coil_helix_scene(coil_bones, ctx.quick ? 2 : 10, coil_steps));
  const CoilMeasured laid =
      coil(ctx, "coil_laid", coil_flat_spiral_scene(coil_bones, true, coil_steps));
  Scene anchored_scene = coil_helix_scene(coil_bones, ctx.quick ? 2 : 10, coil_steps);
  anchored_scene.params.friction_stiffness = anchored_scene.params.contact_k;
  const CoilMeasured anchored = coil(ctx, "coil_static_friction", anchored_scene);
  Report report("Contacts: a floor and self-collision against MuJoCo's contacts");
  add_drop_claims(report, flat, tilted);
  add_hand_claims(report, on, off);
  add_coil_claims(report, dropped, laid, anchored, coil_helix_scene(coil_bones, 1, 1).params.dt);
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
  write_summary(ctx,
                {{"experiment", "contacts"},
                 {"drop_flat", to_json(flat)},
                 {"drop_tilted", to_json(tilted)},
                 {"hand_self_collision", to_json(on)},
                 {"hand_no_self_collision", to_json(off)},
                 {"coil", to_json(dropped)},
                 {"coil_laid", to_json(laid)},
                 {"coil_static_friction", to_json(anchored)},
                 {"sit", sit},
                 {"cannon", cannon}},
                report);
}

const Registration registered{
    290, {"contacts", "Contacts", "a floor and self-collision against MuJoCo's contacts", run}};

}  // namespace

}  // namespace physik::experiments
