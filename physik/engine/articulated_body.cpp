#include "physik/engine/articulated_body.h"

#include "physik/engine/state.h"

namespace physik {

void resize_articulated_data(int n, ArticulatedBodyData& d) {
  d.joint_block.assign(n, Mat3::Zero());
  d.inertia_com_world.assign(n, Mat3::Zero());
  d.point_world.assign(n, Vec3::Zero());
  d.bias_accel.assign(n, Vec6::Zero());
  d.inertia_art.assign(n, SpatialInertia{});
  d.bias_force.assign(n, Vec6::Zero());
  d.torque_ext_world.assign(n, Vec3::Zero());
  d.D_inv.assign(n, Mat3::Zero());
  d.u.assign(n, Vec3::Zero());
  d.inertia_lower.assign(n, Mat3::Zero());
  d.accel_spatial.assign(n, Vec6::Zero());
  d.joint_accel_local.assign(n, Vec3::Zero());
  d.root_accel_world.setZero();
}

Mat6 SpatialInertia::matrix() const {
  Mat6 out;
  out << A, B, B.transpose(), C;
  return out;
}

void SpatialInertia::add(const Mat6& I) {
  A += I.topLeftCorner<3, 3>();
  B += I.topRightCorner<3, 3>();
  C += I.bottomRightCorner<3, 3>();
}

SpatialInertia spatial_inertia(double m, const Mat3& I_com, const Vec3& e) {
  SpatialInertia out;
  // [e]x [e]x^T = |e|^2 1 - e e^T
  out.A = I_com + m * (e.squaredNorm() * Mat3::Identity() - e * e.transpose());
  out.B = m * skew(e);
  out.C = m * Mat3::Identity();
  return out;
}

void articulated_velocity_pass(const Rig& rig, const SimState& s, ArticulatedBodyData& d) {
  for (int i = 0; i < rig.nbone; ++i) {
    const double m = rig.bone_mass[i];
    const Mat3 R = s.frames.orient_world[i].toRotationMatrix();
    Mat3& I_com = d.inertia_com_world[i];
    I_com.noalias() = R * rig.bone_inertia_local[i].asDiagonal() * R.transpose();
    const Vec3& c = s.com_world[i];
    const Vec3& w = s.omega_world[i];
    const Vec3& v_com = s.vel_world[i];
    const int p = rig.bone_parent[i];
    const Vec3 o = p < 0 ? c : s.frames.head_world[i];
    const Vec3 e = c - o;
    d.point_world[i] = o;

    // velocity-product acceleration of the joint (Featherstone's c = V x v_J), v_o = v - w x e
    if (p < 0) {
      d.bias_accel[i] << Vec3::Zero(), -w.cross(v_com);
    } else {
      const Vec3 w_rel = w - s.omega_world[p];
      d.bias_accel[i] << w.cross(w_rel), (v_com - w.cross(e)).cross(w_rel);
    }

    // the external wrench; rigid inertia about o; the bias force V x* I V - f_ext about o
    const Vec3 Iw = I_com * w;
    Vec3& tau = d.torque_ext_world[i];
    tau = s.torque_world[i] + d.torque_per_omega * Iw;
    if (d.cancel_gyroscopic) tau += w.cross(Iw);
    SpatialInertia& IA = d.inertia_art[i];  // spatial_inertia(m, I_com, e), in place
    IA.A = I_com;
    IA.A.noalias() += m * (e.squaredNorm() * Mat3::Identity() - e * e.transpose());
    IA.B = m * skew(e);
    IA.C = m * Mat3::Identity();
    const Vec3 lin = m * w.cross(v_com) - s.force_world[i];
    d.bias_force[i] << w.cross(Iw) + e.cross(lin) - tau, lin;
  }
}

namespace {

// A ball joint's articulated inertia handed to its parent p (every J = 0), r from p's point to
// i's: S' = [1; 0]: U = I^A S' = [A; B^T], D = A, u = -S'^T p^A; I^a = [0, 0; 0, K] with
// K = C - B^T A^-1 B (articulated_body.h). Returns p^a = p^A + I^a c + U D^-1 u in pa_ang, pa_lin.
void ball_to_parent(ArticulatedBodyData& d, int i, int p, const Vec3& r, const Vec3& u,
                    Vec3& pa_ang, Vec3& pa_lin) {
  const SpatialInertia& IA = d.inertia_art[i];
  const Mat3& A = IA.A;
  const Mat3& B = IA.B;
  const Vec6& c = d.bias_accel[i];
  SpatialInertia& IP = d.inertia_art[p];
  d.D_inv[i] = A.inverse();
  Mat3 DinvB;
  DinvB.noalias() = d.D_inv[i] * B;
  Mat3 K = IA.C;
  K.noalias() -= B.transpose() * DinvB;
  K = (0.5 * (K + K.transpose())).eval();
  const Vec3 Dinv_u = d.D_inv[i] * u;
  pa_ang = d.bias_force[i].head<3>() + A * Dinv_u;
  pa_lin = d.bias_force[i].tail<3>() + K * c.tail<3>() + B.transpose() * Dinv_u;
  // a pure translational inertia K at r: X* I^a X = [R K R^T, R K; K R^T, K],  R = [r]x,
  // by cross products: column j of [r]x K is r x K_j; [r]x K [r]x^T is symmetric, its
  // column j is r x (row j of [r]x K)
  Mat3 RK;
  for (int j = 0; j < 3; ++j) RK.col(j) = r.cross(K.col(j));
  for (int j = 0; j < 3; ++j) IP.A.col(j) += r.cross(Vec3(RK.row(j).transpose()));
  IP.B += RK;
  IP.C += K;
}

// The same with general blocks: I^A = [A B; E C], D = A + J,
//   I^a = [A D^-1 J, J D^-1 B; E D^-1 J, C - E D^-1 B] (products, no cancellation)
void general_to_parent(ArticulatedBodyData& d, int i, int p, const Vec3& r, const Vec3& u,
                       Vec3& pa_ang, Vec3& pa_lin) {
  const SpatialInertia& IA = d.inertia_art[i];
  const Mat3& A = IA.A;
  const Mat3& B = IA.B;
  const Vec6& c = d.bias_accel[i];
  SpatialInertia& IP = d.inertia_art[p];
  const Mat3& E = d.inertia_lower[i];
  const Mat3& J = d.joint_block[i];
  d.D_inv[i] = Mat3(A + J).inverse();
  const Mat3& Dinv = d.D_inv[i];
  Mat3 DinvB, EDinv;
  DinvB.noalias() = Dinv * B;
  EDinv.noalias() = E * Dinv;
  Mat3 Aa, Ba, Ea, Ca = IA.C;
  Aa.noalias() = A * Dinv * J;
  Ba.noalias() = J * DinvB;
  Ea.noalias() = EDinv * J;
  Ca.noalias() -= E * DinvB;
  // p^a = p^A + I^a c + U D^-1 u,  U = [A; E]
  const Vec3 Dinv_u = Dinv * u;
  pa_ang = d.bias_force[i].head<3>() + A * Dinv_u + Aa * c.head<3>() + Ba * c.tail<3>();
  pa_lin = d.bias_force[i].tail<3>() + E * Dinv_u + Ea * c.head<3>() + Ca * c.tail<3>();
  // X* I^a X = [A - B R + R (E - C R), B + R C; E - C R, C],  R = [r]x
  const Mat3 R = skew(r);
  Mat3 Es = Ea;
  Es.noalias() -= Ca * R;
  IP.A += Aa;
  IP.A.noalias() -= Ba * R;
  IP.A.noalias() += R * Es;
  IP.B += Ba;
  IP.B.noalias() += R * Ca;
  d.inertia_lower[p] += Es;
  IP.C += Ca;
}

}  // namespace

void articulated_backward_pass(const Rig& rig, ArticulatedBodyData& d) {
  const bool ball = !d.joint_blocks;  // every J = 0: I^A stays symmetric, E = B^T
  if (!ball) {
    // E starts as each body's own (symmetric) B^T; children add theirs below
    for (int i = 0; i < rig.nbone; ++i) d.inertia_lower[i] = d.inertia_art[i].B.transpose();
  }
  for (int i = rig.nbone - 1; i > 0; --i) {
    const int p = rig.bone_parent[i];
    const Vec3 u = -d.bias_force[i].head<3>();
    d.u[i] = u;
    const Vec3 r = d.point_world[i] - d.point_world[p];  // to the parent's point
    Vec3 pa_ang, pa_lin;
    if (ball) {
      ball_to_parent(d, i, p, r, u, pa_ang, pa_lin);
    } else {
      general_to_parent(d, i, p, r, u, pa_ang, pa_lin);
    }
    d.bias_force[p].head<3>() += pa_ang + r.cross(pa_lin);
    d.bias_force[p].tail<3>() += pa_lin;
  }
}

void articulated_forward_pass(const Rig& rig, const SimState& s, ArticulatedBodyData& d) {
  if (rig.nbone == 0) return;
  // the free root: I^A a = -p^A (no joint force), then classical accelerations
  if (d.joint_blocks) {
    Mat6 I0;
    I0 << d.inertia_art[0].A, d.inertia_art[0].B, d.inertia_lower[0], d.inertia_art[0].C;
    d.root_lu.compute(I0);
    d.accel_spatial[0] = d.root_lu.solve(-d.bias_force[0]);
  } else {
    d.root_ldlt.compute(d.inertia_art[0].matrix());
    d.accel_spatial[0] = d.root_ldlt.solve(-d.bias_force[0]);
  }
  const Vec3 alpha0 = d.accel_spatial[0].head<3>();
  d.root_accel_world = d.accel_spatial[0].tail<3>() + s.omega_world[0].cross(s.vel_world[0]);
  d.joint_accel_local[0] = s.frames.orient_world[0].conjugate() * alpha0;

  for (int i = 1; i < rig.nbone; ++i) {
    const int p = rig.bone_parent[i];
    const Vec3 r = d.point_world[i] - d.point_world[p];
    const Vec6& ap = d.accel_spatial[p];
    const Vec3 alpha = ap.head<3>() + d.bias_accel[i].head<3>();
    const Vec3 lin = ap.tail<3>() - r.cross(ap.head<3>()) + d.bias_accel[i].tail<3>();
    // qdd' = D^-1 (u - S'^T I^A a'),  S'^T I^A a' = A alpha + B lin
    const SpatialInertia& IA = d.inertia_art[i];
    const Vec3 qdd = d.D_inv[i] * (d.u[i] - IA.A * alpha - IA.B * lin);  // world axes
    d.accel_spatial[i] << alpha + qdd, lin;
    d.joint_accel_local[i] = s.frames.orient_world[i].conjugate() * qdd;
  }
}

}  // namespace physik
