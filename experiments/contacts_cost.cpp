// Contacts' step cost: the benchmark targets, measured on every `make reproduce`, with
// the same scenes and timed loop as bench/bench_contacts.cpp (experiments/contacts_scenes.h).
//   pinhead  the hand scene under gravity with the floor and self-collision, against the same
//            scene with neither, whole 300-step runs of the implicit scheme (dt 0.05 s).
//            Target: the step with contacts at most 2x the step without.
//   coils    a chain of N bones lying coiled on the floor with self-collision (experiments/coil.h),
//            against the same chain with neither, the first 10 steps of dt 0.01 s, at N = 125,
//            250, 500 and 1,000: the flat spiral (the contacts experiment's laid coil, whose
//            candidate pairs per bone rise with N) and the flat ring (four turns at every N,
//            its pairs per bone nearly fixed). Targets: at most 5x at 1,000 bones; the contact
//            step growing no faster than n log n from 125 to 1,000 bones (a factor
//            8 log 1000 / log 125 = 11.45), judged on the ring.
// Every figure is the fastest of 21 timed runs, each from init_state (untimed), thread CPU time
// (scaling.h thread_seconds), as the timing experiment keeps the best whole run: three sweeps
// over the workloads, each taking seven runs of a workload in a row (warm caches, as in a long
// run), so that a spell of a busy machine slows one sweep, not all of a workload's runs. An
// untimed run first counts the contacts per step. Each sweep's first run of a workload with the
// contacts follows another workload's runs, whose data fills the caches: the fastest of those
// is reported too (cold_contacts_us), without a verdict. Each workload keeps its own states, so
// that no timed run starts on buffers another workload's rig resized. The benchmark reports the
// mean per step over its iterations (medians with --benchmark_repetitions); both are this
// machine's times, not a test. Quick: 125 and 250 bones, one run each.
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "experiments/coil.h"
#include "experiments/common.h"
#include "experiments/contacts_scenes.h"
#include "experiments/scaling.h"
#include "experiments/table.h"
#include "physik/engine/engine.h"

