// The scene readers of scene_io.h with what they changed of a value the file gives, rather than
// refused: a quaternion within 1e-3 of unit, normalised (physik/model/bone_targets.h
// target_quaternion). Each message is appended to `warnings` and names the file, the element and
// the field; the command line prints each once as "physik: warning: ...", Python issues an
// InputWarning. The readers of scene_io.h drop them.
#pragma once

#include <string>
#include <vector>

#include "physik/io/scene_io.h"

namespace physik {

Scene load_scene(const std::string& path, const ParamOverrides& overrides,
                 std::vector<std::string>& warnings);
Scene scene_from_json(const nlohmann::json& doc, const std::string& source,
                      const std::string& base_dir, const ParamOverrides& overrides,
                      std::vector<std::string>& warnings);

}  // namespace physik
