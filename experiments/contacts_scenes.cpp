// Scenes and the timed loop the contacts experiments and the benchmarks share
// (contacts_scenes.h).
#include "experiments/contacts_scenes.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <nlohmann/json.hpp>

#include "experiments/scaling.h"
#include "physik/engine/engine.h"
#include "physik/io/scene_io.h"

namespace physik::experiments {

Scene contacts_hand_scene(const std::string& models_dir, bool self_collision, int steps) {
  const nlohmann::json doc = {{"rig", models_dir + "/rigs/pinhead.json"},
                              {"params", {{"preset", "robust"}, {"dt", 0.05}, {"damping", 3.0}}},
                              {"steps", steps},
                              {"self_collision", self_collision},
                              {"control_points",
                               {{{"name", "neck"},
                                 {"bone", "torso"},
                                 {"alpha", 0.0},
                                 {"target", {0, 0, 1.8155}},
                                 {"k", 300}},
                                {{"name", "pelvis"},
                                 {"bone", "torso"},
                                 {"alpha", 1.0},
                                 {"target", {0, 0, 0.4541}},
                                 {"k", 300}},
                                {{"name", "hand.L"},
                                 {"bone", "hand.L"},
                                 {"alpha", 1.0},
                                 {"target", {-1.0, 0, 1.0}},
                                 {"k", 30}}}}};
  return scene_from_json(doc, self_collision ? "contacts_hand_on" : "contacts_hand_off", ".");
}

double capsule_bottom(const Rig& rig, const BoneFrames& f, int b) {
  return std::min(f.head_world[b].z(), f.tail_world[b].z()) - rig.bone_collision_radius[b];
}

double lowest_capsule_point(const Rig& rig, const BoneFrames& f) {
  double lowest = std::numeric_limits<double>::infinity();
  for (int i = 0; i < rig.nbone; ++i) lowest = std::min(lowest, capsule_bottom(rig, f, i));
  return lowest;
}

Scene contacts_cost_pinhead_scene(const std::string& models_dir, bool contacts) {
  Scene s = contacts_hand_scene(models_dir, contacts, 300);
  s.gravity_world = Vec3(0, 0, -9.81);
  if (contacts) {
    const double floor = lowest_capsule_point(s.rig, forward_kinematics(s.rig, s.initial_pose));
    s.collision.ground = GroundPlane{Vec3::UnitZ(), floor};
  }
  return s;
}

void time_steps(const Scene& scene, SimState& s, int steps, TimedSteps& out) {
  const double t0 = thread_seconds();
  for (int k = 0; k < steps; ++k) {
    const StepStats st = step(scene, s);
    out.substeps += st.substeps;
    out.finite = out.finite && std::isfinite(st.kinetic_energy);
  }
  out.seconds += thread_seconds() - t0;
}

}  // namespace physik::experiments
