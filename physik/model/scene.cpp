#include "physik/model/scene.h"

namespace physik {

double Scene::residual_tol() const {
  if (convergence.residual_tol > 0.0) return convergence.residual_tol;
  return 1e-3 * rig.reference_length();
}

double Scene::speed_tol() const {
  return convergence.speed_tol > 0.0 ? convergence.speed_tol : 1e-3 * rig.length_scale();
}

double Scene::divergence_energy() const {
  const double h = rig.height();
  return convergence.divergence_energy > 0.0 ? convergence.divergence_energy
                                             : 1e6 * rig.total_mass() * h * h;
}

const char* Scene::world_field() const {
  if (collision.ground) return "ground";
  if (collision.self_collision) return "self_collision";
  if (!collision.obstacles.empty()) return "obstacles";
  if (!gravity_world.isZero()) return "gravity";
  return nullptr;
}

}  // namespace physik
