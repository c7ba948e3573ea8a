#include "physik/io/scaled_scene.h"

#include "physik/io/json_fields.h"
#include "physik/io/rig_io.h"

namespace physik {

Scene scaled_scene(const Scene& base, double s, double density, bool scale_torsion) {
  Json doc = rig_to_json(base.rig);
  for (Json& b : doc["bones"]) {
    for (const char* key : {"head", "tail"}) {
      for (auto& v : b[key]) v = v.get<double>() * s;
    }
    const Vec3 head(b["head"][0], b["head"][1], b["head"][2]), tail(b["tail"][0], b["tail"][1], b["tail"][2]);
    b["radius"] = b["radius"].get<double>() * s;
    b["mass"] = density * (tail - head).norm();
    b.erase("inertia_local");
  }
  Scene out = base;
  out.rig = rig_from_json(doc, base.rig_file + " (scaled)");
  for (ControlPoint& cp : out.control_points) {
    cp.target_world *= s;
    if (cp.cap) *cp.cap *= s;  // a point's own cap; the others follow params.control_cap
  }
  out.params.control_cap *= s;
  for (TargetChange& t : out.schedule) t.target_world *= s;
  out.initial_pose.root_head_world *= s;
  if (scale_torsion) out.params.torsion_k *= density * s * s * s;
  return out;
}

}  // namespace physik
