// The gauss-seidel scheme's workspace (newton_euler.h, joint_forces.h, integrate.h), owned by
// the state (SimState::gauss_seidel): the joint solve's caches per joint member and, on a rig
// with welds (rig.h "Welds"), the welded groups as rigid bodies. Arrays in world axes.
// Units: kg, N, N m, rig units, s.
#pragma once

#include <vector>

#include "physik/model/rig.h"

namespace physik {

struct GaussSeidelWorkspace {
  // --- the rigid bodies where bones are welded (sized only for a rig with welds): per body, at
  // its first bone's index; a body of one bone copies it ---
  std::vector<double> body_mass;             // (nbone) kg
  std::vector<Vec3> body_com_world;          // (nbone) rig units
  std::vector<Vec3> body_force_world;        // (nbone) N, at the body's centre of mass
  std::vector<Vec3> body_torque_world;       // (nbone) N m, about it
  std::vector<Mat3> body_inertia_inv_world;  // (nbone) 1/(kg m^2)
  std::vector<Vec3> body_gyro_world;         // (nbone) w x I w, N m
  std::vector<Vec3> body_vel_world;          // (nbone) free rods: its centre's new velocity

  // --- joint solve, per joint member (Rig::joint_member_bone, ...) ---
  std::vector<Vec3> member_r_world;      // (nmember) joint point minus centre of mass
  std::vector<Mat3> member_Minv;         // (nmember) inverse of M_i = m^-1 I + [r]x^T I^-1 [r]x
  std::vector<Mat3> joint_Sinv;          // (njoint) (sum_i M_i^-1)^-1
  std::vector<Vec3> member_accel;        // (nmember) scratch: joint-point accelerations
  std::vector<Vec3> member_force_world;  // (nmember) inter-joint force on that bone at the
                                         //           joint this step, N (sums to 0 per joint)
};

// Size every buffer for a rig, zeroed (size_state, state.h).
void size_gauss_seidel(const Rig& rig, GaussSeidelWorkspace& ws);

}  // namespace physik
