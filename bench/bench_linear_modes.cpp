// damping auto's cost: update_auto_damping (physik/engine/linear_modes.h, the iterative path
// with its workspace kept in the state, as the engine calls it) against the dense reference
// (linear_modes_dense.h) where that is affordable, in thread CPU time per call.
//   BM_DampingAuto/chain or tree2/N   the scaling scenario (experiments/scaling.h: one capped
//                                     spring at the last tail), at the start pose
//   BM_DampingAutoScene/<scene>       a shipped scene at its start pose
//   BM_DenseModes/...                 the same with the dense path (O(n^3))
// Counters: ms per call; the Lanczos steps, runs and counts of the last call; walked = 1 when
// the answer came from the count-driven walk (linear_modes.h, "Certificate").
// Targets: 10,000-bone chain <= 50 ms; pinhead <= the dense path's time.
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "experiments/scaling.h"
#include "physik/engine/engine.h"
#include "physik/engine/linear_modes.h"
#include "physik/engine/linear_modes_dense.h"
#include "physik/io/scene_io.h"

namespace {

using physik::experiments::thread_seconds;

std::vector<physik::Vec3> at_points(const physik::Scene& scene, const physik::SimState& s) {
  std::vector<physik::Vec3> t;
  for (const physik::ControlPoint& cp : scene.control_points) {
    t.push_back(physik::point_on_bone(s.frames, cp.bone, cp.alpha));
  }
  return t;
}

void time_iterative(benchmark::State& state, const physik::Scene& scene) {
  physik::SimState s;
  physik::init_state(scene, s);
  const std::vector<physik::Vec3> targets = at_points(scene, s);
  physik::LinearModes last;
  double t = 0.0;
  long n = 0;
  for (auto _ : state) {
    const double t0 = thread_seconds();
    last = physik::linear_modes(scene, s, targets, s.modes);
    t += thread_seconds() - t0;
    ++n;
  }
  benchmark::DoNotOptimize(last.critical_damping);
  state.counters["ms"] = 1e3 * t / n;
  state.counters["lanczos_steps"] = last.iterations;
  state.counters["runs"] = last.runs;
  state.counters["counts"] = last.counts;
  state.counters["walked"] = last.walked ? 1 : 0;
  state.counters["nbone"] = scene.rig.nbone;
  state.counters["c"] = last.critical_damping;
}

void time_dense(benchmark::State& state, const physik::Scene& scene) {
  physik::SimState s;
  physik::init_state(scene, s);
  const std::vector<physik::Vec3> targets = at_points(scene, s);
  double t = 0.0, c = 0.0;
  long n = 0;
  for (auto _ : state) {
    const double t0 = thread_seconds();
    c = physik::linear_modes_dense(scene, s, targets).modes.critical_damping;
    t += thread_seconds() - t0;
    ++n;
  }
  state.counters["ms"] = 1e3 * t / n;
  state.counters["nbone"] = scene.rig.nbone;
  state.counters["c"] = c;
}

physik::Scene shipped(const std::string& name) {
  return physik::load_scene(std::string(PHYSIK_SOURCE_DIR) + "/models/scenes/" + name + ".json");
}

void BM_DampingAuto(benchmark::State& state, const std::string& kind) {
  time_iterative(state, physik::experiments::scaling_scene(kind, static_cast<int>(state.range(0))));
}
void BM_DenseModes(benchmark::State& state, const std::string& kind) {
  time_dense(state, physik::experiments::scaling_scene(kind, static_cast<int>(state.range(0))));
}
void BM_DampingAutoScene(benchmark::State& state, const std::string& name) {
  time_iterative(state, shipped(name));
}
void BM_DenseModesScene(benchmark::State& state, const std::string& name) {
  time_dense(state, shipped(name));
}

BENCHMARK_CAPTURE(BM_DampingAuto, chain, std::string("chain"))
    ->Arg(100)
    ->Arg(437)
    ->Arg(1000)
    ->Arg(10000)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_DampingAuto, tree2, std::string("tree2"))
    ->Arg(437)
    ->Arg(10000)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_DenseModes, chain, std::string("chain"))
    ->Arg(100)
    ->Arg(437)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_DampingAutoScene, pinhead_two_hands, std::string("pinhead_two_hands"))
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_DenseModesScene, pinhead_two_hands, std::string("pinhead_two_hands"))
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_DampingAutoScene, fig5_running, std::string("fig5_running"))
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_DenseModesScene, fig5_running, std::string("fig5_running"))
    ->Unit(benchmark::kMillisecond);

}  // namespace
