#include "physik/engine/articulated_body.h"

#include "physik/model/joint_coordinates.h"

namespace physik {

void resize_articulated_data(int n, ArticulatedBodyData& d) {
  d.joint_block.assign(n, Mat3::Zero());
  d.inertia_com_world.assign(n, Mat3::Zero());
  d.axis0_world.assign(n, Vec3::Zero());
  d.axis1_world.assign(n, Vec3::Zero());
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
  d.inertia_z.assign(n, SpatialInertia{});
  d.inertia_z_lower.assign(n, Mat3::Zero());
  d.row_ang.assign(n, Mat3::Zero());
  d.row_lin.assign(n, Mat3::Zero());
  d.joint_torque.assign(n, Vec3::Zero());
  d.z_accel.assign(n, Vec6::Zero());
  d.z_axis_turn.assign(n, Vec3::Zero());
  d.z_spatial.assign(n, Vec6::Zero());
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

namespace {

// out = R diag(d) R^T: symmetric, its upper triangle computed and mirrored
inline void rotated_diagonal(const Mat3& R, const Vec3& diag, Mat3& out) {
  Mat3 RD;  // R diag(d): column k scaled by d_k
  for (int k = 0; k < 3; ++k) RD.col(k) = R.col(k) * diag[k];
  const double i00 = RD.row(0).dot(R.row(0)), i01 = RD.row(0).dot(R.row(1));
  const double i02 = RD.row(0).dot(R.row(2)), i11 = RD.row(1).dot(R.row(1));
  const double i12 = RD.row(1).dot(R.row(2)), i22 = RD.row(2).dot(R.row(2));
  out << i00, i01, i02, i01, i11, i12, i02, i12, i22;
}

// S v for a symmetric S (upper triangle read)
inline Vec3 symmetric_times(const Mat3& S, const Vec3& v) {
  return Vec3(S(0, 0) * v.x() + S(0, 1) * v.y() + S(0, 2) * v.z(),
              S(0, 1) * v.x() + S(1, 1) * v.y() + S(1, 2) * v.z(),
              S(0, 2) * v.x() + S(1, 2) * v.y() + S(2, 2) * v.z());
}

// the rigid spatial inertia of spatial_inertia(m, I_com, e) written into out, with the known
// structure: A = I_com + m (|e|^2 1 - e e^T) (symmetric), B = m [e]x, C = m 1
inline void rigid_inertia(double m, const Mat3& I_com, const Vec3& e, SpatialInertia& out) {
  const Vec3 me = m * e;
  const double ee = me.dot(e);
  const double a00 = I_com(0, 0) + (ee - me.x() * e.x());
  const double a01 = I_com(0, 1) - me.x() * e.y();
  const double a02 = I_com(0, 2) - me.x() * e.z();
  const double a11 = I_com(1, 1) + (ee - me.y() * e.y());
  const double a12 = I_com(1, 2) - me.y() * e.z();
  const double a22 = I_com(2, 2) + (ee - me.z() * e.z());
  out.A << a00, a01, a02, a01, a11, a12, a02, a12, a22;
  out.B << 0.0, -me.z(), me.y(), me.z(), 0.0, -me.x(), -me.y(), me.x(), 0.0;
  out.C << m, 0.0, 0.0, 0.0, m, 0.0, 0.0, 0.0, m;
}

// the inverse of a symmetric 3x3 (upper triangle read) by its cofactors, mirrored
inline void symmetric_inverse(const Mat3& S, Mat3& out) {
  const double a = S(0, 0), b = S(0, 1), c = S(0, 2), d = S(1, 1), e = S(1, 2), f = S(2, 2);
  const double c00 = d * f - e * e, c01 = c * e - b * f, c02 = b * e - c * d;
  const double k = 1.0 / (a * c00 + b * c01 + c * c02);
  const double i00 = c00 * k, i01 = c01 * k, i02 = c02 * k;
  const double i11 = (a * f - c * c) * k, i12 = (b * c - a * e) * k, i22 = (a * d - b * b) * k;
  out << i00, i01, i02, i01, i11, i12, i02, i12, i22;
}

// a hinge's or universal's world axes (joint_coordinates.h) into d, and a universal's share of
// its bias acceleration: s0 turns with the parent, so c.ang = w_p x s0 t0' + w_i x s1 t1'
// = w_i x w_rel + t0' t1' s0 x s1 (t_k' = s_k . w_rel)
void hinge_axes_and_bias(const Rig& rig, const BodyMotion& s, int i, const Vec3& w_rel,
                         ArticulatedBodyData& d) {
  const int p = rig.bone_parent[i];
  hinge_axes_world(rig, i, p < 0 ? Quat::Identity() : s.frames.orient_world[p],
                   s.frames.orient_world[i], d.axis0_world[i], d.axis1_world[i]);
  if (rig.bone_joint_type[i] != JointType::kUniversal) return;
  const Vec3& s0 = d.axis0_world[i];
  const Vec3& s1 = d.axis1_world[i];
  d.bias_accel[i].head<3>() += (s0.dot(w_rel) * s1.dot(w_rel)) * s0.cross(s1);
}

}  // namespace

Mat3 axis_projector(const Mat3& M, const Vec3& s0, const Vec3& s1, bool one) {
  const Vec3 Ms0 = M * s0;
  const double d00 = s0.dot(Ms0);
  if (one) return (1.0 / d00) * (s0 * s0.transpose());
  // S (S^T M S)^-1 S^T with the 2x2 inverse [d11 -d01; -d10 d00] / det
  const Vec3 Ms1 = M * s1;
  const double d01 = s0.dot(Ms1), d10 = s1.dot(Ms0), d11 = s1.dot(Ms1);
  const double k = 1.0 / (d00 * d11 - d01 * d10);
  return k * (d11 * s0 * s0.transpose() - d01 * s0 * s1.transpose() - d10 * s1 * s0.transpose() +
              d00 * s1 * s1.transpose());
}

void articulated_velocity_pass(const Rig& rig, const BodyMotion& s, ArticulatedBodyData& d) {
  for (int i = 0; i < rig.nbone; ++i) {
    const double m = rig.bone_mass[i];
    const Mat3 R = s.frames.orient_world[i].toRotationMatrix();
    Mat3& I_com = d.inertia_com_world[i];
    rotated_diagonal(R, rig.bone_inertia_local[i], I_com);
    const Vec3& c = s.com_world[i];
    const Vec3& w = s.omega_world[i];
    const Vec3& v_com = s.vel_world[i];
    const int p = rig.bone_joint_parent[i];
    const JointType type = rig.joint_type(i, d.locked_axes);
    // the joint's point: a free root's centre of mass, else the head (an anchored root's too)
    const Vec3 o = type == JointType::kFree ? c : s.frames.head_world[i];
    const Vec3 e = c - o;
    d.point_world[i] = o;

    // velocity-product acceleration of the joint (Featherstone's c = V x v_J), v_o = v - w x e;
    // a weld has no joint velocity
    if (type == JointType::kFree) {
      d.bias_accel[i] << Vec3::Zero(), -w.cross(v_com);
    } else if (type == JointType::kWeld) {
      d.bias_accel[i].setZero();
    } else {
      const Vec3 w_rel = p < 0 ? w : Vec3(w - s.omega_world[p]);
      d.bias_accel[i] << w.cross(w_rel), (v_com - w.cross(e)).cross(w_rel);
      if (type != JointType::kBall) hinge_axes_and_bias(rig, s, i, w_rel, d);
    }

    // the external wrench; rigid inertia about o; the bias force V x* I V - f_ext about o
    const Vec3 Iw = symmetric_times(I_com, w);
    Vec3& tau = d.torque_ext_world[i];
    tau = s.torque_world[i] + d.torque_per_omega * Iw;
    if (d.cancel_gyroscopic) tau += w.cross(Iw);
    rigid_inertia(m, I_com, e, d.inertia_art[i]);
    const Vec3 lin = m * w.cross(v_com) - s.force_world[i];
    d.bias_force[i] << w.cross(Iw) + e.cross(lin) - tau, lin;
  }
}

namespace {

// A ball joint's articulated inertia handed to its parent p (every J = 0), r from p's point to
// i's: S' = [1; 0]: U = I^A S' = [A; B^T], D = A, u = -S'^T p^A; I^a = [0, 0; 0, K] with
// K = C - B^T A^-1 B (articulated_body.h). p^a = p^A + I^a c + U D^-1 u has the angular part
// p^A_ang + A A^-1 u = 0 (u = -p^A_ang), and the linear part p^A_lin + K c_lin - (A^-1 B)^T p^A_ang
// (A symmetric); it goes to the parent as (r x p^a_lin; p^a_lin). A, D^-1 and K are symmetric:
// their upper triangles are computed and mirrored.
void ball_to_parent(ArticulatedBodyData& d, int i, int p, const Vec3& r) {
  const SpatialInertia& IA = d.inertia_art[i];
  const Mat3& B = IA.B;
  const Mat3& C = IA.C;
  Mat3& Dinv = d.D_inv[i];
  symmetric_inverse(IA.A, Dinv);
  Mat3 DinvB;
  DinvB.noalias() = Dinv * B;
  // K = C - B^T D^-1 B, upper triangle
  const double k00 = C(0, 0) - B.col(0).dot(DinvB.col(0));
  const double k01 = C(0, 1) - B.col(0).dot(DinvB.col(1));
  const double k02 = C(0, 2) - B.col(0).dot(DinvB.col(2));
  const double k11 = C(1, 1) - B.col(1).dot(DinvB.col(1));
  const double k12 = C(1, 2) - B.col(1).dot(DinvB.col(2));
  const double k22 = C(2, 2) - B.col(2).dot(DinvB.col(2));
  Mat3 K;
  K << k00, k01, k02, k01, k11, k12, k02, k12, k22;
  const Vec6& c = d.bias_accel[i];
  const Vec3 p_ang = d.bias_force[i].head<3>();
  const Vec3 pa_lin = d.bias_force[i].tail<3>() + K * c.tail<3>() - DinvB.transpose() * p_ang;
  // a pure translational inertia K at r: X* I^a X = [R K R^T, R K; K R^T, K],  R = [r]x,
  // by cross products: column j of [r]x K is r x K_j; [r]x K [r]x^T is symmetric, its
  // entry (a, j) is (r x row j of [r]x K)_a
  Mat3 RK;
  for (int j = 0; j < 3; ++j) RK.col(j) = r.cross(K.col(j));
  const double x = r.x(), y = r.y(), z = r.z();
  // (r x v)_0 = y v2 - z v1, _1 = z v0 - x v2, _2 = x v1 - y v0 with v = row j of RK
  const double s00 = y * RK(0, 2) - z * RK(0, 1);
  const double s01 = y * RK(1, 2) - z * RK(1, 1);
  const double s02 = y * RK(2, 2) - z * RK(2, 1);
  const double s11 = z * RK(1, 0) - x * RK(1, 2);
  const double s12 = z * RK(2, 0) - x * RK(2, 2);
  const double s22 = x * RK(2, 1) - y * RK(2, 0);
  SpatialInertia& IP = d.inertia_art[p];
  IP.A(0, 0) += s00;
  IP.A(0, 1) += s01;
  IP.A(0, 2) += s02;
  IP.A(1, 0) += s01;
  IP.A(1, 1) += s11;
  IP.A(1, 2) += s12;
  IP.A(2, 0) += s02;
  IP.A(2, 1) += s12;
  IP.A(2, 2) += s22;
  IP.B += RK;
  IP.C += K;
  d.bias_force[p].head<3>() += r.cross(pa_lin);
  d.bias_force[p].tail<3>() += pa_lin;
}

// X* M X for a general spatial 6x6 M = [A B; E C] handed from a child to its parent's point
// (r = o_child - o_parent, R = [r]x): [A - B R + R (E - C R), B + R C; E - C R, C], added to
// the parent's (PA, PB, PE, PC)
inline void add_shifted(const Mat3& A, const Mat3& B, const Mat3& E, const Mat3& C, const Vec3& r,
                        Mat3& PA, Mat3& PB, Mat3& PE, Mat3& PC) {
  const Mat3 R = skew(r);
  Mat3 Es = E;
  Es.noalias() -= C * R;
  PA += A;
  PA.noalias() -= B * R;
  PA.noalias() += R * Es;
  PB += B;
  PB.noalias() += R * C;
  PE += Es;
  PC += C;
}

// A weld hands its whole articulated inertia and bias on to its joint parent (no coordinate to
// eliminate: I^a = I^A, p^a = p^A + I^A c with c = 0). E = B^T unless `general`.
void weld_to_parent(ArticulatedBodyData& d, int i, int p, const Vec3& r, bool general) {
  const SpatialInertia& IA = d.inertia_art[i];
  SpatialInertia& IP = d.inertia_art[p];
  Mat3 unused_lower;
  const Mat3 E = general ? d.inertia_lower[i] : Mat3(IA.B.transpose());
  add_shifted(IA.A, IA.B, E, IA.C, r, IP.A, IP.B, general ? d.inertia_lower[p] : unused_lower,
              IP.C);
  const Vec6& pa = d.bias_force[i];
  d.bias_force[p].head<3>() += pa.head<3>() + r.cross(Vec3(pa.tail<3>()));
  d.bias_force[p].tail<3>() += pa.tail<3>();
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
  add_shifted(Aa, Ba, Ea, Ca, r, IP.A, IP.B, d.inertia_lower[p], IP.C);
}

// A hinge's or universal's (articulated_body.h): D = S^T (A + J) S, D_inv = P = S D^-1 S^T,
//   I^a = I^A - [A; E] P [A B],  p^a = p^A + I^a c + [A; E] P u
// with E = B^T and I^a symmetric unless `general` (joint blocks); handed to the parent as a
// weld's is. The locked directions keep their share of A: I^a's angular blocks are not zero.
void hinge_to_parent(const Rig& rig, ArticulatedBodyData& d, int i, int p, const Vec3& r,
                     const Vec3& u, bool general) {
  const SpatialInertia& IA = d.inertia_art[i];
  const Mat3& A = IA.A;
  const Mat3& B = IA.B;
  const Mat3 E = general ? d.inertia_lower[i] : Mat3(B.transpose());
  const Mat3 AJ = general ? Mat3(A + d.joint_block[i]) : A;
  d.D_inv[i] = axis_projector(AJ, d.axis0_world[i], d.axis1_world[i],
                              rig.bone_joint_type[i] == JointType::kHinge);
  const Mat3& P = d.D_inv[i];
  Mat3 AP, EP;
  AP.noalias() = A * P;
  EP.noalias() = E * P;
  Mat3 Aa = A, Ba = B, Ea = E, Ca = IA.C;
  Aa.noalias() -= AP * A;
  Ba.noalias() -= AP * B;
  Ea.noalias() -= EP * A;
  Ca.noalias() -= EP * B;
  const Vec6& c = d.bias_accel[i];
  const Vec3 Pu = P * u;
  const Vec3 pa_ang = d.bias_force[i].head<3>() + A * Pu + Aa * c.head<3>() + Ba * c.tail<3>();
  const Vec3 pa_lin = d.bias_force[i].tail<3>() + E * Pu + Ea * c.head<3>() + Ca * c.tail<3>();
  SpatialInertia& IP = d.inertia_art[p];
  Mat3 unused_lower;
  add_shifted(Aa, Ba, Ea, Ca, r, IP.A, IP.B, general ? d.inertia_lower[p] : unused_lower, IP.C);
  d.bias_force[p].head<3>() += pa_ang + r.cross(pa_lin);
  d.bias_force[p].tail<3>() += pa_lin;
}

// is the symmetric part (A + A^T) / 2 positive definite (its Cholesky factor exists)
template <typename M>
bool symmetric_part_positive(const M& A) {
  return Eigen::LLT<M>(M(0.5 * (A + A.transpose()))).info() == Eigen::Success;
}

// Pass 2 with the pose terms (articulated_body.h, ArticulatedBodyData::pose_terms). Per joint,
// with P = S'^T I^Z T and PE its lower block, U = I^A S' + I^Z T = [A + P; E + PE], the row
// S'^T (I^A + G) = [A + G_A, B + G_B], D = A + G_A + P + J:
//   I^a  = I^A - U D^-1 [A + G_A, B + G_B],   I^za = I^Z - U D^-1 [Z_A, Z_B]
// as products where a block would be a difference of near-equal terms (A + G_A = D - P - J,
// A + P = D - G_A - J):
//   I^a  = [(A + P) D^-1 (P + J) - P, (G_A + J) D^-1 (B + G_B) - G_B;
//           (E + PE) D^-1 (P + J) - PE, C - (E + PE) D^-1 (B + G_B)]
//   I^za = [(G_A + J) D^-1 Z_A, (G_A + J) D^-1 Z_B; Z_E - (E + PE) D^-1 Z_A,
//           Z_C - (E + PE) D^-1 Z_B]
//   p^a  = p^A + I^a c + U D^-1 u,   u = joint_torque - S'^T p^A
// joint i's T (the turn of the joint accelerations below it, implicit_pose_terms.h (4)) on its
// world-axes rate: [[alpha]x; [a]x] of z_accel[i], a universal's angular block plus
// z_axis_turn[i] s1^T (its second axis turns after its first hinge's rest acceleration)
inline void turn_blocks(const Rig& rig, const ArticulatedBodyData& d, int i, JointType type,
                        Mat3& Ta, Mat3& Tl) {
  const Vec6& za = d.z_accel[i];
  Ta = skew(za.head<3>());
  Tl = skew(za.tail<3>());
  if (type == JointType::kUniversal)
    Ta.noalias() += d.z_axis_turn[i] * d.axis1_world[i].transpose();
  (void)rig;
}

// a weld under the pose terms: its inertias (I^A and I^Z, general) and bias handed to its joint
// parent whole (no coordinate to eliminate; its c is 0)
void weld_pose_terms(ArticulatedBodyData& d, int i, int p, const Vec3& r) {
  const SpatialInertia& IA = d.inertia_art[i];
  const SpatialInertia& IZ = d.inertia_z[i];
  add_shifted(IA.A, IA.B, d.inertia_lower[i], IA.C, r, d.inertia_art[p].A, d.inertia_art[p].B,
              d.inertia_lower[p], d.inertia_art[p].C);
  add_shifted(IZ.A, IZ.B, d.inertia_z_lower[i], IZ.C, r, d.inertia_z[p].A, d.inertia_z[p].B,
              d.inertia_z_lower[p], d.inertia_z[p].C);
  const Vec6& pa = d.bias_force[i];
  d.bias_force[p].head<3>() += pa.head<3>() + r.cross(Vec3(pa.tail<3>()));
  d.bias_force[p].tail<3>() += pa.tail<3>();
}

// the pivot D's inverse (a ball's) or its projector on the joint's axes (a hinge's, a
// universal's: S (S^T D S)^-1 S^T); false when the symmetric part of D (of S^T D S) is not
// positive definite
bool pose_pivot(const ArticulatedBodyData& d, int i, JointType type, const Mat3& D, Mat3& Dinv) {
  if (type == JointType::kBall) {
    Dinv = D.inverse();
    return symmetric_part_positive(D);
  }
  const Vec3& s0 = d.axis0_world[i];
  const Vec3& s1 = d.axis1_world[i];
  const bool one = type == JointType::kHinge;
  Dinv = axis_projector(D, s0, s1, one);
  if (one) return s0.dot(D * s0) > 0.0;
  Eigen::Matrix2d Dk;
  Dk << s0.dot(D * s0), s0.dot(D * s1), s1.dot(D * s0), s1.dot(D * s1);
  return symmetric_part_positive(Dk);
}

// joint i's pose-terms elimination (backward_pass_pose_terms below), its pivot inverse Dinv (or
// projector) given: I^a, I^za and p^a handed to the parent p. A ball's blocks are the products of
// the comment below (D^-1 a true inverse); a hinge's are the differences I^A - U P row, I^Z - U P
// [Z_A Z_B] (its P is no inverse of D, and its angular blocks are not near zero anyway).
void pose_terms_to_parent(ArticulatedBodyData& d, int i, int p, JointType type, const Mat3& P,
                          const Mat3& PE, const Mat3& GJ, const Mat3& PJ) {
  const SpatialInertia& IA = d.inertia_art[i];
  const SpatialInertia& IZ = d.inertia_z[i];
  const Mat3& E = d.inertia_lower[i];
  const Mat3& ZE = d.inertia_z_lower[i];
  const Mat3& GA = d.row_ang[i];
  const Mat3& GB = d.row_lin[i];
  const Mat3& Dinv = d.D_inv[i];
  const Mat3 UA = IA.A + P, UE = E + PE, BG = IA.B + GB;
  Mat3 UADinv, UEDinv;
  UADinv.noalias() = UA * Dinv;
  UEDinv.noalias() = UE * Dinv;
  Mat3 Aa, Ba, Ea, Ca = IA.C, ZAa, ZBa, ZEa = ZE, ZCa = IZ.C;
  if (type == JointType::kBall) {
    Mat3 GJDinv;
    GJDinv.noalias() = GJ * Dinv;
    Aa = -P, Ba = -GB, Ea = -PE;
    Aa.noalias() += UADinv * PJ;
    Ba.noalias() += GJDinv * BG;
    Ea.noalias() += UEDinv * PJ;
    ZAa.noalias() = GJDinv * IZ.A;
    ZBa.noalias() = GJDinv * IZ.B;
  } else {
    const Mat3 AG = IA.A + GA;
    Aa = IA.A, Ba = IA.B, Ea = E, ZAa = IZ.A, ZBa = IZ.B;
    Aa.noalias() -= UADinv * AG;
    Ba.noalias() -= UADinv * BG;
    Ea.noalias() -= UEDinv * AG;
    ZAa.noalias() -= UADinv * IZ.A;
    ZBa.noalias() -= UADinv * IZ.B;
  }
  Ca.noalias() -= UEDinv * BG;
  ZEa.noalias() -= UEDinv * IZ.A;
  ZCa.noalias() -= UEDinv * IZ.B;
  const Vec6& c = d.bias_accel[i];
  const Vec3 Dinv_u = Dinv * d.u[i];
  const Vec3 pa_ang = d.bias_force[i].head<3>() + Aa * c.head<3>() + Ba * c.tail<3>() + UA * Dinv_u;
  const Vec3 pa_lin = d.bias_force[i].tail<3>() + Ea * c.head<3>() + Ca * c.tail<3>() + UE * Dinv_u;
  const Vec3 r = d.point_world[i] - d.point_world[p];
  SpatialInertia& IP = d.inertia_art[p];
  add_shifted(Aa, Ba, Ea, Ca, r, IP.A, IP.B, d.inertia_lower[p], IP.C);
  SpatialInertia& ZP = d.inertia_z[p];
  add_shifted(ZAa, ZBa, ZEa, ZCa, r, ZP.A, ZP.B, d.inertia_z_lower[p], ZP.C);
  d.bias_force[p].head<3>() += pa_ang + r.cross(pa_lin);
  d.bias_force[p].tail<3>() += pa_lin;
}

void backward_pass_pose_terms(const Rig& rig, ArticulatedBodyData& d) {
  d.pose_terms_positive = true;
  for (int i = rig.nbone - 1; i > 0; --i) {
    const int p = rig.bone_joint_parent[i];
    const JointType type = rig.joint_type(i, d.locked_axes);
    if (type == JointType::kWeld) {
      weld_pose_terms(d, i, p, d.point_world[i] - d.point_world[p]);
      continue;
    }
    const SpatialInertia& IZ = d.inertia_z[i];
    Mat3 Ta, Tl;
    turn_blocks(rig, d, i, type, Ta, Tl);
    Mat3 P, PE;
    P.noalias() = IZ.A * Ta;
    P.noalias() += IZ.B * Tl;
    PE.noalias() = d.inertia_z_lower[i] * Ta;
    PE.noalias() += IZ.C * Tl;
    Mat3 PJ = P, GJ = d.row_ang[i];
    if (d.joint_blocks) {
      PJ += d.joint_block[i];
      GJ += d.joint_block[i];
    }
    const Mat3 D = d.inertia_art[i].A + d.row_ang[i] + PJ;
    if (!pose_pivot(d, i, type, D, d.D_inv[i])) d.pose_terms_positive = false;
    d.u[i] = d.joint_torque[i] - d.bias_force[i].head<3>();
    pose_terms_to_parent(d, i, p, type, P, PE, GJ, PJ);
  }
}

// Pass 3 with the pose terms: the root's 6x6 (articulated_body.h), then per joint
//   a' = X a_p + c,  z' = X z_p,  qdd' = D^-1 (u - [A + G_A, B + G_B] a' - [Z_A, Z_B] z'),
//   a = a' + S' qdd',  z = z' + T qdd'
void forward_pass_pose_terms(const Rig& rig, const BodyMotion& s, ArticulatedBodyData& d) {
  const SpatialInertia& I0 = d.inertia_art[0];
  const SpatialInertia& Z0 = d.inertia_z[0];
  const Vec3 alpha_z = d.z_accel[0].head<3>(), a_z = d.z_accel[0].tail<3>();
  const Mat3 Ta = skew(alpha_z), Tl = skew(a_z);
  Mat6 M0;
  M0 << I0.A + d.row_ang[0] + Z0.A * Ta + Z0.B * Tl, I0.B + d.row_lin[0],
      d.inertia_lower[0] + d.inertia_z_lower[0] * Ta + Z0.C * Tl, I0.C;
  Vec6 rhs = -d.bias_force[0];
  rhs.head<3>() += d.joint_torque[0];
  if (!symmetric_part_positive(M0)) d.pose_terms_positive = false;
  const Eigen::PartialPivLU<Mat6> lu(M0);  // fixed size: on the stack
  d.accel_spatial[0] = lu.solve(rhs);
  const Vec3 alpha0 = d.accel_spatial[0].head<3>();
  d.z_spatial[0] << alpha_z.cross(alpha0), a_z.cross(alpha0);
  d.root_accel_world = d.accel_spatial[0].tail<3>() + s.omega_world[0].cross(s.vel_world[0]);
  d.joint_accel_local[0] = s.frames.orient_world[0].conjugate() * alpha0;

  for (int i = 1; i < rig.nbone; ++i) {
    const int p = rig.bone_joint_parent[i];
    const JointType type = rig.joint_type(i, d.locked_axes);
    const Vec3 r = d.point_world[i] - d.point_world[p];
    const Vec6& ap = d.accel_spatial[p];
    const Vec6& zp = d.z_spatial[p];
    const Vec3 alpha = ap.head<3>() + d.bias_accel[i].head<3>();
    const Vec3 lin = ap.tail<3>() - r.cross(ap.head<3>()) + d.bias_accel[i].tail<3>();
    const Vec3 z_ang = zp.head<3>();
    const Vec3 z_lin = zp.tail<3>() - r.cross(zp.head<3>());
    if (type == JointType::kWeld) {  // moves with its joint parent
      d.accel_spatial[i] << alpha, lin;
      d.z_spatial[i] << z_ang, z_lin;
      d.joint_accel_local[i].setZero();
      continue;
    }
    const SpatialInertia& IA = d.inertia_art[i];
    const SpatialInertia& IZ = d.inertia_z[i];
    const Vec3 qdd = d.D_inv[i] * (d.u[i] - (IA.A + d.row_ang[i]) * alpha -
                                   (IA.B + d.row_lin[i]) * lin - IZ.A * z_ang - IZ.B * z_lin);
    d.accel_spatial[i] << alpha + qdd, lin;
    const Vec6& za = d.z_accel[i];
    d.z_spatial[i] << z_ang + za.head<3>().cross(qdd), z_lin + za.tail<3>().cross(qdd);
    if (type == JointType::kBall) {
      d.joint_accel_local[i] = s.frames.orient_world[i].conjugate() * qdd;
      continue;
    }
    if (type == JointType::kUniversal) {  // turn_blocks' share: z_axis_turn (s1 . qdd)
      d.z_spatial[i].head<3>() += d.z_axis_turn[i] * d.axis1_world[i].dot(qdd);
    }
    d.joint_accel_local[i] << d.axis0_world[i].dot(qdd), d.axis1_world[i].dot(qdd), 0.0;
  }
}

}  // namespace

void articulated_backward_pass(const Rig& rig, ArticulatedBodyData& d) {
  if (d.pose_terms) {
    backward_pass_pose_terms(rig, d);
    return;
  }
  const bool ball = !d.joint_blocks;  // every J = 0: I^A stays symmetric, E = B^T
  if (!ball) {
    // E starts as each body's own (symmetric) B^T; children add theirs below
    for (int i = 0; i < rig.nbone; ++i) d.inertia_lower[i] = d.inertia_art[i].B.transpose();
  }
  for (int i = rig.nbone - 1; i > 0; --i) {
    const int p = rig.bone_joint_parent[i];
    const Vec3 r = d.point_world[i] - d.point_world[p];  // to the parent's point
    const JointType type = rig.joint_type(i, d.locked_axes);
    if (type == JointType::kWeld) {
      weld_to_parent(d, i, p, r, !ball);
      continue;
    }
    const Vec3 u = -d.bias_force[i].head<3>();
    d.u[i] = u;
    if (type != JointType::kBall) {
      hinge_to_parent(rig, d, i, p, r, u, !ball);
      continue;
    }
    if (ball) {
      ball_to_parent(d, i, p, r);
      continue;
    }
    Vec3 pa_ang, pa_lin;
    general_to_parent(d, i, p, r, u, pa_ang, pa_lin);
    d.bias_force[p].head<3>() += pa_ang + r.cross(pa_lin);
    d.bias_force[p].tail<3>() += pa_lin;
  }
}

namespace {

// the root's spatial acceleration a_0 about o_0 by its joint to the world: a free root's
// I^A a = -p^A (LDL^T; LU with joint blocks); a pinned root's ball, qdd = D^-1 (u - S'^T I^A c),
// D = A (+ J), its hinge or universal joint the same with P for D^-1; a fixed root's none
void root_acceleration(const Rig& rig, ArticulatedBodyData& d) {
  const SpatialInertia& I0 = d.inertia_art[0];
  const JointType type = rig.joint_type(0, d.locked_axes);
  switch (type) {
    case JointType::kFree:
      if (d.joint_blocks) {
        Mat6 M0;
        M0 << I0.A, I0.B, d.inertia_lower[0], I0.C;
        const Eigen::PartialPivLU<Mat6> lu(M0);  // fixed size: on the stack
        d.accel_spatial[0] = lu.solve(-d.bias_force[0]);
      } else {
        const Eigen::LDLT<Mat6> ldlt(I0.matrix());
        d.accel_spatial[0] = ldlt.solve(-d.bias_force[0]);
      }
      return;
    case JointType::kBall:
    case JointType::kHinge:
    case JointType::kUniversal: {
      const Vec6& c = d.bias_accel[0];
      const Mat3 AJ = d.joint_blocks ? Mat3(I0.A + d.joint_block[0]) : I0.A;
      d.D_inv[0] = type == JointType::kBall ? Mat3(AJ.inverse())
                                            : axis_projector(AJ, d.axis0_world[0], d.axis1_world[0],
                                                             type == JointType::kHinge);
      d.u[0] = -d.bias_force[0].head<3>();
      const Vec3 qdd = d.D_inv[0] * (d.u[0] - I0.A * c.head<3>() - I0.B * c.tail<3>());
      d.accel_spatial[0] << c.head<3>() + qdd, c.tail<3>();
      return;
    }
    case JointType::kWeld:
      d.accel_spatial[0].setZero();
      return;
  }
}

}  // namespace

void articulated_forward_pass(const Rig& rig, const BodyMotion& s, ArticulatedBodyData& d) {
  if (rig.nbone == 0) return;
  if (d.pose_terms) {
    forward_pass_pose_terms(rig, s, d);
    return;
  }
  root_acceleration(rig, d);
  // the classical acceleration of the root's centre: a.lin + alpha x e + w x v_com (e = 0 for a
  // free root, whose point is its centre)
  const Vec3 alpha0 = d.accel_spatial[0].head<3>();
  d.root_accel_world = d.accel_spatial[0].tail<3>() + s.omega_world[0].cross(s.vel_world[0]);
  if (rig.bone_joint_type[0] != JointType::kFree) {
    d.root_accel_world += alpha0.cross(Vec3(s.com_world[0] - d.point_world[0]));
  }
  const JointType root = rig.joint_type(0, d.locked_axes);
  if (root == JointType::kHinge || root == JointType::kUniversal) {
    const Vec3 qdd = alpha0 - d.bias_accel[0].head<3>();
    d.joint_accel_local[0] << d.axis0_world[0].dot(qdd), d.axis1_world[0].dot(qdd), 0.0;
  } else {
    d.joint_accel_local[0] = s.frames.orient_world[0].conjugate() * alpha0;
  }

  for (int i = 1; i < rig.nbone; ++i) {
    const int p = rig.bone_joint_parent[i];
    const Vec3 r = d.point_world[i] - d.point_world[p];
    const Vec6& ap = d.accel_spatial[p];
    const Vec3 alpha = ap.head<3>() + d.bias_accel[i].head<3>();
    const Vec3 lin = ap.tail<3>() - r.cross(ap.head<3>()) + d.bias_accel[i].tail<3>();
    const JointType type = rig.joint_type(i, d.locked_axes);
    if (type == JointType::kWeld) {  // moves with its joint parent
      d.accel_spatial[i] << alpha, lin;
      d.joint_accel_local[i].setZero();
      continue;
    }
    // qdd' = D^-1 (u - S'^T I^A a'),  S'^T I^A a' = A alpha + B lin (a hinge's: P for D^-1)
    const SpatialInertia& IA = d.inertia_art[i];
    const Vec3 qdd = d.D_inv[i] * (d.u[i] - IA.A * alpha - IA.B * lin);  // world axes
    d.accel_spatial[i] << alpha + qdd, lin;
    if (type == JointType::kBall) {
      d.joint_accel_local[i] = s.frames.orient_world[i].conjugate() * qdd;
    } else {  // qdd = S t'': the angles' accelerations
      d.joint_accel_local[i] << d.axis0_world[i].dot(qdd), d.axis1_world[i].dot(qdd), 0.0;
    }
  }
}

}  // namespace physik
