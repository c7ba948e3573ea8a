#include "physik/model/scaled_scene.h"

namespace physik {

namespace {

// the rig's bones as build_rig takes them, scaled by s about the origin, mass density x length
// (or the masses kept); the rest frames as matrices, the limits as they are, the inertia the
// cylinder's
std::vector<BoneSpec> scaled_bones(const Rig& rig, double s, std::optional<double> density) {
  std::vector<BoneSpec> specs(rig.nbone);
  for (int i = 0; i < rig.nbone; ++i) {
    BoneSpec& b = specs[i];
    b.name = rig.bone_name[i];
    if (rig.bone_parent[i] >= 0) b.parent = rig.bone_name[rig.bone_parent[i]];
    b.head_world = rig.bone_rest_head_world[i] * s;
    b.tail_world = rig.bone_rest_tail_world[i] * s;
    b.rest_frame_world = rig.bone_rest_orient_world[i].toRotationMatrix();
    b.limit = rig.bone_limit[i];
    b.mass = density ? *density * (b.tail_world - b.head_world).norm() : rig.bone_mass[i];
    b.radius = rig.bone_radius[i] * s;
    b.segment = rig.bone_segment[i];
    b.forward_local = rig.bone_forward_local[i];
  }
  return specs;
}

}  // namespace

Scene scaled_scene(const Scene& base, double s, std::optional<double> density, bool scale_torsion) {
  Scene out = base;
  out.rig =
      build_rig(scaled_bones(base.rig, s, density), base.rig_file + " (scaled)", base.rig.name);
  for (ControlPoint& cp : out.control_points) {
    cp.target_world *= s;
    if (cp.cap) *cp.cap *= s;  // a point's own cap; the others follow params.control_cap
  }
  out.params.control_cap *= s;
  for (TargetChange& t : out.schedule) t.target_world *= s;
  out.initial_pose.root_head_world *= s;
  if (scale_torsion) out.params.torsion_k *= density.value_or(1.0) * s * s * s;
  return out;
}

}  // namespace physik
