// Scene files: read, validate and write the JSON scene format (models/README.md, "Scenes").
// Every error names the file, the element and the field (physik/model/errors.h).
#pragma once

#include <string>
#include <vector>

#include "physik/io/json_fields.h"
#include "physik/model/scene.h"

namespace physik {

// Load and validate a scene file. Errors name the file, the element and the field.
Scene load_scene(const std::string& path);
// The same, with parameter overrides merged into the file's "params" before it is parsed, so
// control points that take their spring, k and cap from the params see the overrides too. A
// "preset" override swaps the base preset; the file's other params still apply on top of it.
Scene load_scene(const std::string& path, const nlohmann::json& param_overrides);
// "key=value" strings (values parsed as JSON, else taken as a string) into an overrides object;
// unknown keys are an InputError naming `source` (e.g. "--set").
nlohmann::json parse_param_overrides(const std::vector<std::string>& assignments,
                                     const std::string& source);
// Parse a scene from JSON; relative rig paths resolve against `base_dir`. "rig" may also be the
// rig object itself (the rig file format; rig_file is then empty).
Scene scene_from_json(const nlohmann::json& doc, const std::string& source,
                      const std::string& base_dir);
// Apply "params" overrides on top of `base` (shared with the tuner).
EngineParams params_from_json(const nlohmann::json& params, const std::string& source);
nlohmann::json params_to_json(const EngineParams& p);
// The scene back to JSON (rig given by its path, or inline when it has none), e.g. for a tuned
// scene.
nlohmann::json scene_to_json(const Scene& scene);

}  // namespace physik
