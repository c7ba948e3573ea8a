// The springs' potential energy, one copy for the run monitor's energy ledger (run_monitor.h)
// and the exact equilibrium (tune/equilibrium.h, where Ceres differentiates the templates).
//
//   control springs (control_springs.h), d = |a - t| (rig units), k in N/m, cap c in rig units:
//     linear  U_c = k d^2 / 2;   capped  U_c = k d^2 / 2 (d <= c),  k c (d - c/2) (d > c)
//   torsion springs (torsion_springs.h), theta = rotation vector of the bone's local rotation,
//   per limited axis the dead-zone excess
//     lo = min + tol (max - min),  hi = max - tol (max - min)
//     e  = lo - theta  (theta < lo),   hi - theta  (theta > hi),   0 otherwise
//   and, k_t in N m/rad, cap c_t in rad:
//     linear  U_t = k_t e^2 / 2; capped  U_t = k_t e^2 / 2 (|e| <= c_t), k_t c_t (|e| - c_t/2)
// Each force law is minus the derivative of its potential (the torsion torque with respect to
// theta; see tune/equilibrium.h for the caveat at large angles). Energies in J.
#pragma once

#include <array>
#include <vector>

#include "physik/engine/state.h"
#include "physik/model/rig.h"
#include "physik/model/scene.h"

namespace physik {

double control_spring_potential(SpringLaw law, double k, double cap, double distance);
double torsion_spring_potential(SpringLaw law, double k, double cap, double excess);

// Dead-zone excess of angle theta (rad) for one limited axis; templated for Ceres' Jets.
template <typename T>
T torsion_excess(const AxisLimit& l, double tolerance, const T& theta) {
  const double band = tolerance * (l.max - l.min);
  const double lo = l.min + band, hi = l.max - band;
  if (theta < T(lo)) return T(lo) - theta;
  if (theta > T(hi)) return T(hi) - theta;
  return T(0);
}

// Excess per local axis of a bone with local rotation q (0 on free axes), rad.
Vec3 torsion_excess(const std::array<AxisLimit, 3>& limits, double tolerance, const Quat& q);

// U of the control springs of `scene` with attachment points `attach_world` pulled toward
// `targets_world` (both (ncontrol), rig units).
double control_potential(const Scene& scene, const std::vector<Vec3>& attach_world,
                         const std::vector<Vec3>& targets_world);

// U of the torsion springs of a pose (0 when torsion_k is 0).
double torsion_potential(const Rig& rig, const EngineParams& params, const Pose& pose);

// U of a state: its control springs toward its effective targets, and its torsion springs
// (the run monitor's energy ledger, the implicit step's energy guard). Allocates nothing.
double spring_potential(const Scene& scene, const SimState& state);

// The whole potential energy of a state (the run monitor's energy ledger, the implicit step's
// energy guard): its springs, gravity and contacts (contacts.h; gravity's and the contacts' only
// where the scene has them). Allocates nothing once the state's collision world is built.
double potential_energy(const Scene& scene, const SimState& state);

}  // namespace physik
