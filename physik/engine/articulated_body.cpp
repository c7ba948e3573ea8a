#include "physik/engine/articulated_body.h"

#include "physik/engine/state.h"

namespace physik {

void resize_articulated_data(int n, ArticulatedBodyData& d) {
  d.force_ext_world.assign(n, Vec3::Zero());
  d.torque_ext_world.assign(n, Vec3::Zero());
  d.point_world.assign(n, Vec3::Zero());
  d.vel_spatial.assign(n, Vec6::Zero());
  d.bias_accel.assign(n, Vec6::Zero());
  d.inertia_art.assign(n, Mat6::Zero());
  d.bias_force.assign(n, Vec6::Zero());
  d.joint_block.assign(n, Mat3::Zero());
  d.U.assign(n, Mat63::Zero());
  d.D_inv.assign(n, Mat3::Zero());
  d.u.assign(n, Vec3::Zero());
  d.accel_spatial.assign(n, Vec6::Zero());
  d.joint_accel_local.assign(n, Vec3::Zero());
  d.root_accel_world.setZero();
}

Mat6 spatial_inertia(double m, const Mat3& I_com, const Vec3& e) {
  const Mat3 ex = skew(e);
  Mat6 out;
  out.topLeftCorner<3, 3>() = I_com + m * ex * ex.transpose();
  out.topRightCorner<3, 3>() = m * ex;
  out.bottomLeftCorner<3, 3>() = m * ex.transpose();
  out.bottomRightCorner<3, 3>() = m * Mat3::Identity();
  return out;
}

Mat6 shift_inertia(const Mat6& I, const Vec3& r) {
  // [A B; B^T C] -> [A + R B^T + B' R^T, B'; B'^T, C],  B' = B + R C,  R = [r]x
  const Mat3 R = skew(r);
  const Mat3 B1 = I.topRightCorner<3, 3>() + R * I.bottomRightCorner<3, 3>();
  const Mat3 RBt = R * I.topRightCorner<3, 3>().transpose();
  Mat6 out;
  out.topLeftCorner<3, 3>() = I.topLeftCorner<3, 3>() + RBt + B1 * R.transpose();
  out.topRightCorner<3, 3>() = B1;
  out.bottomLeftCorner<3, 3>() = B1.transpose();
  out.bottomRightCorner<3, 3>() = I.bottomRightCorner<3, 3>();
  return out;
}

void articulated_velocity_pass(const Rig& rig, const SimState& s, ArticulatedBodyData& d) {
  for (int i = 0; i < rig.nbone; ++i) {
    const double m = rig.bone_mass[i];
    const Mat3 R = s.frames.orient_world[i].toRotationMatrix();
    const Mat3 I_com = R * rig.bone_inertia_local[i].asDiagonal() * R.transpose();
    const Vec3& c = s.com_world[i];
    const Vec3& w = s.omega_world[i];
    const Vec3& v_com = s.vel_world[i];
    const int p = rig.bone_parent[i];
    const Vec3 o = p < 0 ? c : s.frames.head_world[i];
    const Vec3 e = c - o;
    const Vec3 v_o = v_com - w.cross(e);  // v_com = v_o + w x e
    d.point_world[i] = o;
    d.vel_spatial[i] << w, v_o;

    // velocity-product acceleration of the joint (Featherstone's c = V x v_J)
    if (p < 0) {
      d.bias_accel[i] << Vec3::Zero(), -w.cross(v_com);
    } else {
      const Vec3 w_rel = w - s.omega_world[p];
      d.bias_accel[i] << w.cross(w_rel), v_o.cross(w_rel);
    }

    // rigid inertia about o, and the bias force V x* I V - f_ext about o
    d.inertia_art[i] = spatial_inertia(m, I_com, e);
    const Vec3 lin = m * w.cross(v_com);
    const Vec3& F = d.force_ext_world[i];
    d.bias_force[i] << w.cross(I_com * w) + e.cross(lin) - d.torque_ext_world[i] - e.cross(F),
        lin - F;
    d.joint_block[i].setZero();
  }
}

void articulated_backward_pass(const Rig& rig, ArticulatedBodyData& d) {
  for (int i = rig.nbone - 1; i > 0; --i) {
    const int p = rig.bone_parent[i];
    const Mat6& IA = d.inertia_art[i];
    const Mat3 A = IA.topLeftCorner<3, 3>(), B = IA.topRightCorner<3, 3>();
    const Mat3& J = d.joint_block[i];
    // S' = [1; 0]: U = I^A S' is I^A's left block column, D its top-left block (+ joint block)
    d.U[i] = IA.leftCols<3>();
    d.D_inv[i] = (A + J).inverse();
    d.u[i] = -d.bias_force[i].head<3>();
    // I^a = I^A - U D^-1 U^T in a form without cancellation: with D = A + J,
    //   A - A D^-1 A = A D^-1 J,  B - A D^-1 B = J D^-1 B,  C - B^T D^-1 B
    // so a ball (J = 0) passes on only the 3x3 translational block. (The difference form leaves
    // round-off in the top blocks that doubles with every link of a long chain.)
    const Mat3 DinvB = d.D_inv[i] * B;
    Mat3 K = IA.bottomRightCorner<3, 3>() - B.transpose() * DinvB;
    K = 0.5 * (K + K.transpose()).eval();
    Mat6 Ia;
    Ia.bottomRightCorner<3, 3>() = K;
    if (J.isZero(0.0)) {
      Ia.topLeftCorner<3, 3>().setZero();
      Ia.topRightCorner<3, 3>().setZero();
      Ia.bottomLeftCorner<3, 3>().setZero();
    } else {
      Ia.topLeftCorner<3, 3>() = A * d.D_inv[i] * J;
      Ia.topRightCorner<3, 3>() = J * DinvB;
      Ia.bottomLeftCorner<3, 3>() = Ia.topRightCorner<3, 3>().transpose();
    }
    const Vec6 pa = d.bias_force[i] + Ia * d.bias_accel[i] + d.U[i] * (d.D_inv[i] * d.u[i]);
    // to the parent's point: X* I^a X and X* p^a, r = o_i - o_p
    const Vec3 r = d.point_world[i] - d.point_world[p];
    d.inertia_art[p] += shift_inertia(Ia, r);
    d.bias_force[p].head<3>() += pa.head<3>() + r.cross(pa.tail<3>());
    d.bias_force[p].tail<3>() += pa.tail<3>();
  }
}

void articulated_forward_pass(const Rig& rig, const SimState& s, ArticulatedBodyData& d) {
  if (rig.nbone == 0) return;
  // the free root: I^A a = -p^A (no joint force), then classical accelerations
  d.root_ldlt.compute(d.inertia_art[0]);
  d.accel_spatial[0] = d.root_ldlt.solve(-d.bias_force[0]);
  const Vec3 alpha0 = d.accel_spatial[0].head<3>();
  d.root_accel_world =
      d.accel_spatial[0].tail<3>() + s.omega_world[0].cross(s.vel_world[0]);
  d.joint_accel_local[0] = s.frames.orient_world[0].conjugate() * alpha0;

  for (int i = 1; i < rig.nbone; ++i) {
    const int p = rig.bone_parent[i];
    const Vec3 r = d.point_world[i] - d.point_world[p];
    const Vec6& ap = d.accel_spatial[p];
    Vec6 a;
    a << ap.head<3>(), ap.tail<3>() - r.cross(ap.head<3>());
    a += d.bias_accel[i];
    const Vec3 qdd = d.D_inv[i] * (d.u[i] - d.U[i].transpose() * a);  // world axes
    a.head<3>() += qdd;
    d.accel_spatial[i] = a;
    d.joint_accel_local[i] = s.frames.orient_world[i].conjugate() * qdd;
  }
}

}  // namespace physik
