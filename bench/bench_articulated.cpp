// The exact joint solve (scheme exact: articulated-body algorithm + MuJoCo's Euler in joint
// space) beside mj_step on the equivalent ball-joint model, in thread CPU
// time (other processes on a shared machine do not count). Each iteration restores the same
// initial state and times the same first steps of the run (motion, not rest), per step:
//   exact_us     PhysIK's whole step() with scheme exact (force stages included)
//   gs_us        PhysIK's step() with the paper's Gauss-Seidel solve (pinhead only)
//   mj_step_us   mj_step on the ball-joint MJCF of the same rig, replaying the applied forces
//                (xfrc_applied) of a same-forces reference run: the same trajectory, MuJoCo's cost
//                without PhysIK's force stages
//   exact_over_mj_step = exact_us / mj_step_us  (target: <= 0.5 on pinhead)
//   implicit_us  PhysIK's step() with scheme implicit (linearised backward Euler over the
//                exact solve, implicit_step.h)
//   implicit_over_mj_step = implicit_us / mj_step_us  (target: <= 1.0 on pinhead)
// Scaling (BM_Exact / BM_MjStep, rig = chain or tree2 (balanced binary tree), N bones): the
// scaling experiment's scenario (experiments/scaling.h). Targets:
// <= 0.5 us per bone per step at 10,000 bones; cost exponent <= 1.1 (fit us_per_step vs N).
// BM_Implicit: the same scenario with scheme implicit (target: <= 1 us per bone
// per step at 10,000 bones). BM_ExactIeee, BM_ImplicitIeee: the same with flush_subnormals off.
// mj_step grows ~N^2.7 on chains (dense ancestor blocks of M), so it is run only up to 1000 bones.
#include <algorithm>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "bench/alloc_counter.h"
#include "experiments/scaling.h"
#include "physik/io/scene_io.h"

