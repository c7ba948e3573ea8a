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
// The same, with `--set` overrides (parse_param_overrides in physik/model/params.h) on top of the
// file's "params"; a preset override swaps the base preset under them. Control points that give
// no spring, k or cap take the params' at use, so they follow the overrides too.
Scene load_scene(const std::string& path, const ParamOverrides& overrides);
// Parse a scene from JSON; relative rig paths resolve against `base_dir`.
Scene scene_from_json(const nlohmann::json& doc, const std::string& source,
                      const std::string& base_dir, const ParamOverrides& overrides = {});
// A scene's "params" object (null: the default preset) by the parameter table: the preset, then
// each row's value, each checked against the row's range; overridden keys are not read.
EngineParams params_from_json(const nlohmann::json& params, const std::string& source,
                              const ParamOverrides& overrides = {});
nlohmann::json params_to_json(const EngineParams& p);
// One value as the scene format writes it: a number, an integer, true/false or the choice's name.
nlohmann::json param_value_json(const ParamRow& row, ParamValue v);
// The scene back to JSON (rig given by its path), e.g. for a tuned scene.
nlohmann::json scene_to_json(const Scene& scene);

}  // namespace physik
