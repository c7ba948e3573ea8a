// The linear modes' buffers (linear_modes.h, mode_operators.h), owned by the state
// (SimState::modes) so that damping auto allocates nothing once they are sized: data only.
#pragma once

#include <utility>
#include <vector>

#include <Eigen/Core>

#include "physik/engine/articulated_body.h"
#include "physik/engine/force_stages.h"

namespace physik {

using VecX = Eigen::VectorXd;

// A point element of K (forces.h mode_stiffness): K_c at offset r from its body's point.
struct ModePointElement {
  int bone = 0;
  Vec3 offset = Vec3::Zero();     // rig units, from o_bone, world
  Mat3 stiffness = Mat3::Zero();  // N/m, world
};

// Every buffer of the linear modes (mode_operators.h, linear_modes.cpp).
struct ModeWorkspace {
  ArticulatedBodyData articulated;     // the recursion's buffers at zero velocity
  std::vector<Vec6> velocity, wrench;  // (nbone) product passes
  std::vector<Mat3> second_moment;     // (nbone) end-damper scale, per subtree's bone
  std::vector<Vec3> first_moment;      //         ends: sum d d^T, sum d, and their count
  std::vector<double> ends;
  ModeStiffness stiffness;                    // K's elements, every force's (forces.h)
  std::vector<ModePointElement> springs;      // K's point elements, about the bodies' points
  std::vector<std::pair<int, Mat3>> couples;  // K's couples on bodies' own turns, N m/rad
  std::vector<std::pair<int, Mat3>> torsion;  // K's ball blocks, N m/rad
  std::vector<VecX> basis, basis_k, basis_f;  // Lanczos: q_j, K q_j, F q_j (grown, never shrunk)
  std::vector<VecX> locked, locked_k;         // converged modes kept out of the Krylov space, K y
  VecX w, kw, my, ay, start;                  // (nv) scratch vectors
};

}  // namespace physik
