// The implicit step with contacts beside the same scene without them, in the same run, thread CPU
// time per step. Every timed run starts from init_state (untimed, as a run starts), so that the
// runs of a benchmark are one and the same run; allocations are counted over the timed steps.
//
// The experiment `contacts_cost` (experiments/contacts_cost.cpp) times the same runs on every
// `make reproduce` (the fastest of several) and reports the targets' claims; here each counter
// is the mean per step over the benchmark's iterations (--benchmark_repetitions=3 for medians).
//
// ImplicitPinheadContacts: experiments/contacts_scenes.h contacts_cost_pinhead_scene (the
// contacts experiment's hand scene under gravity, with the floor and self-collision), beside
// the same scene with neither (gravity kept). The whole run, 300 steps of the implicit scheme at
// dt 0.05 s. Target: ratio at most 2.
//
// ImplicitCoil, ImplicitCoilRing: a chain of N bones lying coiled on the floor with
// self-collision (experiments/coil.h), beside the same chain in the same pose with neither
// (gravity kept), the first 10 steps:
//   ImplicitCoil      the flat spiral, the contacts experiment's laid coil: 2N ground contacts
//                     and 7 self-contacts on its innermost turns; its turn count grows with N,
//                     and its candidate pairs per bone with it (by about a quarter from 125 to
//                     1,000 bones)
//   ImplicitCoilRing  the flat ring, four turns at every N whose turns clear each other: 2N
//                     ground contacts, no self-contact at the start, and candidate pairs per bone
//                     within a few percent at every N
// Targets: ratio at most 5 at 1,000 bones; contacts_us growing no faster than n log n from 125 to
// 1,000 bones (a factor 8 log 1000 / log 125 = 11.4), judged on the ring, whose work per bone is
// nearly the same at every size.
//
// ImplicitStiffFloorAtRest: one bone (1 kg, 1 rig unit) lying on a floor of contact_k 1e20 under
// gravity, implicit_max_splits 20: its rest depth W / k is below a coordinate's resolution, so
// every step starts just off the floor (implicit_advance.h). The run of 10 steps, the energy
// guard's substeps and retaken (sub)steps per step. Target: the run under 0.5 s (the guard split
// every step 2^19 times before it retook a step with the contacts it reached: 9.8 s).
//
// Counters:
//   contacts_us, no_contacts_us   step() with the contacts, without them
//   ratio            contacts_us / no_contacts_us
//   substeps, substeps_off        the energy guard's substeps per step (implicit_advance.h)
//   allocs_per_step  heap allocations per timed step with the contacts
//   ground_contacts, self_contacts   (pinhead) per step over the run
//   contacts, self_contacts          (coils) found at the initial pose
//   detect_us        (coils) CollisionWorld::detect alone (part of contacts_us), alternately on
//                    the initial pose and on the pose after the steps
//   pairs_per_bone   (coils) the broad phase's workload at the initial pose (coil.h)
#include <benchmark/benchmark.h>

#include <string>
#include <vector>

#include "bench/alloc_counter.h"
#include "experiments/coil.h"
#include "experiments/contacts_scenes.h"
#include "experiments/scaling.h"
#include "physik/engine/collision.h"
#include "physik/engine/engine.h"

