#include "physik/model/scene.h"

namespace physik {

double Scene::residual_tol() const {
  return convergence.residual_tol > 0.0 ? convergence.residual_tol : 1e-3 * rig.height();
}

double Scene::speed_tol() const {
  return convergence.speed_tol > 0.0 ? convergence.speed_tol : 1e-3 * rig.height();
}

double Scene::divergence_energy() const {
  const double h = rig.height();
  return convergence.divergence_energy > 0.0 ? convergence.divergence_energy
                                             : 1e6 * rig.total_mass() * h * h;
}

}  // namespace physik
