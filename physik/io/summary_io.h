// A run's summary as JSON: the keys of `physik simulate`'s summary.json (README "The command
// line"), shared by every command and experiment that writes one.
#pragma once

#include <nlohmann/json.hpp>

#include "physik/engine/run_summary.h"
#include "physik/model/scene.h"

namespace physik {

nlohmann::json summary_to_json(const Scene& scene, const RunSummary& s);

}  // namespace physik
