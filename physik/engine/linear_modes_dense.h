// The linear modes by a dense generalised eigensolver: the reference for the iterative path
// (linear_modes.h, which states the matrices and the rule), for its tests and benchmarks.
// M, K, D1 and Dr are assembled from explicit Jacobians in the exact solve's coordinates (root
// translation world and rotation local, every ball local), and K phi = w^2 M phi is solved by
// Eigen's GeneralizedSelfAdjointEigenSolver (phi^T M phi = 1): O(n^3) time, O(n^2) memory (a
// 437-bone rig takes seconds). K is the force list's (forces.h mode_stiffness), the same elements
// the O(n) operators see. Every mode's w comes out; the rule is linear_modes.h's.
// Units: kg, N/m, N s/m, rad/s.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "physik/engine/linear_modes.h"

namespace physik {

struct DenseLinearModes {
  LinearModes modes;           // the rule's answer (iterations and runs 0)
  std::vector<double> omega;   // rad/s, every mode's angular frequency, ascending
  int first_constrained = -1;  // index of the first mode above the zero-mode threshold
  int slowest = -1;            // index of the mode damping_auto damps; -1 if none
};

// M, K, D1, Dr in the dense coordinates (nv x nv)
struct DenseModeMatrices {
  Eigen::MatrixXd M, K, D1, Dr;
};

DenseModeMatrices dense_mode_matrices(const Scene& scene, const SimState& state,
                                      const std::vector<Vec3>& targets_world);

DenseLinearModes linear_modes_dense(const Scene& scene, const SimState& state,
                                    const std::vector<Vec3>& targets_world);

}  // namespace physik
