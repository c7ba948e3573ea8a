// The contacts experiment's coil study (experiments/contacts.cpp):
//   coil  a 1,000-bone chain (experiments/coil.h) with self-collision on, two ways: dropped in a
//         helix of 10 turns just above the floor (the turns fall onto one another and pile), and
//         laid in a flat spiral whose turns touch. The implicit scheme, run until at rest (or
//         30 s): does each come to rest without diverging, and the deepest penetration at rest,
//         into the floor and between bones, against 5% of the radius; and the dropped one
//         again with static friction against the floor (friction_stiffness = contact_k).
//         PhysIK only (MuJoCo's step grows ~N^2.7 on chains, experiment `scaling`). The quick
//         mode runs 100 bones (2 turns) for 1 s.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "experiments/coil.h"
#include "experiments/common.h"
#include "experiments/contacts.h"
#include "experiments/report.h"
#include "physik/engine/contact_data.h"
#include "physik/engine/engine.h"

namespace physik::experiments::contacts_study {

namespace {

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
  const std::vector<Contact> contacts = contacts_at_pose(scene, m.run.final_frames);
  std::vector<Contact> ground, bones;
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

}  // namespace

nlohmann::json coil_section(const Context& ctx, Report& report) {
  const int coil_bones = ctx.quick ? 100 : 1000, coil_steps = ctx.quick ? 100 : 3000;
  const CoilMeasured dropped =
      coil(ctx, "coil", coil_helix_scene(coil_bones, ctx.quick ? 2 : 10, coil_steps));
  const CoilMeasured laid =
      coil(ctx, "coil_laid", coil_flat_spiral_scene(coil_bones, true, coil_steps));
  Scene anchored_scene = coil_helix_scene(coil_bones, ctx.quick ? 2 : 10, coil_steps);
  anchored_scene.params.friction_stiffness = anchored_scene.params.contact_k;
  const CoilMeasured anchored = coil(ctx, "coil_static_friction", anchored_scene);
  add_coil_claims(report, dropped, laid, anchored, coil_helix_scene(coil_bones, 1, 1).params.dt);
  return {{"coil", to_json(dropped)},
          {"coil_laid", to_json(laid)},
          {"coil_static_friction", to_json(anchored)}};
}

}  // namespace physik::experiments::contacts_study
