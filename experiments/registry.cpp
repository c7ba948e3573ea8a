// The list of experiments, in run order. Each lives in its own file; add one line here.
#include <filesystem>
#include <fstream>

#include "experiments/experiment.h"
#include "physik/errors.h"

namespace physik::experiments {

Experiment rest_poses_experiment();
Experiment ik_comparison_experiment();

const std::vector<Experiment>& all_experiments() {
  static const std::vector<Experiment> list = {
      rest_poses_experiment(),
      ik_comparison_experiment(),
  };
  return list;
}

void write_json_file(const nlohmann::json& doc, const std::string& path) {
  const std::filesystem::path p(path);
  if (p.has_parent_path()) std::filesystem::create_directories(p.parent_path());
  std::ofstream out(p);
  if (!out) throw_input_error(path, "", "", "cannot write file");
  out << doc.dump(2) << "\n";
}

}  // namespace physik::experiments
