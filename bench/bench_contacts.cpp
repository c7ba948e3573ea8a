// The implicit step with contacts on a long chain coiled on the floor (experiments/coil.h, the
// flat spiral: about 2N ground contacts and a self-contact or two per bone), beside the same chain
// in the same pose with the contacts off (gravity kept), in the same run, thread CPU time.
// Each iteration puts the initial pose back (set_pose: the state's buffers and its collision world
// are kept, as in a run) and times the same first steps of each, per step:
//   contacts_us      step() with the ground and self-collision (FCL broad and narrow phase, the
//                    contact forces and their elements, the step with augmented inertias)
//   no_contacts_us   step() with neither
//   ratio            contacts_us / no_contacts_us (target: at most 5 at 1,000 bones)
//   detect_us        CollisionWorld::detect alone (part of contacts_us), alternately on the initial
//                    pose and on the pose after the steps
//   contacts, self_contacts   found at the initial pose
//   substeps         the energy guard's substeps per step (implicit_advance.h)
//   pairs_per_bone   the broad phase's workload at the initial pose: bone pairs whose capsule
//                    boxes overlap, bones sharing a joint excluded (a brute-force count), over N
// Two workloads (experiments/coil.h):
//   ImplicitCoil      the flat spiral, the contacts experiment's: its turn count grows with N, and
//                     its pairs per bone with it (by about a quarter from 125 to 1,000 bones)
//   ImplicitCoilRing  the flat ring, four turns at every N: the same pairs per bone at every N
// BM_ImplicitPinheadContacts: pinhead under gravity with its torso held by two springs and its
// left hand pulled through the torso (the contacts experiment's hand scene), the floor at its
// rest pose's lowest point and self-collision on, beside the same scene with neither: the feet
// and hands come onto the floor and the arm onto the torso. Times the whole run (300 steps of the
// implicit scheme, dt 0.05 s), per step, each from the initial pose put back with set_pose (the
// buffers kept, as in a run; the targets stay where the last run left them, at their goals).
// ground_contacts and self_contacts: per step over the run. Target: ratio at most 2.
// Growth target: contacts_us no faster than n log n from 125 to 1000 bones (a factor 8 log 1000 /
// log 125 = 11.4), judged on the ring, whose work per bone is the same at every size.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <limits>
#include <vector>

#include <Eigen/Geometry>

#include "bench/alloc_counter.h"
#include "experiments/coil.h"
#include "experiments/scaling.h"
#include "physik/engine/collision.h"
#include "physik/engine/engine.h"
#include "physik/io/scene_io.h"

