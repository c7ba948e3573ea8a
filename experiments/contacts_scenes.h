// Scenes of the contacts experiments (experiments/contacts.cpp, experiments/contacts_cost.cpp)
// that the benchmarks (bench/bench_contacts.cpp) time as well, and the timed loop both use, so
// that the report and the benchmarks time the same runs.
// Units: rig units, kg, s, N/m; times are the calling thread's CPU time (scaling.h).
#pragma once

#include <string>

#include "physik/engine/state.h"
#include "physik/model/kinematics.h"
#include "physik/model/scene.h"

namespace physik::experiments {

// The lowest point of bone b's capsule at these frames (its lower end's z minus its collision
// radius), and of every bone's: where a floor under the pose (z up) touches it. Rig units.
double capsule_bottom(const Rig& rig, const BoneFrames& frames, int bone);
double lowest_capsule_point(const Rig& rig, const BoneFrames& frames);

// pinhead (models_dir/rigs/pinhead.json) with its torso held at its rest head and tail by two
// springs of 300 N/m, the left hand's tip pulled by a spring of 30 N/m to x = -1, to the right
// of the torso (through it); with or without self-collision, no ground, no gravity; the robust
// preset at dt 0.05 s with damping 3 N s/m, `steps` steps.
Scene contacts_hand_scene(const std::string& models_dir, bool self_collision, int steps);

// The hand scene (300 steps) under gravity (9.81 down), with the floor at the rest pose's lowest
// point and self-collision (`contacts`), or with neither: the step-cost scene of the issue's
// pinhead target. Over the run the feet and the shins' lower ends come onto the floor, the left
// upper arm onto the torso and the right forearm onto the right thigh.
Scene contacts_cost_pinhead_scene(const std::string& models_dir, bool contacts);

// Timed steps: their thread CPU time (s), the energy guard's substeps, and whether every step's
// kinetic energy stayed finite.
struct TimedSteps {
  double seconds = 0.0;
  long substeps = 0;
  bool finite = true;
};

// Take `steps` steps of `state` (as the caller left it: from init_state, for a run from the
// start), adding their time and substeps to `out`.
void time_steps(const Scene& scene, SimState& state, int steps, TimedSteps& out);

}  // namespace physik::experiments
