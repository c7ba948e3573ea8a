// physik_count: the stepping that `make bench-count` counts with callgrind (bench/bench_count.py).
// One scaling scenario (experiments/scaling.h: a straight chain or a balanced binary tree of N
// bones from rest, pulled at its last tail by one capped control spring, the `original` preset)
// in the chosen scheme is set up (rig, scene, init_state), then `--steps` calls of physik::step
// run inside count_stepping_loop, the one function the count collects
// (valgrind --tool=callgrind --toggle-collect='count_stepping_loop*'): the program's start, the
// rig, the scene and init_state are outside it and never counted; every step's whole step()
// (targets, forces, the solve, the integrator, the step's measures) is inside.
// Prints one JSON object on stdout: rig, bones, scheme, steps, the substeps or joint passes the
// steps took, the final kinetic energy (J) and final_state_hash (as a run's summary.json), so two
// counts of the same run can be seen to be the same run.
// Exit status: 0 success, 2 bad input (the option and the reason on stderr), 3 a diverged run
// (a kinetic energy that is not finite).
#include <algorithm>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <exception>
#include <iostream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "bench/tool_main.h"
#include "experiments/scaling.h"
#include "physik/engine/engine.h"
#include "physik/model/errors.h"

namespace {

struct LoopResult {
  long iterations = 0;  // substeps (implicit) or joint passes (exact: 1 a step; gauss-seidel)
  double kinetic_energy = 0.0;
};

}  // namespace

// the counted loop: kept out of line (and out of any namespace, so that its name is the pattern
// the count matches), nothing but the steps in it
__attribute__((noinline)) LoopResult count_stepping_loop(const physik::Scene& scene,
                                                         physik::SimState& state, int steps) {
  LoopResult r;
  for (int k = 0; k < steps; ++k) {
    const physik::StepStats st = physik::step(scene, state);
    r.iterations += st.iterations();
    r.kinetic_energy = st.kinetic_energy;
  }
  return r;
}

namespace {

// the scheme of a name of choice_names(Scheme) (checked by the option)
physik::Scheme scheme_named(const std::string& name) {
  const std::vector<std::string>& names = physik::choice_names(physik::Scheme{});
  const auto at = std::find(names.begin(), names.end(), name);
  return static_cast<physik::Scheme>(at - names.begin());
}

int run(const std::string& kind, int bones, const std::string& scheme_name, int steps) {
  physik::Scene scene = physik::experiments::scaling_scene(kind, bones, scheme_named(scheme_name));
  physik::SimState state;
  physik::init_state(scene, state);
  const LoopResult r = count_stepping_loop(scene, state, steps);
  std::printf(
      "{\"rig\": \"%s\", \"bones\": %d, \"scheme\": \"%s\", \"steps\": %d, \"iterations\": %ld, "
      "\"final_kinetic_energy\": %.17g, \"final_state_hash\": \"%016" PRIx64 "\"}\n",
      kind.c_str(), bones, scheme_name.c_str(), steps, r.iterations,
      std::isfinite(r.kinetic_energy) ? r.kinetic_energy : -1.0,
      static_cast<std::uint64_t>(physik::state_hash(state.frames)));
  if (!std::isfinite(r.kinetic_energy)) {
    std::cerr << "physik_count: the run diverged (kinetic energy " << r.kinetic_energy << ")\n";
    return physik::kExitDiverged;
  }
  return physik::kExitOk;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "physik_count: set up a scaling scenario, then run its steps in count_stepping_loop, the "
      "function `make bench-count` counts with callgrind (bench/bench_count.py)."};
  std::string kind = "chain", scheme = "exact";
  int bones = 1000, steps = 100;
  app.add_option("--rig", kind, "chain or tree2 (a balanced binary tree)")
      ->check(CLI::IsMember({"chain", "tree2"}));
  app.add_option("--bones", bones, "bones N")->check(CLI::Range(1, 1000000));
  app.add_option("--scheme", scheme, "gauss-seidel, exact or implicit")
      ->check(CLI::IsMember(physik::choice_names(physik::Scheme{})));
  app.add_option("--steps", steps, "steps counted")->check(CLI::Range(1, 1000000));
  app.footer("Exit status: 0 success, 1 an unexpected failure, 2 bad input, 3 a diverged run.");
  return physik::bench::tool_main("physik_count", app, argc, argv,
                                  [&] { return run(kind, bones, scheme, steps); });
}