namespace {

using physik::experiments::coil_flat_ring_scene;
using physik::experiments::coil_flat_spiral_scene;
using physik::experiments::thread_seconds;

constexpr int kSteps = 10;

// s of thread time for kSteps steps from the initial pose; adds the substeps taken
double time_steps(const physik::Scene& scene, physik::SimState& s, long& substeps) {
  physik::set_pose(scene, s, scene.initial_pose);
  const double t0 = thread_seconds();
  for (int k = 0; k < kSteps; ++k) {
    const physik::StepStats st = physik::step(scene, s);
    substeps += st.substeps;
    benchmark::DoNotOptimize(st.kinetic_energy);
  }
  return thread_seconds() - t0;
}

// bone pairs whose capsule boxes overlap at these frames, bones sharing a joint excluded
long overlapping_boxes(const physik::Scene& scene, const physik::BoneFrames& f) {
  const int n = scene.rig.nbone;
  std::vector<Eigen::AlignedBox3d> box(n);
  for (int i = 0; i < n; ++i) {
    const physik::Vec3 r = physik::Vec3::Constant(scene.rig.bone_collision_radius[i]);
    box[i] = Eigen::AlignedBox3d(f.head_world[i].cwiseMin(f.tail_world[i]) - r,
                                 f.head_world[i].cwiseMax(f.tail_world[i]) + r);
  }
  long count = 0;
  for (int a = 0; a < n; ++a)
    for (int b = a + 1; b < n; ++b)
      if (!scene.rig.bones_share_joint(a, b) && box[a].intersects(box[b])) ++count;
  return count;
}

void run_coil(benchmark::State& state, const physik::Scene& on, const physik::Scene& off) {
  const int n = on.rig.nbone;
  physik::SimState s_on, s_off;
  physik::init_state(on, s_on);
  physik::init_state(off, s_off);
  const physik::BoneFrames start = s_on.frames;
  std::vector<physik::Contact> contacts;
  physik::CollisionWorld world;
  world.detect(on, start, contacts);
  long warm = 0;  // one untimed batch of each: buffers at their run's size, FCL's world built
  time_steps(on, s_on, warm);
  time_steps(off, s_off, warm);
  double t_on = 0.0, t_off = 0.0, t_detect = 0.0;
  long steps = 0, sub_on = 0, sub_off = 0, allocs = 0;
  for (auto _ : state) {
    const long a0 = physik::bench::allocations();
    t_on += time_steps(on, s_on, sub_on);
    allocs += physik::bench::allocations() - a0;
    t_off += time_steps(off, s_off, sub_off);
    // alternately at the start and at the pose the steps reached, so no query repeats the last
    const double t0 = thread_seconds();
    for (int k = 0; k < kSteps; ++k) world.detect(on, k % 2 == 0 ? start : s_on.frames, contacts);
    t_detect += thread_seconds() - t0;
    steps += kSteps;
  }
  world.detect(on, start, contacts);
  int self = 0;
  for (const physik::Contact& c : contacts) self += c.other_bone >= 0 ? 1 : 0;
  state.counters["contacts_us"] = 1e6 * t_on / steps;
  state.counters["no_contacts_us"] = 1e6 * t_off / steps;
  state.counters["ratio"] = t_on / t_off;
  state.counters["detect_us"] = 1e6 * t_detect / steps;
  state.counters["contacts"] = static_cast<double>(contacts.size());
  state.counters["self_contacts"] = self;
  state.counters["substeps"] = static_cast<double>(sub_on) / steps;
  state.counters["substeps_off"] = static_cast<double>(sub_off) / steps;
  state.counters["allocs_per_step"] = static_cast<double>(allocs) / steps;
  state.counters["nbone"] = n;
  state.counters["pairs_per_bone"] = static_cast<double>(overlapping_boxes(on, start)) / n;
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

// the contacts experiment's hand scene under gravity, with the floor and self-collision or neither
physik::Scene pinhead_scene(bool contacts) {
  nlohmann::json doc = {{"rig", std::string(PHYSIK_SOURCE_DIR) + "/models/rigs/pinhead.json"},
                        {"params", {{"preset", "robust"}, {"dt", 0.05}, {"damping", 3.0}}},
                        {"steps", 300},
                        {"gravity", {0, 0, -9.81}},
                        {"control_points",
                         {{{"name", "neck"},
                           {"bone", "torso"},
                           {"alpha", 0.0},
                           {"target", {0, 0, 1.8155}},
                           {"k", 300}},
                          {{"name", "pelvis"},
                           {"bone", "torso"},
                           {"alpha", 1.0},
                           {"target", {0, 0, 0.4541}},
                           {"k", 300}},
                          {{"name", "hand.L"},
                           {"bone", "hand.L"},
                           {"alpha", 1.0},
                           {"target", {-1.0, 0, 1.0}},
                           {"k", 30}}}}};
  physik::Scene probe = physik::scene_from_json(doc, "bench_pinhead", ".");
  if (contacts) {
    const physik::BoneFrames f = physik::forward_kinematics(probe.rig, probe.initial_pose);
    double lowest = std::numeric_limits<double>::infinity();
    for (int i = 0; i < probe.rig.nbone; ++i) {
      lowest = std::min(lowest, std::min(f.head_world[i].z(), f.tail_world[i].z()) -
                                    probe.rig.bone_collision_radius[i]);
    }
    doc["ground"] = {{"height", lowest}, {"normal", {0, 0, 1}}};
    doc["self_collision"] = true;
  }
  return physik::scene_from_json(doc, "bench_pinhead", ".");
}

// per step over one run from the initial pose: its s of thread time, its substeps, its ground
// and bone-bone contacts
struct PinheadRun {
  double seconds = 0.0;
  long substeps = 0, ground = 0, self = 0;
};
void run_pinhead(const physik::Scene& scene, physik::SimState& s, PinheadRun& r) {
  physik::set_pose(scene, s, scene.initial_pose);
  const double t0 = thread_seconds();
  for (int k = 0; k < scene.steps; ++k) {
    r.substeps += physik::step(scene, s).substeps;
    for (const physik::Contact& c : s.contacts) ++(c.other_bone >= 0 ? r.self : r.ground);
  }
  r.seconds += thread_seconds() - t0;
}

void BM_ImplicitPinheadContacts(benchmark::State& state) {
  const physik::Scene on = pinhead_scene(true), off = pinhead_scene(false);
  physik::SimState s_on, s_off;
  physik::init_state(on, s_on);
  physik::init_state(off, s_off);
  PinheadRun warm, r_on, r_off;  // one untimed run of each: buffers at their run's size
  run_pinhead(on, s_on, warm);
  run_pinhead(off, s_off, warm);
  long steps = 0, allocs = 0;
  for (auto _ : state) {
    const long a0 = physik::bench::allocations();
    run_pinhead(on, s_on, r_on);
    allocs += physik::bench::allocations() - a0;
    run_pinhead(off, s_off, r_off);
    steps += on.steps;
  }
  state.counters["contacts_us"] = 1e6 * r_on.seconds / steps;
  state.counters["no_contacts_us"] = 1e6 * r_off.seconds / steps;
  state.counters["ratio"] = r_on.seconds / r_off.seconds;
  state.counters["ground_contacts"] = static_cast<double>(r_on.ground) / steps;
  state.counters["self_contacts"] = static_cast<double>(r_on.self) / steps;
  state.counters["substeps"] = static_cast<double>(r_on.substeps) / steps;
  state.counters["allocs_per_step"] = static_cast<double>(allocs) / steps;
}

BENCHMARK(BM_ImplicitPinheadContacts)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ImplicitCoil)->Arg(125)->Arg(250)->Arg(500)->Arg(1000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ImplicitCoilRing)
    ->Arg(125)
    ->Arg(250)
    ->Arg(500)
    ->Arg(1000)
    ->Unit(benchmark::kMillisecond);

}  // namespace