namespace physik::experiments {

namespace {

// One workload at one size: its scenes, the fastest runs with and without the contacts, and the
// contacts.
struct Cost {
  std::string workload;
  Scene on, off;
  SimState s_on, s_off;  // each scene's own state, its buffers kept from run to run
  int bones = 0, steps = 0;
  double contacts_us = std::numeric_limits<double>::infinity();  // us per step
  double no_contacts_us = std::numeric_limits<double>::infinity();
  double cold_contacts_us = std::numeric_limits<double>::infinity();  // a sweep's first run
  double ground = 0.0, self = 0.0;            // contacts per step over the run
  double substeps = 0.0, substeps_off = 0.0;  // per step, with the contacts and without
  double pairs_per_bone = 0.0;  // the broad phase's candidate pairs per bone at the start
  double ratio() const { return contacts_us / no_contacts_us; }
};

Cost workload(const std::string& name, Scene on, Scene off, int steps) {
  Cost c;
  c.workload = name;
  c.on = std::move(on);
  c.off = std::move(off);
  c.bones = c.on.rig.nbone;
  c.steps = steps;
  init_state(c.on, c.s_on);  // the untimed run: contacts per step
  for (int k = 0; k < steps; ++k) {
    step(c.on, c.s_on);
    for (const Contact& ct : c.s_on.contact.found) {
      (ct.other_bone >= 0 ? c.self : c.ground) += 1.0 / steps;
    }
  }
  return c;
}

// us per step of one timed run of the scene from init_state (on `s`, sized for it by the last
// run), its substeps per step
double run_us(const Scene& scene, int steps, SimState& s, double& substeps) {
  init_state(scene, s);
  TimedSteps t;
  time_steps(scene, s, steps, t);
  if (!t.finite) throw std::runtime_error("contacts_cost: " + scene.file + " diverged");
  substeps = static_cast<double>(t.substeps) / steps;
  return 1e6 * t.seconds / steps;
}

// `sweeps` sweeps over every workload, each taking `repeats` runs with the contacts and as many
// without, alternately, and keeping each one's fastest: a workload's runs follow one another,
// as a run's steps do (warm caches), and a spell of a busy machine slows one sweep's runs, not
// all of a workload's
void time_all(std::vector<Cost>& costs, int sweeps, int repeats) {
  for (int w = 0; w < sweeps; ++w) {
    for (Cost& c : costs) {
      for (int r = 0; r < repeats; ++r) {
        const double us = run_us(c.on, c.steps, c.s_on, c.substeps);
        c.contacts_us = std::min(c.contacts_us, us);
        if (r == 0) c.cold_contacts_us = std::min(c.cold_contacts_us, us);
        c.no_contacts_us =
            std::min(c.no_contacts_us, run_us(c.off, c.steps, c.s_off, c.substeps_off));
      }
    }
  }
}

Table tabulate(const std::vector<Cost>& costs) {
  Table t("contacts_cost", "",
          {text("workload", "pinhead, or the coil: flat_spiral or flat_ring (coil.h)"),
           integer("bones", "", "the rig's bones"),
           integer("steps", "steps", "steps of each timed run"),
           real("contacts_us", "us", "thread time per step with the contacts, fastest run"),
           real("no_contacts_us", "us", "the same without them"),
           real("ratio", "", "contacts_us / no_contacts_us"),
           real("ground_contacts", "", "ground contacts per step over the run"),
           real("self_contacts", "", "bone-bone contacts per step over the run"),
           real("cold_contacts_us", "us",
                "contacts_us of the runs that follow another workload's (cold caches)"),
           real("substeps", "", "the energy guard's substeps per step with the contacts"),
           real("substeps_off", "", "the same without them"),
           real("pairs_per_bone", "", "candidate pairs per bone at the start (coil.h)")});
  for (const Cost& c : costs) {
    t.add({c.workload, c.bones, c.steps, c.contacts_us, c.no_contacts_us, c.ratio(), c.ground,
           c.self, c.cold_contacts_us, c.substeps, c.substeps_off, c.pairs_per_bone});
  }
  return t;
}

// a coil workload's rows, smallest first (measure_all's order)
std::vector<const Cost*> of(const std::vector<Cost>& costs, const std::string& workload) {
  std::vector<const Cost*> out;
  for (const Cost& c : costs) {
    if (c.workload == workload) out.push_back(&c);
  }
  return out;
}

// a count to the unit ("2007")
std::string count(double v) {
  return std::to_string(std::lround(v));
}

void add_claims(Report& report, const std::vector<Cost>& costs) {
  const Cost& pin = costs.front();
  report.claim(
      "Pinhead with the floor and self-collision on: the implicit step costs at most 2x "
      "the step without contacts",
      num(pin.contacts_us) + " us against " + num(pin.no_contacts_us) + " us: " + num(pin.ratio()) +
          "x (" + num(pin.ground) + " ground and " + num(pin.self) +
          " bone-bone contacts per step)",
      pin.ratio() <= 2.0 ? "yes" : "no");
  report.named("pinhead-step");
  const std::vector<const Cost*> spiral = of(costs, "flat_spiral"), ring = of(costs, "flat_ring");
  const Cost &s = *spiral.back(), &r = *ring.back(), &s0 = *spiral.front(), &r0 = *ring.front();
  report.claim("A " + std::to_string(s.bones) +
                   "-bone chain coiled on the floor: the step costs at most 5x the contact-free "
                   "step",
               "flat spiral " + num(s.ratio()) + "x (" + count(s.ground + s.self) +
                   " contacts per step), flat ring " + num(r.ratio()) + "x (" +
                   count(r.ground + r.self) + " contacts per step)",
               s.ratio() <= 5.0 && r.ratio() <= 5.0 ? "yes" : "no");
  report.named("coil-step");
  const int n0 = r0.bones, n1 = r.bones;
  const double nlogn = n1 * std::log(double(n1)) / (n0 * std::log(double(n0)));
  const double ring_growth = r.contacts_us / r0.contacts_us;
  report.claim("The coiled chain's contact step grows no faster than n log n from " +
                   std::to_string(n0) + " to " + std::to_string(n1) +
                   " bones (the flat ring, whose work per bone is nearly fixed)",
               "flat ring " + num(ring_growth) + "x against n log n's " + num(nlogn) +
                   "x (candidate pairs per bone " + num(r0.pairs_per_bone) + " to " +
                   num(r.pairs_per_bone) + "); flat spiral " + num(s.contacts_us / s0.contacts_us) +
                   "x (pairs per bone " + num(s0.pairs_per_bone) + " to " + num(s.pairs_per_bone) +
                   ")",
               ring_growth <= nlogn ? "yes" : "no");
  report.named("coil-growth");
}

// three sweeps of seven runs in a row per workload (the header); quick: one run
int sweeps(const Context& ctx) {
  return ctx.quick ? 1 : 3;
}
int repeats(const Context& ctx) {
  return ctx.quick ? 1 : 7;
}

std::vector<Cost> measure_all(const Context& ctx) {
  const std::vector<int> sizes =
      ctx.quick ? std::vector<int>{125, 250} : std::vector<int>{125, 250, 500, 1000};
  std::vector<Cost> costs;
  costs.reserve(1 + 2 * sizes.size());  // no reallocation: a Cost holds two states
  costs.push_back(workload("pinhead", contacts_cost_pinhead_scene(ctx.models_dir, true),
                           contacts_cost_pinhead_scene(ctx.models_dir, false), 300));
  constexpr int kCoilSteps = 10, kRingTurns = 4;
  for (const int n : sizes) {
    costs.push_back(workload("flat_spiral", coil_flat_spiral_scene(n, true),
                             coil_flat_spiral_scene(n, false), kCoilSteps));
  }
  for (const int n : sizes) {
    costs.push_back(workload("flat_ring", coil_flat_ring_scene(n, kRingTurns, true),
                             coil_flat_ring_scene(n, kRingTurns, false), kCoilSteps));
  }
  for (Cost& c : costs) {
    c.pairs_per_bone =
        candidate_pairs_per_bone(c.on, forward_kinematics(c.on.rig, c.on.initial_pose));
  }
  time_all(costs, sweeps(ctx), repeats(ctx));
  if (ctx.log) {
    for (const Cost& c : costs) {
      *ctx.log << "  " << c.workload << " " << c.bones << ": " << num(c.contacts_us) << " us/step, "
               << num(c.ratio()) << "x\n";
    }
  }
  return costs;
}

void run(const Context& ctx) {
  const std::vector<Cost> costs = measure_all(ctx);
  const Table table = tabulate(costs);
  Report report("Contacts: the step's cost");
  add_claims(report, costs);
  table.add_to_report(report, "Step cost with and without contacts (thread CPU time)",
                      {{"workload", "workload"},
                       {"bones", "bones"},
                       {"us/step with contacts", "contacts_us"},
                       {"without", "no_contacts_us"},
                       {"ratio", "ratio"},
                       {"ground contacts/step", "ground_contacts"},
                       {"bone-bone/step", "self_contacts"},
                       {"pairs/bone", "pairs_per_bone"},
                       {"cold, us/step", "cold_contacts_us"}},
                      4);
  report
      .note(
          "Thread CPU time on this machine, each run from init_state. Each figure is the "
          "fastest of " +
          std::to_string(sweeps(ctx) * repeats(ctx)) + " runs: " + std::to_string(sweeps(ctx)) +
          " sweeps over the workloads, each taking " + std::to_string(repeats(ctx)) +
          " runs of a workload in a row, as a long run's steps follow one another on the same "
          "data (warm caches). The cold column is the fastest of each sweep's first run of a "
          "workload with contacts, which follows another workload's runs (their data in the "
          "caches). Coils: the first 10 steps of dt 0.01 s; pinhead: the whole 300-step "
          "run. `make bench` times the same runs (bench/bench_contacts.cpp).")
      .figures({"contacts_cost.png"});
  write_summary(ctx, {{"experiment", "contacts_cost"}, {"rows", table.rows_json()}}, report,
                {&table});
}

const Registration registered{
    291,
    {"contacts_cost", "study: contacts",
     "the step's cost with a floor and self-collision against the step without", run}};

}  // namespace

}  // namespace physik::experiments
