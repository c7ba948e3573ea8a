#include "experiments/common.h"

#include <algorithm>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "physik/ik/ik_solver.h"
#include "physik/io/output_files.h"
#include "physik/io/rig_io.h"
#include "physik/io/run_folder.h"
#include "physik/io/scene_io.h"
#include "physik/model/params.h"
#include "physik/posing/posing_session.h"

namespace physik::experiments {

RecordOptions trajectory_table(const std::string& path, int every) {
  RecordOptions o;
  o.csv_path = path;
  o.csv_every = every;
  o.csv_rows = RowRule::kEveryAndFirst;
  return o;
}

std::string run_folder_path(const Context& ctx, const std::string& name) {
  const std::string runs = ctx.out_dir + "/runs";
  create_output_dir(runs, "--out");
  std::ofstream order(runs + "/order.txt", std::ios::app);
  order << name << "\n";
  return runs + "/" + name;
}

int run_folder_every(const Scene& scene) {
  return std::max(1, (scene.steps + 599) / 600);
}

RunSummary write_run_folder(const Context& ctx, const std::string& name, const Scene& scene) {
  return simulate_into_folder(scene, run_folder_path(ctx, name), run_folder_every(scene));
}

void write_pose_run_folder(const Context& ctx, const std::string& name, const Scene& scene,
                           const BoneFrames& frames, const nlohmann::json& summary) {
  write_pose_folder(scene, run_folder_path(ctx, name), frames, summary);
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

nlohmann::json claim(const std::string& text, const std::string& measured,
                     const std::string& holds) {
  check_verdict(holds);
  return {{"claim", text}, {"measured", measured}, {"holds", holds}};
}

std::string num(double v, int digits) {
  std::ostringstream s;
  s << std::setprecision(digits) << v;
  return s.str();
}

Vec3 random_direction(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Vec3 v(n(rng), n(rng), n(rng));
  return v.normalized();
}

Pose random_legal_pose(const Rig& rig, std::mt19937& rng) {
  Pose p = rest_pose(rig);
  for (int i = 0; i < rig.nbone; ++i) {
    Vec3 v;
    for (int k = 0; k < 3; ++k) {
      const AxisLimit& l = rig.bone_limit[i][k];
      const bool lim = l.limited && i > 0;
      v[k] = std::uniform_real_distribution<double>(lim ? l.min : -1.0, lim ? l.max : 1.0)(rng);
    }
    p.bone_local_rotation[i] = quat_from_rotation_vector(v);
  }
  return p;
}

Scene effector_scene(const std::string& file, const Rig& rig, int bone, bool solve_mode) {
  Scene sc;
  sc.file = file;
  sc.rig = rig;
  sc.params = preset_params("original");
  if (solve_mode) use_solve_mode(sc.params);  // as physik solve --solver physik
  ControlPoint effector, pin;
  effector.bone = bone;
  effector.alpha = 1.0;
  effector.target_world = forward_kinematics(rig, rest_pose(rig)).tail_world[bone];
  pin.bone = 0;
  pin.alpha = 0.0;
  pin.target_world = rig.bone_rest_head_world[0];
  sc.control_points = {effector, pin};
  sc.initial_pose = rest_pose(rig);
  return sc;
}

}  // namespace physik::experiments
