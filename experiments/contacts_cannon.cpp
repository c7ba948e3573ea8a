// The contacts experiment's cannon study (experiments/contacts.cpp):
//   cannon Fig 7's linear cannon (the torso's centre pulled 12 units away, linear spring):
//         the deepest bone-bone overlap over the run over the thinner radius (as the hand's),
//         in the paper's scheme as shipped (no contacts) and, with and without self-collision,
//         in the implicit scheme at the paper's dt 0.05 (the paper's explicit scheme at dt
//         0.05 is unstable at any contact stiffness that stops a bone)
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "experiments/common.h"
#include "experiments/contacts.h"
#include "experiments/report.h"
#include "physik/engine/contact_data.h"
#include "physik/io/recorder.h"
#include "physik/io/scene_io.h"

namespace physik::experiments::contacts_study {

namespace {

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
  ContactData data;  // one world for the whole run's measures
  prepare_contact_data(measure, data);
  CannonRun out;
  const RecordedRun run =
      record_run(scene, RecordOptions{}, [&](const SimState& s, const StepStats&) {
        out.deepest =
            std::max(out.deepest, penetration(measure, s.frames, data).max_depth_fraction);
      });
  out.diverged = run.summary.diverged;
  write_run_folder(ctx, name, scene);
  if (ctx.log) *ctx.log << "  " << name << ": deepest overlap " << num(out.deepest) << "\n";
  return out;
}

nlohmann::json to_json(const CannonRun& r) {
  return {{"deepest_bone_overlap_over_radius", r.deepest}, {"diverged", r.diverged}};
}

}  // namespace

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

}  // namespace physik::experiments::contacts_study
