// Scenes of the contacts experiment (experiments/contacts.cpp) that the benchmarks
// (bench/bench_contacts.cpp) time as well, so that both run the same scene.
// Units: rig units, kg, s, N/m.
#pragma once

#include <string>

#include "physik/model/scene.h"

namespace physik::experiments {

// pinhead (models_dir/rigs/pinhead.json) with its torso held at its rest head and tail by two
// springs of 300 N/m, the left hand's tip pulled by a spring of 30 N/m to x = -1, to the right
// of the torso (through it); with or without self-collision, no ground, no gravity; the robust
// preset at dt 0.05 s with damping 3 N s/m, `steps` steps.
Scene contacts_hand_scene(const std::string& models_dir, bool self_collision, int steps);

}  // namespace physik::experiments
