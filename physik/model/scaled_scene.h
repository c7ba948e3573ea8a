// A scene on a scaled rig: the tuning study's 0.1x / 10x rigs (experiments/tuning_study.cpp),
// beyond_the_paper's scaled-rig sweep, and the engine tests that need a small rig.
#pragma once

#include <optional>

#include "physik/model/scene.h"

namespace physik {

// The scene on its rig scaled by s about the origin (heads, tails, radii, targets, the points'
// own caps and params.control_cap, the schedule's targets, the root's start), every bone's mass
// density x length (kg per rig unit; no density: the masses kept) and its inertia recomputed (the
// cylinder's); torsion k scaled like the inertia (density x s^3, density 1 if none) when asked. k
// and dt stay as given. The rig is built by build_rig, so the scaled rig is checked as a loaded one
// is.
Scene scaled_scene(const Scene& base, double s, std::optional<double> density,
                   bool scale_torsion = false);

}  // namespace physik
