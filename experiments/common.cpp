#include "experiments/common.h"

#include <algorithm>
#include <iomanip>
#include <sstream>

#include "physik/io/rig_io.h"
#include "physik/io/scene_io.h"

namespace physik::experiments {

RecordOptions trajectory_table(const std::string& path, int every) {
  RecordOptions o;
  o.csv_path = path;
  o.csv_every = every;
  o.csv_rows = RowRule::kEveryAndFirst;
  return o;
}

Scene scene_named(const Context& ctx, const std::string& name) {
  return load_scene(ctx.models_dir + "/scenes/" + name + ".json");
}

double off_chain_rotation(const Rig& rig, const BoneFrames& a, const BoneFrames& b,
                          const std::vector<int>& controlled) {
  double total = 0.0;
  for (int i = 0; i < rig.nbone; ++i) {
    if (std::find(controlled.begin(), controlled.end(), i) != controlled.end()) continue;
    total += a.orient_world[i].angularDistance(b.orient_world[i]);
  }
  return total;
}

std::vector<int> chains_to_root(const Rig& rig, const std::vector<int>& bones) {
  std::vector<int> out;
  for (int b : bones) {
    for (int i = b; i >= 0; i = rig.bone_parent[i]) {
      if (std::find(out.begin(), out.end(), i) == out.end()) out.push_back(i);
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

nlohmann::json settings_json(const Scene& scene, const nlohmann::json& extra) {
  // the parameters a report line shows, by the parameter table's names and values
  nlohmann::json j = {{"steps", scene.steps}};
  for (const char* name : {"dt", "damping", "control_k", "torsion_k", "joint_eps", "interpolation",
                           "interpolation_steps"}) {
    const ParamRow& row = param_row(name);
    j[name] = param_value_json(row, row.get(scene.params));
  }
  j.update(extra);
  return j;
}

nlohmann::json claim(const std::string& text, const std::string& measured, const std::string& holds) {
  return {{"claim", text}, {"measured", measured}, {"holds", holds}};
}

std::string num(double v, int digits) {
  std::ostringstream s;
  s << std::setprecision(digits) << v;
  return s.str();
}


}  // namespace physik::experiments
