#include "physik/io/json_fields.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <sstream>

#include "physik/io/output_files.h"
#include "physik/model/errors.h"
#include "physik/model/names.h"

namespace physik {

void JsonContext::fail(const std::string& field, const std::string& reason) const {
  throw_input_error(file, element, field, reason);
}

const Json& JsonContext::require(const Json& obj, const std::string& key) const {
  if (!obj.is_object()) fail(key, "expected an object holding this field");
  auto it = obj.find(key);
  if (it == obj.end()) fail(key, "missing required field");
  return *it;
}

double JsonContext::number_value(const Json& v, const std::string& field) const {
  if (!v.is_number()) fail(field, "expected a number, got " + std::string(v.type_name()));
  const double d = v.get<double>();
  if (!std::isfinite(d)) fail(field, "not a finite number");
  return d;
}

double JsonContext::number(const Json& obj, const std::string& key) const {
  return number_value(require(obj, key), key);
}

double JsonContext::number_or(const Json& obj, const std::string& key, double fallback) const {
  auto it = obj.find(key);
  if (it == obj.end() || it->is_null()) return fallback;
  return number_value(*it, key);
}

namespace {

// an integer that fits an int, without wrapping (4294967297 is not 1)
int checked_int(const JsonContext& ctx, const Json& v, const std::string& key) {
  if (!v.is_number_integer()) ctx.fail(key, "expected an integer");
  if (v.is_number_unsigned()) {
    if (v.get<unsigned long long>() >
        static_cast<unsigned long long>(std::numeric_limits<int>::max())) {
      ctx.fail(key, "integer out of range");
    }
    return static_cast<int>(v.get<unsigned long long>());
  }
  const long long x = v.get<long long>();
  if (x < std::numeric_limits<int>::min() || x > std::numeric_limits<int>::max()) {
    ctx.fail(key, "integer out of range");
  }
  return static_cast<int>(x);
}

}  // namespace

int JsonContext::integer(const Json& obj, const std::string& key) const {
  return checked_int(*this, require(obj, key), key);
}

int JsonContext::integer_or(const Json& obj, const std::string& key, int fallback) const {
  auto it = obj.find(key);
  if (it == obj.end() || it->is_null()) return fallback;
  return checked_int(*this, *it, key);
}

bool JsonContext::boolean_or(const Json& obj, const std::string& key, bool fallback) const {
  auto it = obj.find(key);
  if (it == obj.end() || it->is_null()) return fallback;
  if (!it->is_boolean()) fail(key, "expected true or false");
  return it->get<bool>();
}

std::string JsonContext::string(const Json& obj, const std::string& key) const {
  const Json& v = require(obj, key);
  if (!v.is_string()) fail(key, "expected a string, got " + std::string(v.type_name()));
  return v.get<std::string>();
}

std::string JsonContext::string_or(const Json& obj, const std::string& key,
                                   const std::string& fallback) const {
  auto it = obj.find(key);
  if (it == obj.end() || it->is_null()) return fallback;
  if (!it->is_string()) fail(key, "expected a string, got " + std::string(it->type_name()));
  return it->get<std::string>();
}

void JsonContext::check_name(const std::string& text, const std::string& field) const {
  const std::string bad = name_problem(text);
  if (!bad.empty()) fail(field, bad);
}

std::string JsonContext::name(const Json& obj, const std::string& key) const {
  std::string text = string(obj, key);
  check_name(text, key);
  return text;
}

std::string JsonContext::name_or(const Json& obj, const std::string& key,
                                 const std::string& fallback) const {
  std::string text = string_or(obj, key, fallback);
  check_name(text, key);
  return text;
}

std::string JsonContext::choice_or(const Json& obj, const std::string& key,
                                   std::initializer_list<const char*> choices,
                                   const std::string& fallback) const {
  return choice_or(obj, key, std::vector<std::string>(choices.begin(), choices.end()), fallback);
}

std::string JsonContext::choice_or(const Json& obj, const std::string& key,
                                   const std::vector<std::string>& choices,
                                   const std::string& fallback) const {
  const std::string v = string_or(obj, key, fallback);
  std::string all;
  for (const std::string& c : choices) {
    if (v == c) return v;
    all += (all.empty() ? "" : "|") + c;
  }
  fail(key, "unknown value '" + v + "' (expected " + all + ")");
}

Vec3 JsonContext::vec3_value(const Json& v, const std::string& field) const {
  if (!v.is_array() || v.size() != 3) fail(field, "expected an array of 3 numbers");
  Vec3 out;
  for (int k = 0; k < 3; ++k) {
    out[k] = number_value(v[k], field + "[" + std::to_string(k) + "]");
  }
  return out;
}

Vec3 JsonContext::vec3(const Json& obj, const std::string& key) const {
  return vec3_value(require(obj, key), key);
}

void JsonContext::only_keys(const Json& obj, std::initializer_list<const char*> known) const {
  only_keys(obj, std::vector<std::string>(known.begin(), known.end()));
}

void JsonContext::only_keys(const Json& obj, const std::vector<std::string>& known) const {
  for (auto it = obj.begin(); it != obj.end(); ++it) {
    bool ok = false;
    for (const std::string& k : known) ok = ok || it.key() == k;
    if (!ok) {
      std::string all;
      for (const std::string& k : known) all += (all.empty() ? "" : ", ") + k;
      fail(it.key(), "unknown field (known fields: " + all + ")");
    }
  }
}

void JsonContext::require_object(const Json& obj, const std::string& field) const {
  if (!obj.is_object()) fail(field, "expected a JSON object");
}

namespace {

// Rejects nesting deeper than kMaxJsonDepth before nlohmann parses: its parser is iterative, but
// copying, comparing and dumping a value recurse once per level, so a 200,000-deep array would
// overflow the stack later. Brackets inside strings do not count; a malformed document is left
// to the parser's own message.
void check_json_depth(const std::string& text, const std::string& source) {
  int depth = 0, line = 1;
  bool in_string = false, escaped = false;
  for (const char c : text) {
    if (c == '\n') ++line;
    if (in_string) {
      if (escaped) {
        escaped = false;
      } else if (c == '\\') {
        escaped = true;
      } else if (c == '"') {
        in_string = false;
      }
      continue;
    }
    if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxJsonDepth) {
        throw_input_error(source, "line " + std::to_string(line), "",
                          "JSON nested deeper than " + std::to_string(kMaxJsonDepth) +
                              " levels (json_fields.h kMaxJsonDepth)");
      }
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
}

}  // namespace

Json parse_json_text(const std::string& text, const std::string& source) {
  check_json_depth(text, source);
  try {
    return Json::parse(text);
  } catch (const Json::parse_error& e) {
    // nlohmann's message carries "line L, column C" for syntax errors (NaN, Infinity, ...)
    std::string what = e.what();
    const std::string tag = "parse error";
    auto pos = what.find(tag);
    throw_input_error(source, "", "",
                      "invalid JSON: " + (pos == std::string::npos ? what : what.substr(pos)));
  } catch (const Json::exception& e) {
    // e.g. a number literal that overflows a double (1e999): not a finite number
    std::string what = e.what();
    auto pos = what.find("] ");
    throw_input_error(source, "", "",
                      "invalid JSON: " + (pos == std::string::npos ? what : what.substr(pos + 2)));
  }
}

Json read_json_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw_input_error(path, "", "", "cannot open file");
  std::stringstream buf;
  buf << in.rdbuf();
  return parse_json_text(buf.str(), path);
}

void write_json(const Json& doc, const std::string& path) {
  if (path.empty() || path == "-") {
    std::cout << doc.dump(2) << "\n";
    return;
  }
  std::ofstream out = open_output_file(path, "");
  out << doc.dump(2) << "\n";
}

}  // namespace physik
