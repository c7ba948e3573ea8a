// PhysIK step cost: microseconds and joint passes per step, heap allocations per step.
// Scenario: pinhead with 8 control points (models/scenes/fig5_running.json when present, else
// the two-hand scene), articulated integration, the paper's settings (dt 0.05, eps 1e-3, k 30)
// with the damping of the preset that converges (the paper's c = 20 diverges on pinhead, and a
// diverging state is not a fair timing). A saved state is restored before every batch so the
// timed steps are always the same first steps of the run (MuJoCo's step_benchmark_test habit).
#include <filesystem>

#include <benchmark/benchmark.h>

#include "bench/alloc_counter.h"
#include "physik/engine/engine.h"
#include "physik/io/scene_io.h"

namespace {

std::string scene_path(const char* name) {
  return std::string(PHYSIK_SOURCE_DIR) + "/models/scenes/" + name;
}

physik::Scene bench_scene(const std::string& integration, const std::string& damping) {
  const std::string running = scene_path("fig5_running.json");
  physik::Scene scene = physik::load_scene(
      std::filesystem::exists(running) ? running : scene_path("pinhead_two_hands.json"));
  scene.params.dt = 0.05;
  scene.params.joint_eps = 1e-3;
  for (auto& cp : scene.control_points) cp.k = 30.0;
  scene.params.damping = damping == "paper" ? 20.0 : 3.0;
  scene.params.scheme = physik::Scheme::kGaussSeidel;
  scene.params.free_rods = integration == "free-rods";
  return scene;
}

void run_steps(benchmark::State& state, const std::string& integration,
               const std::string& damping) {
  const physik::Scene scene = bench_scene(integration, damping);
  physik::SimState initial;
  physik::init_state(scene, initial);
  constexpr int kSteps = 100;  // one batch: the first 100 steps of the run (motion, not rest)
  physik::SimState s = initial;
  long passes = 0, steps = 0, allocs = 0;
  for (auto _ : state) {
    state.PauseTiming();
    s = initial;
    const long a0 = physik::bench::allocations();
    state.ResumeTiming();
    for (int n = 0; n < kSteps; ++n) {
      const physik::StepStats st = physik::step(scene, s);
      passes += st.iterations();
      benchmark::DoNotOptimize(st.kinetic_energy);
    }
    state.PauseTiming();
    allocs += physik::bench::allocations() - a0;
    state.ResumeTiming();
    steps += kSteps;
  }
  state.counters["us_per_step"] = benchmark::Counter(
      static_cast<double>(steps) * 1e-6, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.counters["passes_per_step"] = static_cast<double>(passes) / steps;
  state.counters["allocs_per_step"] = static_cast<double>(allocs) / steps;
  state.counters["control_points"] = static_cast<double>(scene.control_points.size());
  state.SetItemsProcessed(steps);
}

void BM_PhysikStep_Articulated(benchmark::State& state) {
  run_steps(state, "articulated", "original");
}
void BM_PhysikStep_FreeRods(benchmark::State& state) {
  run_steps(state, "free-rods", "original");
}
BENCHMARK(BM_PhysikStep_Articulated)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_PhysikStep_FreeRods)->Unit(benchmark::kMicrosecond);

}  // namespace