namespace {

using physik::experiments::MjStepReplay;
using physik::experiments::record_mj_step_replay;
using physik::experiments::scaling_scene;
using physik::experiments::thread_seconds;
using physik::experiments::time_mj_step_replay;

std::string scene_file(const std::string& name) {
  return std::string(PHYSIK_SOURCE_DIR) + "/models/scenes/" + name + ".json";
}

int steps_for(int n) {
  return std::clamp(20000 / n, 2, 100);
}

// the timed steps of step() from the scene's initial state, us per step
void time_physik(benchmark::State& state, const physik::Scene& scene, int steps) {
  physik::SimState initial;
  physik::init_state(scene, initial);
  physik::SimState s = initial;
  double t = 0.0;
  long n = 0, allocs = 0;
  for (auto _ : state) {
    s = initial;
    const long a0 = physik::bench::allocations();
    const double t0 = thread_seconds();
    for (int k = 0; k < steps; ++k) benchmark::DoNotOptimize(physik::step(scene, s).kinetic_energy);
    t += thread_seconds() - t0;
    allocs += physik::bench::allocations() - a0;
    n += steps;
  }
  state.counters["us_per_step"] = 1e6 * t / n;
  state.counters["us_per_bone"] = 1e6 * t / n / scene.rig.nbone;
  state.counters["allocs_per_step"] = static_cast<double>(allocs) / n;
  state.counters["nbone"] = scene.rig.nbone;
}

void BM_Exact(benchmark::State& state, const std::string& kind) {
  const int n = static_cast<int>(state.range(0));
  time_physik(state, scaling_scene(kind, n), steps_for(n));
}

void BM_Implicit(benchmark::State& state, const std::string& kind) {
  const int n = static_cast<int>(state.range(0));
  physik::Scene scene = scaling_scene(kind, n);
  scene.params.scheme = physik::Scheme::kImplicit;
  time_physik(state, scene, steps_for(n));
}

// the same two with IEEE gradual underflow (flush_subnormals false; docs/engine.md "Subnormal
// numbers"): beside BM_Exact and BM_Implicit, the flush's effect on the time per bone
void BM_ExactIeee(benchmark::State& state, const std::string& kind) {
  physik::Scene scene = scaling_scene(kind, static_cast<int>(state.range(0)));
  scene.params.flush_subnormals = false;
  time_physik(state, scene, steps_for(scene.rig.nbone));
}

void BM_ImplicitIeee(benchmark::State& state, const std::string& kind) {
  physik::Scene scene = scaling_scene(kind, static_cast<int>(state.range(0)));
  scene.params.scheme = physik::Scheme::kImplicit;
  scene.params.flush_subnormals = false;
  time_physik(state, scene, steps_for(scene.rig.nbone));
}

void BM_MjStep(benchmark::State& state, const std::string& kind) {
  const int n = static_cast<int>(state.range(0));
  const physik::Scene scene = scaling_scene(kind, n);
  MjStepReplay r = record_mj_step_replay(scene, std::clamp(2000 / n, 2, 100));
  double us = 0.0;
  long iters = 0;
  for (auto _ : state) {
    us += time_mj_step_replay(r);
    ++iters;
  }
  state.counters["us_per_step"] = us / iters;
  state.counters["us_per_bone"] = us / iters / n;
  state.counters["nbone"] = n;
}

// a paper scene: exact, Gauss-Seidel and mj_step in one run, and the ratio
void BM_ExactVsMjStep(benchmark::State& state, const std::string& name) {
  physik::Scene exact = physik::load_scene(scene_file(name));
  exact.params.scheme = physik::Scheme::kExact;
  const physik::Scene gs = physik::load_scene(scene_file(name));
  physik::Scene implicit = physik::load_scene(scene_file(name));
  implicit.params.scheme = physik::Scheme::kImplicit;
  constexpr int kSteps = 100;
  MjStepReplay r = record_mj_step_replay(exact, kSteps);
  physik::SimState init_exact, init_gs, init_implicit;
  physik::init_state(exact, init_exact);
  physik::init_state(gs, init_gs);
  physik::init_state(implicit, init_implicit);
  double t_exact = 0.0, t_gs = 0.0, t_implicit = 0.0, t_mj = 0.0;
  long steps = 0;
  for (auto _ : state) {
    physik::SimState s = init_exact;
    double t0 = thread_seconds();
    for (int k = 0; k < kSteps; ++k)
      benchmark::DoNotOptimize(physik::step(exact, s).kinetic_energy);
    t_exact += thread_seconds() - t0;
    s = init_gs;
    t0 = thread_seconds();
    for (int k = 0; k < kSteps; ++k) benchmark::DoNotOptimize(physik::step(gs, s).kinetic_energy);
    t_gs += thread_seconds() - t0;
    s = init_implicit;
    t0 = thread_seconds();
    for (int k = 0; k < kSteps; ++k)
      benchmark::DoNotOptimize(physik::step(implicit, s).kinetic_energy);
    t_implicit += thread_seconds() - t0;
    t_mj += 1e-6 * kSteps * time_mj_step_replay(r);
    steps += kSteps;
  }
  state.counters["exact_us"] = 1e6 * t_exact / steps;
  state.counters["gs_us"] = 1e6 * t_gs / steps;
  state.counters["mj_step_us"] = 1e6 * t_mj / steps;
  state.counters["exact_over_mj_step"] = t_exact / t_mj;
  state.counters["implicit_us"] = 1e6 * t_implicit / steps;
  state.counters["implicit_over_mj_step"] = t_implicit / t_mj;
  state.counters["nbone"] = exact.rig.nbone;
}

BENCHMARK_CAPTURE(BM_ExactVsMjStep, pinhead_two_hands, std::string("pinhead_two_hands"))
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ExactVsMjStep, fig5_running, std::string("fig5_running"))
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Exact, chain, std::string("chain"))
    ->RangeMultiplier(10)
    ->Range(10, 10000)
    ->Arg(30)
    ->Arg(300)
    ->Arg(3000)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Exact, tree2, std::string("tree2"))
    ->RangeMultiplier(10)
    ->Range(10, 10000)
    ->Arg(30)
    ->Arg(300)
    ->Arg(3000)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Implicit, chain, std::string("chain"))
    ->RangeMultiplier(10)
    ->Range(10, 10000)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Implicit, tree2, std::string("tree2"))
    ->RangeMultiplier(10)
    ->Range(10, 10000)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ExactIeee, chain, std::string("chain"))
    ->Arg(100)
    ->Arg(10000)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ImplicitIeee, chain, std::string("chain"))
    ->Arg(100)
    ->Arg(10000)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_MjStep, chain, std::string("chain"))
    ->RangeMultiplier(10)
    ->Range(10, 1000)
    ->Arg(30)
    ->Arg(300)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_MjStep, tree2, std::string("tree2"))
    ->RangeMultiplier(10)
    ->Range(10, 10000)
    ->Arg(30)
    ->Arg(300)
    ->Arg(3000)
    ->Unit(benchmark::kMillisecond);

}  // namespace
