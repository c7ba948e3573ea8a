// physik params: the engine parameter table (physik/model/params.h): every scene "params" key
// with its kind, unit, default per preset, valid values, tuning bounds and doc line.
#include <algorithm>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>
#include <vector>

#include "cli/commands.h"
#include "physik/io/scene_io.h"
#include "physik/model/errors.h"
#include "physik/model/params.h"

namespace physik::cli {

namespace {

struct ParamsOptions {
  bool json = false;
  std::string preset;  // "" = every preset
};

// the table for machines (analysis/report.py reads it): one object per row
nlohmann::json table_json() {
  nlohmann::json rows = nlohmann::json::array();
  for (const ParamRow& r : param_table()) {
    nlohmann::json defaults = nlohmann::json::object();
    for (int i = 0; i < kPresetCount; ++i) defaults[kPresetNames[i]] = param_value_json(r, r.defaults[i]);
    nlohmann::json row = {{"name", r.name},
                          {"kind", to_string(r.kind)},
                          {"unit", r.unit},
                          {"defaults", defaults},
                          {"valid", valid_text(r)},
                          {"doc", r.doc}};
    if (!r.choices.empty()) row["choices"] = r.choices;
    if (r.valid.lo) row["range"].update({{"lo", *r.valid.lo}, {"lo_allowed", r.valid.lo_allowed}});
    if (r.valid.hi) row["range"].update({{"hi", *r.valid.hi}, {"hi_allowed", r.valid.hi_allowed}});
    if (!r.zero_means.empty()) row["zero_means"] = r.zero_means;
    row["tune"] = r.tune ? nlohmann::json{r.tune->first, r.tune->second} : nlohmann::json(nullptr);
    rows.push_back(row);
  }
  return {{"presets", kPresetNames}, {"default_preset", kDefaultPreset}, {"params", rows}};
}

// a readable table: one line per parameter, the presets' values (or one preset's) as columns
std::string table_text(int only_preset) {
  std::vector<std::vector<std::string>> lines = {{"key", "kind", "unit"}};
  for (int i = 0; i < kPresetCount; ++i) {
    if (only_preset < 0 || i == only_preset) lines[0].push_back(kPresetNames[i]);
  }
  for (const char* h : {"valid", "tune", "doc"}) lines[0].push_back(h);
  for (const ParamRow& r : param_table()) {
    std::vector<std::string> line = {r.name, to_string(r.kind), r.unit};
    for (int i = 0; i < kPresetCount; ++i) {
      if (only_preset < 0 || i == only_preset) line.push_back(format_param(r, r.defaults[i]));
    }
    line.push_back(valid_text(r) + (r.zero_means.empty() ? "" : " (0 = " + r.zero_means + ")"));
    std::ostringstream tune;
    if (r.tune) tune << r.tune->first << ".." << r.tune->second;
    line.push_back(tune.str());
    line.push_back(r.doc);
    lines.push_back(line);
  }
  std::vector<std::size_t> width(lines[0].size(), 0);
  for (const auto& line : lines) {
    for (std::size_t c = 0; c < line.size(); ++c) width[c] = std::max(width[c], line[c].size());
  }
  std::ostringstream o;
  for (const auto& line : lines) {
    for (std::size_t c = 0; c + 1 < line.size(); ++c) o << std::left << std::setw(width[c] + 2) << line[c];
    o << line.back() << "\n";
  }
  return o.str();
}

}  // namespace

void add_params_commands(CLI::App& app) {
  auto opt = std::make_shared<ParamsOptions>();
  auto* cmd = app.add_subcommand(
      "params",
      "List the engine parameters (a scene's \"params\" keys and simulate's --set keys): kind, "
      "unit, default per preset, valid values, tuning bounds (tune --params) and what each does.");
  cmd->add_flag("--json", opt->json,
                "JSON for machines: {presets, default_preset, params: [{name, kind, unit, defaults, "
                "valid, tune, doc, ...}]}; with --preset, that preset's \"params\" object");
  cmd->add_option("--preset", opt->preset, "Show one preset's values only (original|paper)");
  cmd->callback([opt] {
    const int only = opt->preset.empty() ? -1 : preset_index(opt->preset);
    if (!opt->preset.empty()) preset_params(opt->preset, "--preset");  // unknown: exit 2
    if (opt->json) {
      write_json(only < 0 ? table_json() : params_to_json(preset_params(opt->preset)), "-");
    } else {
      std::cout << table_text(only);
    }
  });
}

}  // namespace physik::cli