namespace {

using physik::experiments::coil_flat_ring_scene;
using physik::experiments::coil_flat_spiral_scene;
using physik::experiments::thread_seconds;

// A timed run of `steps` steps from the scene's start (init_state, untimed), its allocations.
struct Run {
  physik::experiments::TimedSteps timed;
  long allocations = 0;
};

void time_run(const physik::Scene& scene, physik::SimState& s, int steps, Run& r) {
  physik::init_state(scene, s);
  const long a0 = physik::bench::allocations();
  physik::experiments::time_steps(scene, s, steps, r.timed);
  r.allocations += physik::bench::allocations() - a0;
}

// the shared counters of a benchmark's runs with and without the contacts; false (and the
// benchmark skipped with an error) when a run did not stay finite
bool report_runs(benchmark::State& state, const Run& on, const Run& off, long steps) {
  if (!on.timed.finite || !off.timed.finite) {
    state.SkipWithError(on.timed.finite ? "the run without contacts diverged" : "the run diverged");
    return false;
  }
  state.counters["contacts_us"] = 1e6 * on.timed.seconds / steps;
  state.counters["no_contacts_us"] = 1e6 * off.timed.seconds / steps;
  state.counters["ratio"] = on.timed.seconds / off.timed.seconds;
  state.counters["substeps"] = static_cast<double>(on.timed.substeps) / steps;
  state.counters["substeps_off"] = static_cast<double>(off.timed.substeps) / steps;
  state.counters["allocs_per_step"] = static_cast<double>(on.allocations) / steps;
  return true;
}

physik::Scene pinhead_scene(bool contacts) {
  return physik::experiments::contacts_cost_pinhead_scene(
      std::string(PHYSIK_SOURCE_DIR) + "/models", contacts);
}

void BM_ImplicitPinheadContacts(benchmark::State& state) {
  const physik::Scene on = pinhead_scene(true), off = pinhead_scene(false);
  physik::SimState s_on, s_off;
  // an untimed run, the same as every timed one: its contacts per step
  long ground = 0, self = 0;
  physik::init_state(on, s_on);
  for (int k = 0; k < on.steps; ++k) {
    physik::step(on, s_on);
    for (const physik::Contact& c : s_on.contact.found) ++(c.other_bone >= 0 ? self : ground);
  }
  Run r_on, r_off;
  long steps = 0;
  for (auto _ : state) {
    time_run(on, s_on, on.steps, r_on);
    time_run(off, s_off, off.steps, r_off);
    steps += on.steps;
  }
  if (!report_runs(state, r_on, r_off, steps)) return;
  state.counters["ground_contacts"] = static_cast<double>(ground) / on.steps;
  state.counters["self_contacts"] = static_cast<double>(self) / on.steps;
}

constexpr int kCoilSteps = 10;

void run_coil(benchmark::State& state, const physik::Scene& on, const physik::Scene& off) {
  const int n = on.rig.nbone;
  physik::SimState s_on, s_off;
  physik::init_state(on, s_on);
  const physik::BoneFrames start = s_on.frames;
  std::vector<physik::Contact> contacts;
  physik::CollisionWorld world;
  world.detect(on, start, contacts);
  Run r_on, r_off;
  double t_detect = 0.0;
  long steps = 0;
  for (auto _ : state) {
    time_run(on, s_on, kCoilSteps, r_on);
    time_run(off, s_off, kCoilSteps, r_off);
    // alternately at the start and at the pose the steps reached, so no query repeats the last
    const double t0 = thread_seconds();
    for (int k = 0; k < kCoilSteps; ++k) {
      world.detect(on, k % 2 == 0 ? start : s_on.frames, contacts);
    }
    t_detect += thread_seconds() - t0;
    steps += kCoilSteps;
  }
  if (!report_runs(state, r_on, r_off, steps)) return;
  world.detect(on, start, contacts);
  int self = 0;
  for (const physik::Contact& c : contacts) self += c.other_bone >= 0 ? 1 : 0;
  state.counters["detect_us"] = 1e6 * t_detect / steps;
  state.counters["contacts"] = static_cast<double>(contacts.size());
  state.counters["self_contacts"] = self;
  state.counters["nbone"] = n;
  state.counters["pairs_per_bone"] = physik::experiments::candidate_pairs_per_bone(on, start);
}

void BM_ImplicitCoil(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  run_coil(state, coil_flat_spiral_scene(n, true), coil_flat_spiral_scene(n, false));
}

constexpr int kRingTurns = 4;

void BM_ImplicitCoilRing(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  run_coil(state, coil_flat_ring_scene(n, kRingTurns, true),
           coil_flat_ring_scene(n, kRingTurns, false));
}

// one bone lying on a floor too stiff for its rest depth (above)
physik::Scene stiff_floor_scene() {
  physik::BoneSpec b;
  b.name = "a";
  b.head_world = physik::Vec3(0.0, 0.0, 0.06);  // the capsule (radius 0.06) on the floor
  b.tail_world = physik::Vec3(1.0, 0.0, 0.06);
  b.rest_frame_world = physik::rest_frame_from_roll(b.head_world, b.tail_world, 0.0);
  b.mass = 1.0;
  b.radius = 0.5;
  physik::Scene s;
  s.rig = physik::build_rig({b}, "<bench>", "bone");
  s.params = physik::preset_params("robust");
  s.params.contact_k = 1e20;
  s.params.implicit_max_splits = 20;
  s.initial_pose = physik::rest_pose(s.rig);
  s.gravity_world = physik::Vec3(0.0, 0.0, -9.81);
  s.collision.ground = physik::GroundPlane{};
  s.steps = 10;
  return s;
}

void BM_ImplicitStiffFloorAtRest(benchmark::State& state) {
  const physik::Scene scene = stiff_floor_scene();
  physik::SimState s;
  Run r;
  long steps = 0;
  for (auto _ : state) {
    time_run(scene, s, scene.steps, r);
    steps += scene.steps;
  }
  if (!r.timed.finite) {
    state.SkipWithError("the run diverged");
    return;
  }
  state.counters["run_ms"] = 1e3 * r.timed.seconds * scene.steps / steps;
  state.counters["substeps"] = static_cast<double>(r.timed.substeps) / steps;
  state.counters["retaken"] = static_cast<double>(s.implicit.retaken_steps) / scene.steps;
  state.counters["allocs_per_step"] = static_cast<double>(r.allocations) / steps;
}

BENCHMARK(BM_ImplicitPinheadContacts)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ImplicitStiffFloorAtRest)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ImplicitCoil)->Arg(125)->Arg(250)->Arg(500)->Arg(1000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ImplicitCoilRing)
    ->Arg(125)
    ->Arg(250)
    ->Arg(500)
    ->Arg(1000)
    ->Unit(benchmark::kMillisecond);

}  // namespace
