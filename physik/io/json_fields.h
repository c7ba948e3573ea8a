// Typed, validated access to fields of a parsed JSON document. Every failure throws InputError
// naming the file, the element (e.g. "bones[3] 'forearm.L'") and the field.
// Shared by every file format in the core (rigs, scenes, limit files).
#pragma once

#include <initializer_list>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "physik/model/types.h"

namespace physik {

using Json = nlohmann::json;

// Where a JSON object came from, for error messages.
struct JsonContext {
  std::string file;     // path as given by the user
  std::string element;  // e.g. "bones[2] 'torso'" or "control_points[0]"

  [[noreturn]] void fail(const std::string& field, const std::string& reason) const;

  const Json& require(const Json& obj, const std::string& key) const;
  double number(const Json& obj, const std::string& key) const;  // finite number
  double number_or(const Json& obj, const std::string& key, double fallback) const;
  int integer(const Json& obj, const std::string& key) const;
  int integer_or(const Json& obj, const std::string& key, int fallback) const;
  bool boolean_or(const Json& obj, const std::string& key, bool fallback) const;
  std::string string(const Json& obj, const std::string& key) const;
  std::string string_or(const Json& obj, const std::string& key, const std::string& fallback) const;
  // A name (a bone, a control point, an obstacle, a rig or a scene, or a reference to one): a
  // string of valid UTF-8 without control characters (physik/model/names.h). The reason names the
  // offending byte and its offset, never the name itself.
  std::string name(const Json& obj, const std::string& key) const;
  std::string name_or(const Json& obj, const std::string& key, const std::string& fallback) const;
  // `text` (a name read as a key or an array element) checked the same way, `field` named
  void check_name(const std::string& text, const std::string& field) const;
  // one of `choices`
  std::string choice_or(const Json& obj, const std::string& key,
                        std::initializer_list<const char*> choices,
                        const std::string& fallback) const;
  std::string choice_or(const Json& obj, const std::string& key,
                        const std::vector<std::string>& choices, const std::string& fallback) const;
  Vec3 vec3(const Json& obj, const std::string& key) const;
  Vec3 vec3_value(const Json& value, const std::string& field) const;
  double number_value(const Json& value, const std::string& field) const;
  // fails on any key of `obj` that is not in `known`
  void only_keys(const Json& obj, std::initializer_list<const char*> known) const;
  void only_keys(const Json& obj, const std::vector<std::string>& known) const;
  void require_object(const Json& obj, const std::string& field) const;
};

// Deepest nesting of arrays and objects a JSON input may have (the formats need 4).
constexpr int kMaxJsonDepth = 256;

// Read and parse a JSON file; a missing file, a syntax error or nesting deeper than
// kMaxJsonDepth is an InputError naming the file (and the line).
Json read_json_file(const std::string& path);
Json parse_json_text(const std::string& text, const std::string& source);
// Write a JSON document pretty-printed (2 spaces, a final newline): to a file, created with its
// parent folders (InputError naming it if it cannot be written), or to stdout for "-" or "".
void write_json(const Json& doc, const std::string& path);

}  // namespace physik
