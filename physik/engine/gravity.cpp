#include "physik/engine/gravity.h"

#include "physik/engine/measures.h"

namespace physik {

void apply_gravity(const Scene& scene, SimState& s) {
  const Vec3& g = scene.gravity_world;
  if (g.isZero(0.0)) return;
  for (int i = 0; i < scene.rig.nbone; ++i) s.force_world[i] += scene.rig.bone_mass[i] * g;
}

Vec3 gravity_reference(const Scene& scene) {
  if (scene.collision.ground) {
    return scene.collision.ground->height * scene.collision.ground->normal_world;
  }
  return scene.initial_pose.root_head_world;
}

double gravity_potential(const Scene& scene, const BoneFrames& f) {
  const Vec3& g = scene.gravity_world;
  if (g.isZero(0.0)) return 0.0;
  const Vec3 x0 = gravity_reference(scene);
  double u = 0.0;
  for (int i = 0; i < scene.rig.nbone; ++i) {
    u -= scene.rig.bone_mass[i] * g.dot(bone_centre_world(f, i) - x0);
  }
  return u;
}

}  // namespace physik
