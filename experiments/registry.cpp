// The list of experiments, in run order. Each lives in its own file; add one line here.
#include <filesystem>
#include <fstream>

#include "experiments/experiment.h"
#include "physik/model/errors.h"

namespace physik::experiments {

Experiment rest_poses_experiment();
Experiment ik_comparison_experiment();
Experiment fig5_running_experiment();
Experiment fig6_elbow_experiment();
Experiment fig7_cannon_experiment();
Experiment fig8_wobble_experiment();
Experiment fig9_outstretched_experiment();
Experiment fig10_interpolation_experiment();
Experiment fig11_sit_experiment();
Experiment hand_explodes_experiment();
Experiment timing_experiment();
Experiment damping_sweep_experiment();
Experiment mujoco_gap_experiment();
Experiment tuning_study_experiment();
Experiment beyond_the_paper_experiment();
Experiment scaling_experiment();

const std::vector<Experiment>& all_experiments() {
  static const std::vector<Experiment> list = {
      rest_poses_experiment(),
      fig5_running_experiment(),
      fig6_elbow_experiment(),
      fig7_cannon_experiment(),
      fig8_wobble_experiment(),
      fig9_outstretched_experiment(),
      fig10_interpolation_experiment(),
      fig11_sit_experiment(),
      hand_explodes_experiment(),
      timing_experiment(),
      damping_sweep_experiment(),
      mujoco_gap_experiment(),
      ik_comparison_experiment(),
      tuning_study_experiment(),
      beyond_the_paper_experiment(),
      scaling_experiment(),
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
