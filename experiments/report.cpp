#include "experiments/report.h"

#include "physik/io/json_fields.h"

namespace physik::experiments {

Report& Report::section(const std::string& name) {
  section_ = name;
  return *this;
}

Report& Report::claim(const std::string& text, const std::string& measured,
                      const std::string& holds) {
  claims_.push_back({{"claim", text}, {"measured", measured}, {"holds", holds}});
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
  return j;
}

void write_summary(const Context& ctx, nlohmann::json doc, const Report& report) {
  doc["report"] = report.to_json();
  write_json(doc, ctx.out_dir + "/summary.json");
}

}  // namespace physik::experiments
