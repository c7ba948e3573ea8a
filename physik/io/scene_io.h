// Scene files: read, validate and write the JSON scene format (models/README.md, "Scenes").
// Every error names the file, the element and the field (physik/model/errors.h).
#pragma once

#include <string>
#include <vector>

#include "physik/io/json_fields.h"
#include "physik/model/scene.h"
#include "physik/posing/solve_options.h"

namespace physik {

// Load and validate a scene file. Errors name the file, the element and the field.
Scene load_scene(const std::string& path);
// The same, with `--set` overrides (parse_param_overrides in physik/model/params.h) on top of the
// file's "params"; a preset override swaps the base preset under them. Control points that give
// no spring, k or cap take the params' at use, so they follow the overrides too.
Scene load_scene(const std::string& path, const ParamOverrides& overrides);
// Parse a scene from JSON; relative rig paths resolve against `base_dir`. "rig" may also be the
// rig object itself (the rig file format; rig_file is then empty).
Scene scene_from_json(const nlohmann::json& doc, const std::string& source,
                      const std::string& base_dir, const ParamOverrides& overrides = {});
// A scene's "params" object (null: the default preset) by the parameter table: the preset, then
// each row's value, each checked against the row's range; overridden keys are not read. A value
// given explicitly (by the file or an override) that the run would not use is refused
// (ParamRow::conflict, judged with `scene`): a damping value beside damping auto, a Gauss-Seidel
// setting under the exact solve, a contact row in a scene without contacts, ... `given_out`
// receives the keys given explicitly.
EngineParams params_from_json(const nlohmann::json& params, const std::string& source,
                              const ParamOverrides& overrides = {},
                              std::vector<std::string>* given_out = nullptr,
                              const ParamScene& scene = {});
nlohmann::json params_to_json(const EngineParams& p);
// The params a run of `scene` reads, each at the value it uses: params_to_json's, and the rows it
// leaves out at their default (ParamRow::written_at_default false: torsion_torque, free_rods, the
// implicit_* rows, the contact rows) wherever the run reads them (a scheme's own rows under that
// scheme, the contact rows in a scene with contacts). The run folder's summary.json and
// scene.json record these "params" (read back, they give the same EngineParams).
nlohmann::json params_as_run_json(const Scene& scene);
// One value as the scene format writes it: a number, an integer, true/false or the choice's name.
nlohmann::json param_value_json(const ParamRow& row, ParamValue v);
// The parameter table for machines (`physik params --json`, physik.param_table(), analysis/
// report.py): {"presets", "default_preset", "params": one object per row (name, kind, unit,
// defaults per preset, valid, doc, choices, range, zero_means, tune)}.
nlohmann::json param_table_json();
// A scene file's "solve" object, by the solve options' table (physik/posing/solve_options.h): the
// options `physik solve` uses where its flags say nothing; defaults where absent. Errors name the
// file, "solve" and the field. The scene reader checks it too (scene_from_json).
SceneSolveOptions solve_options_from_json(const nlohmann::json& solve, const std::string& source);
// The same, from a scene file (the defaults when it has no "solve" object).
SceneSolveOptions load_solve_options(const std::string& scene_path);

// The scene back to JSON (rig given by its path, or inline when it has none or rig_inline), e.g.
// for a tuned scene, or a run folder's scene.json. The rig's path stays as the scene gave it:
// absolute when it was, and relative when it was, then from the folder of `written_to` (the file
// the JSON goes to) to the rig, so that it reads back from there; absolute when `written_to` is
// "" or "-" (no folder to be relative to).
nlohmann::json scene_to_json(const Scene& scene, bool rig_inline = false,
                             const std::string& written_to = "");

}  // namespace physik
