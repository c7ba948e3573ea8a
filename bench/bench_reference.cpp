// PhysIK's step beside MuJoCo's mj_step on the equivalent model, in one binary and one
// run. Each benchmark iteration restores the same initial state and times, in thread CPU time
// (other processes on a shared machine do not count), per step over the first kSteps steps of the
// scene (motion, not rest):
//   physik_us     PhysIK's step() (the scene's integration, Gauss-Seidel joint forces)
//   mj_step_us    mj_step on the MJCF of the same rig, replaying the applied forces
//                 (xfrc_applied) recorded from a reference run, so it follows the same trajectory:
//                 MuJoCo's own cost for the equivalent model, without PhysIK's force stages
//   reference_us  the whole reference step: PhysIK's force stages on MuJoCo's state +
//                 mj_step2 + mj_step1 (reference/mujoco_runner.h)
// and the ratio
//   physik_over_mj_step = physik_us / mj_step_us.
// Scenes: pinhead with two hand targets and the Fig 5 running pose (8 control points).
// The entry point is bench/bench_main.cpp (no main here).
#include <algorithm>
#include <ctime>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "physik/engine/engine.h"
#include "physik/io/scene_io.h"
#include "reference/mujoco_runner.h"

namespace {

constexpr int kSteps = 100;

std::string scene_file(const std::string& name) {
#ifdef PHYSIK_SOURCE_DIR
  return std::string(PHYSIK_SOURCE_DIR) + "/models/scenes/" + name + ".json";
#else
  return "models/scenes/" + name + ".json";
#endif
}

// CPU time of this thread, s
double thread_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

double seconds_since(double t0) {
  return thread_seconds() - t0;
}

void BM_PhysikVsMujoco(benchmark::State& state, const std::string& name,
                       physik::ReferenceMode mode) {
  const physik::Scene scene = physik::load_scene(scene_file(name));
  physik::SimState initial;
  physik::init_state(scene, initial);
  physik::MujocoReference ref(scene, mode);
  const mjModel* m = ref.model();
  // the applied forces of every step of one reference run, replayed into plain mj_step
  physik::MjDataPtr start(mj_makeData(m));
  mj_copyData(start.get(), m, ref.data());
  std::vector<std::vector<mjtNum>> xfrc(kSteps);
  for (int k = 0; k < kSteps; ++k) {
    ref.step();
    xfrc[k].assign(ref.data()->xfrc_applied, ref.data()->xfrc_applied + 6 * m->nbody);
  }
  physik::MjDataPtr d(mj_makeData(m));

  double t_physik = 0.0, t_mj = 0.0, t_ref = 0.0;
  long steps = 0;
  for (auto _ : state) {
    physik::SimState s = initial;
    double t0 = thread_seconds();
    for (int k = 0; k < kSteps; ++k)
      benchmark::DoNotOptimize(physik::step(scene, s).kinetic_energy);
    t_physik += seconds_since(t0);

    mj_copyData(d.get(), m, start.get());
    t0 = thread_seconds();
    for (int k = 0; k < kSteps; ++k) {
      std::copy(xfrc[k].begin(), xfrc[k].end(), d->xfrc_applied);
      mj_step(m, d.get());
    }
    benchmark::DoNotOptimize(d->qpos[0]);
    t_mj += seconds_since(t0);

    ref.reset();
    t0 = thread_seconds();
    for (int k = 0; k < kSteps; ++k) benchmark::DoNotOptimize(ref.step().kinetic_energy);
    t_ref += seconds_since(t0);
    steps += kSteps;
  }
  state.counters["physik_us"] = 1e6 * t_physik / steps;
  state.counters["mj_step_us"] = 1e6 * t_mj / steps;
  state.counters["reference_us"] = 1e6 * t_ref / steps;
  state.counters["physik_over_mj_step"] = t_physik / t_mj;
  state.counters["nbone"] = scene.rig.nbone;
  state.counters["nv"] = m->nv;
}

BENCHMARK_CAPTURE(BM_PhysikVsMujoco, pinhead_two_hands_same_forces,
                  std::string("pinhead_two_hands"), physik::ReferenceMode::kSameForces)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_PhysikVsMujoco, pinhead_two_hands_exact, std::string("pinhead_two_hands"),
                  physik::ReferenceMode::kExactConstraints)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_PhysikVsMujoco, fig5_running_same_forces, std::string("fig5_running"),
                  physik::ReferenceMode::kSameForces)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_PhysikVsMujoco, fig5_running_exact, std::string("fig5_running"),
                  physik::ReferenceMode::kExactConstraints)
    ->Unit(benchmark::kMillisecond);

}  // namespace
