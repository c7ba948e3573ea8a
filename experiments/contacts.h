// What the contacts experiment's studies share (experiments/contacts.cpp runs them: drop and
// hand there, coil in contacts_coil.cpp, sit in contacts_sit.cpp, cannon in contacts_cannon.cpp).
// Each study runs its scenes, adds its claims to the report and returns its summary's part.
// Units: rig units; penetrations are fractions of the thinner touching capsule's radius.
#pragma once

#include <nlohmann/json.hpp>

#include "experiments/experiment.h"
#include "experiments/report.h"
#include "physik/model/kinematics.h"
#include "physik/model/scene.h"

namespace physik::experiments::contacts_study {

// An experiment scene must start at rest against its ground and obstacles (start_contacts.h);
// std::runtime_error naming the scene otherwise. Returns the scene.
const Scene& checked_start(const Scene& scene);

// The deepest overlap of a pose, as a fraction of the thinner touching capsule's radius.
double penetration_fraction(const Scene& scene, const BoneFrames& frames);

// The studies: "coil", "coil_laid", "coil_static_friction"; the sit's; the cannon's.
nlohmann::json coil_section(const Context& ctx, Report& report);
nlohmann::json sit_section(const Context& ctx, Report& report);
nlohmann::json cannon_section(const Context& ctx, Report& report);

}  // namespace physik::experiments::contacts_study
