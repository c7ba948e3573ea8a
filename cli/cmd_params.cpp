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

constexpr std::size_t kWidth = 100;  // columns of the terminal table

// `text` wrapped into lines of at most kWidth columns, each starting with `indent`
std::string wrapped(const std::string& text, const std::string& indent) {
  std::istringstream words(text);
  std::string word, line, out;
  while (words >> word) {
    if (!line.empty() && indent.size() + line.size() + 1 + word.size() > kWidth) {
      out += indent + line + "\n";
      line.clear();
    }
    line += (line.empty() ? "" : " ") + word;
  }
  if (!line.empty()) out += indent + line + "\n";
  return out;
}

// a readable table within kWidth columns: per parameter, a line with its key, unit and the
// presets' values (or one preset's), then its doc, valid values and tuning bounds, indented
std::string table_text(int only_preset) {
  std::vector<std::vector<std::string>> heads = {{"key", "unit"}};
  for (int i = 0; i < kPresetCount; ++i) {
    if (only_preset < 0 || i == only_preset) heads[0].push_back(kPresetNames[i]);
  }
  for (const ParamRow& r : param_table()) {
    std::vector<std::string> line = {r.name, r.unit.empty() ? "-" : r.unit};
    for (int i = 0; i < kPresetCount; ++i) {
      if (only_preset >= 0 && i != only_preset) continue;
      // damping auto is a preset's damping: say so where the value would be
      const bool is_auto = r.name == "damping" && param_row("damping_auto").defaults[i] != 0.0;
      line.push_back(is_auto ? "auto" : format_param(r, r.defaults[i]));
    }
    heads.push_back(line);
  }
  std::vector<std::size_t> width(heads[0].size(), 0);
  for (const auto& line : heads) {
    for (std::size_t c = 0; c < line.size(); ++c) width[c] = std::max(width[c], line[c].size());
  }
  std::ostringstream o;
  for (std::size_t k = 0; k < heads.size(); ++k) {
    const auto& line = heads[k];
    for (std::size_t c = 0; c + 1 < line.size(); ++c)
      o << std::left << std::setw(width[c] + 2) << line[c];
    o << line.back() << "\n";
    if (k == 0) continue;
    const ParamRow& r = param_table()[k - 1];
    std::ostringstream more;
    more << r.doc << ". Valid: " << valid_text(r)
         << (r.zero_means.empty() ? "" : " (0 = " + r.zero_means + ")") << ".";
    if (r.tune) more << " Tuned within " << r.tune->first << ".." << r.tune->second << ".";
    o << wrapped(more.str(), "    ");
  }
  return o.str();
}

}  // namespace

void add_params_commands(CLI::App& app) {
  auto opt = std::make_shared<ParamsOptions>();
  auto* cmd = app.add_subcommand(
      "params",
      "List the engine parameters (a scene's \"params\" keys and --set keys): unit, default per "
      "preset (a scene that names none gets " +
          std::string(kDefaultPreset) +
          "), valid values, "
          "tuning bounds (tune --params) and what each does, within 100 columns.");
  cmd->add_flag(
      "--json", opt->json,
      "JSON for machines: {presets, default_preset, params: [{name, kind, unit, defaults, "
      "valid, tune, doc, ...}]}; with --preset, that preset's \"params\" object");
  cmd->add_option("--preset", opt->preset, "Show one preset's values only (original|paper|robust)");
  cmd->callback([opt] {
    const int only = opt->preset.empty() ? -1 : preset_index(opt->preset);
    if (!opt->preset.empty()) preset_params(opt->preset, "--preset");  // unknown: exit 2
    if (opt->json) {
      write_json(only < 0 ? param_table_json() : params_to_json(preset_params(opt->preset)), "-");
    } else {
      std::cout << table_text(only);
    }
  });
}

}  // namespace physik::cli
