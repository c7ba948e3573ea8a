#include "experiments/report.h"

#include <cctype>
#include <stdexcept>

#include "physik/io/json_fields.h"

namespace physik::experiments {

void check_verdict(const std::string& holds) {
  for (const char* word : {"yes", "no", "partly", "n/a"}) {
    const std::string w = word;
    if (holds == w) return;
    // the word, then " (reason)" closing the cell
    if (holds.size() > w.size() + 3 && holds.compare(0, w.size() + 2, w + " (") == 0 &&
        holds.back() == ')') {
      return;
    }
  }
  throw std::logic_error("report: a claim's verdict '" + holds +
                         "' is not yes, no, partly or n/a (with a reason in parentheses); the "
                         "reason belongs in \"measured\"");
}

Report& Report::section(const std::string& name) {
  section_ = name;
  return *this;
}

Report& Report::claim(const std::string& text, const std::string& measured,
                      const std::string& holds) {
  check_verdict(holds);
  claims_.push_back({{"claim", text}, {"measured", measured}, {"holds", holds}});
  return *this;
}

Report& Report::named(const std::string& name) {
  if (claims_.empty()) throw std::logic_error("report: named('" + name + "') before any claim");
  for (const char ch : name) {
    if (!(std::islower(static_cast<unsigned char>(ch)) ||
          std::isdigit(static_cast<unsigned char>(ch)) || ch == '-')) {
      throw std::logic_error("report: claim name '" + name + "' holds other than a-z, 0-9 and '-'");
    }
  }
  for (const auto& c : claims_) {
    if (c.value("name", "") == name)
      throw std::logic_error("report: two claims named '" + name + "'");
  }
  claims_.back()["name"] = name;
  return *this;
}

Report& Report::note(const std::string& text) {
  notes_.push_back(text);
  return *this;
}

Report& Report::figures(const std::vector<std::string>& files) {
  figures_.insert(figures_.end(), files.begin(), files.end());
  return *this;
}

Report& Report::table(const std::string& title, const std::vector<std::string>& columns,
                      const nlohmann::json& rows) {
  for (const auto& row : rows) {
    if (!row.is_array() || row.size() != columns.size()) {
      throw std::logic_error("report table '" + title + "': a row has " +
                             std::to_string(row.size()) + " cells for " +
                             std::to_string(columns.size()) + " columns");
    }
  }
  tables_.push_back({{"title", title}, {"columns", columns}, {"rows", rows}});
  return *this;
}

Report& Report::settings(const nlohmann::json& settings) {
  settings_ = settings;
  return *this;
}

nlohmann::json Report::to_json() const {
  nlohmann::json j = {{"title", title_}, {"claims", claims_}};
  if (!section_.empty()) j["section"] = section_;
  if (!notes_.empty()) j["notes"] = notes_;
  if (!figures_.empty()) j["figures"] = figures_;
  if (!settings_.is_null()) j["settings"] = settings_;
  if (!tables_.empty()) j["tables"] = tables_;
  return j;
}

void write_summary(const Context& ctx, nlohmann::json doc, const Report& report) {
  doc["report"] = report.to_json();
  write_json(doc, ctx.out_dir + "/summary.json");
}

}  // namespace physik::experiments
