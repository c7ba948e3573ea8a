// The "report" section of an experiment's summary.json, which analysis/report.py gathers into
// results/REPORT.md:
//
//   "report": {"title": "...", "section": "...",
//              "claims": [{"claim": "...", "measured": "...", "holds": "yes" | "no" | "partly" |
//              "n/a",
//                          "name": "..." (when named)}],
//              "notes": ["..."], "figures": ["x.png"], "settings": {...},
//              "tables": [{"title": "...", "columns": ["..."], "rows": [[cell, ...]]}]}
//
// title and claims are always written; section, notes, figures, settings and tables only when
// given.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "experiments/experiment.h"

namespace physik::experiments {

// A claim's "holds" cell is a verdict: yes, no, partly or n/a, optionally followed by a short
// reason in parentheses ("no (a run diverged)"); REPORT.md's summary table shows the word alone.
// Throws std::logic_error (an experiment's bug, not a user's input) for anything else, such as a
// sentence where the word belongs ("no: a resting pose that ...").
void check_verdict(const std::string& holds);

class Report {
 public:
  explicit Report(std::string title) : title_(std::move(title)) {}

  Report& section(const std::string& name);
  // One claim row: the claim, what was measured, and whether it holds: a verdict
  // (check_verdict). The reason for a verdict belongs in `measured`.
  Report& claim(const std::string& text, const std::string& measured, const std::string& holds);
  // Names the last claim, so that prose can cite it as claim `experiment/name` (lower case,
  // digits and '-'; unique within the experiment). The doc test checks every citation.
  Report& named(const std::string& name);
  Report& note(const std::string& text);
  Report& figures(const std::vector<std::string>& files);
  // A table report.py renders under the section (markdown); every row has one cell per column.
  Report& table(const std::string& title, const std::vector<std::string>& columns,
                const nlohmann::json& rows);
  // The engine settings the report states (common.h settings_json).
  Report& settings(const nlohmann::json& settings);

  nlohmann::json to_json() const;

 private:
  std::string title_, section_;
  nlohmann::json claims_ = nlohmann::json::array();
  std::vector<std::string> notes_, figures_;
  nlohmann::json settings_;  // null = none
  nlohmann::json tables_ = nlohmann::json::array();
};

// Write <ctx.out_dir>/summary.json: `doc` with the report as its "report" section.
void write_summary(const Context& ctx, nlohmann::json doc, const Report& report);

}  // namespace physik::experiments
