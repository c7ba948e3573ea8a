#include "physik/engine/newton_euler.h"

namespace physik {

Mat3 inertia_world(const Rig& rig, const Quat& orient_world, int bone) {
  const Mat3 R = orient_world.toRotationMatrix();
  return R * rig.bone_inertia_local[bone].asDiagonal() * R.transpose();
}

void prepare_bodies(const Rig& rig, const EngineParams& params, SimState& s) {
  for (int i = 0; i < rig.nbone; ++i) {
    s.force_world[i].setZero();
    s.torque_world[i].setZero();
    s.joint_force_world[i].setZero();
    s.joint_torque_world[i].setZero();
    // only the Gauss-Seidel solve and its integration read I^-1 and w x I w; the exact solve
    // forms the inertias itself (articulated_body.h)
    if (params.scheme != Scheme::kGaussSeidel) continue;
    const Mat3 R = s.frames.orient_world[i].toRotationMatrix();
    s.inertia_inv_world[i] =
        R * rig.bone_inertia_local[i].cwiseInverse().asDiagonal() * R.transpose();
    if (params.gyroscopic) {
      const Vec3& w = s.omega_world[i];
      const Vec3 Iw = R * rig.bone_inertia_local[i].asDiagonal() * (R.transpose() * w);
      s.gyro_world[i] = w.cross(Iw);
    } else {
      s.gyro_world[i].setZero();
    }
  }
}

void apply_factor_torque(const Rig& rig, const EngineParams& params, SimState& s) {
  const double per_w = (params.angular_velocity_factor - 1.0) / params.dt;  // 1/s
  for (int i = 0; i < rig.nbone; ++i) {
    s.torque_world[i] +=
        inertia_world(rig, s.frames.orient_world[i], i) * (per_w * s.omega_world[i]);
  }
}

void prepare_welded_bodies(const Rig& rig, const EngineParams& params, SimState& s) {
  GaussSeidelWorkspace& gs = s.gauss_seidel;
  const int n = rig.nbone;
  // a body of one bone is the bone, copied
  for (int i = 0; i < n; ++i) {
    gs.body_mass[i] = rig.bone_mass[i];
    gs.body_com_world[i] = s.com_world[i];
    gs.body_force_world[i] = s.force_world[i];
    gs.body_torque_world[i] = s.torque_world[i];
    gs.body_inertia_inv_world[i] = s.inertia_inv_world[i];
    gs.body_gyro_world[i] = s.gyro_world[i];
  }
  // welded groups: mass and centre first, then the force, torque and inertia about that centre
  std::vector<Mat3>& inertia = gs.body_inertia_inv_world;  // the inertia first, inverted below
  for (int b = 0; b < n; ++b) {
    if (rig.body_nbone[b] < 2) continue;
    gs.body_com_world[b] = rig.bone_mass[b] * s.com_world[b];
    gs.body_force_world[b].setZero();
    gs.body_torque_world[b].setZero();
    inertia[b].setZero();
  }
  for (int i = 0; i < n; ++i) {
    const int b = rig.bone_body[i];
    if (b == i) continue;
    gs.body_mass[b] += rig.bone_mass[i];
    gs.body_com_world[b] += rig.bone_mass[i] * s.com_world[i];
  }
  for (int b = 0; b < n; ++b) {
    if (rig.body_nbone[b] >= 2) gs.body_com_world[b] /= gs.body_mass[b];
  }
  for (int i = 0; i < n; ++i) {
    const int b = rig.bone_body[i];
    if (rig.body_nbone[b] < 2) continue;  // a body of one bone, copied above
    const Vec3 r = s.com_world[i] - gs.body_com_world[b];
    gs.body_force_world[b] += s.force_world[i];
    gs.body_torque_world[b] += s.torque_world[i] + r.cross(s.force_world[i]);
    inertia[b] += inertia_world(rig, s.frames.orient_world[i], i) +
                  rig.bone_mass[i] * (r.squaredNorm() * Mat3::Identity() - r * r.transpose());
  }
  for (int b = 0; b < n; ++b) {
    if (rig.body_nbone[b] < 2) continue;
    const Mat3 I = inertia[b];
    inertia[b] = I.inverse();
    const Vec3& w = s.omega_world[b];
    gs.body_gyro_world[b] = params.gyroscopic ? Vec3(w.cross(I * w)) : Vec3::Zero();
  }
}

}  // namespace physik
