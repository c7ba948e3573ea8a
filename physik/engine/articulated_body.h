// Exact articulated dynamics in O(n): Featherstone's articulated-body algorithm (ABA).
// Source: R. Featherstone, Rigid Body Dynamics Algorithms, Springer 2008, ch. 7 (Table 7.1, the
// multi-DOF form of eq. 7.36-7.43); spatial algebra of ch. 2.
//
// Tree (docs/engine.md "The exact scheme"): the rig's bones, a free root (6 DOF at its
// centre of mass, as MuJoCo's free joint) and at every other bone's head a ball joint (3 DOF), a
// hinge (1), a universal joint (2: two hinges in sequence) or a weld (0), as the rig's locked
// axes say (rig.h "Locked axes"; or balls throughout with LockedAxes::kSprings): exactly the
// reference's MuJoCo model (reference/mjcf_export.h), in MuJoCo's coordinates:
//   root   qvel = (v_com world, w local),  qacc = (a_com world, d/dt w_local = R^T alpha)
//   ball i qvel = u_i = R_i^T (w_i - w_parent)  (relative angular velocity in the child's frame)
//   hinge, universal i  qvel = (t0', t1'), the hinge angles' rates (joint_coordinates.h), and
//          w_i - w_parent = S t' with S = [s0 s1] the joints' world axes (orthonormal)
//
// Frames. Every spatial quantity of body i is in world-aligned axes about a point o_i that moves
// with the body: its joint point (the head) for i > 0, its centre of mass for the root. Motion
// vectors are (w; v_o), force vectors (n_o; f) (torque about o_i). Neighbouring points are one
// bone apart, so the numbers stay moderate on long chains, and the transform between a child's
// and its parent's point is a pure translation r = o_i - o_p:
//   motion  X (w; v) = (w; v - r x w),    force  X* (n; f) = (n + r x f; f)   (child -> parent)
// With the joint at o_i, a ball's motion subspace is S = [R_i; 0] (u in the child's frame), so
// with S' = [1; 0] everything below is in world axes and u_dot = R_i^T qdd' at the end.
// A hinge or universal joint's is S' = [S; 0]: where a ball's pass has D^-1 (D = S'^T I^A S' + J
// below), it has the projector P = S (S^T (A + J) S)^-1 S^T (3x3, rank 1 or 2; D_inv holds it),
// so qdd' = P (...) is S t'' and t''_k = s_k . qdd' at the end; every formula is the ball's with
// D^-1 replaced by P, and I^a keeps the torque the locked directions carry
// (I^a = I^A - [A; E] P [A B], computed as that difference: its angular blocks are not zero).
//
// Pass 1, velocities and bias (any order):
//   I_i  = [I_c + m [e]x [e]x^T, m [e]x; m [e]x^T, m 1]      e = com_i - o_i, rigid inertia about
//   o_i p_i  = V_i x* I_i V_i - f_ext_i                          V_i = (w_i; v_o), f_ext about o_i
//        = (w x I_c w + e x (m w x v_com); m w x v_com) - (n_com + e x F; F)
//   c_i  = V_i x (S u) = (w_i x w_rel; v_o x w_rel)          w_rel = w_i - w_parent   (ball)
//        = the same + (t0' t1' s0 x s1; 0)    (universal: s0 turns with the parent, not the bone)
//   c_0  = (0; -w x v_com)                                   (root, spatial vs classical accel.)
// Pass 2, leaves to root (articulated inertia I^A = [A B; E C], E = B^T while every joint block
// is symmetric; bias p^A; J_i an optional 3x3 joint block, world axes, not necessarily symmetric):
//   U = I^A S' = [A; E] (column),  S'^T I^A = [A B] (row),  D = A + J_i,  u = -S'^T p^A
//   I^a = I^A - U D^-1 S'^T I^A = [A D^-1 J, J D^-1 B; E D^-1 J, C - E D^-1 B]
//   p^a = p^A + I^a c + U D^-1 u
//   I^A_parent += X* I^a X,  p^A_parent += X* p^a
// (Schur complements of the joint's block: no symmetry is needed, only D invertible, which the
// implicit step's blocks guarantee by keeping their symmetric parts positive semi-definite:
// implicit_step.h.) A ball
// (J = 0) passes on only the translational block C - E A^-1 B, exactly: computing the top blocks
// as differences leaves round-off there that doubles with every link (on a long chain it
// swamps the root's inertia), so they are products. Without joint
// blocks every I^A stays symmetric and the pass keeps only [A B; . C]; with them it carries E
// (inertia_lower), as a non-symmetric block (the paper's torsion torque's tangent,
// implicit_step.h) makes the articulated inertias of its ancestors general 6x6 matrices.
// Pass 3, root to leaves (spatial accelerations a_i):
//   root:  a_0 = -(I^A_0)^-1 p^A_0 (LDL^T; LU with joint blocks),  alpha = a_0.ang,
//          a_com = a_0.lin + w x v_com
//   ball:  a' = X a_parent + c,  qdd' = D^-1 (u - S'^T I^A a'),  a_i = a' + S' qdd',  u_dot = R^T
//   qdd'   (hinge, universal: P for D^-1, t''_k = s_k . qdd')
// A spatial acceleration a about o is Featherstone's (the derivative of the velocity field at the
// fixed point o); the classical acceleration of the centre is a.lin + alpha x e + w x v_com.
//
// External wrench: the state's force_world/torque_world (about each centre of mass, world axes),
// plus torque_per_omega * I w on every body (a rotational damper; the factor f's torque
// I (f - 1) w / dt) and, with cancel_gyroscopic, +w x I w.
//
// Extension points, for the implicit step (docs/engine.md "The implicit scheme":
// M + h D + h^2 K is the same tree with augmented inertias): after articulated_velocity_pass, a
// caller may add spatial inertia to inertia_art[i] (SpatialInertia::add; about o_i, world axes),
// set joint_block[i] (world axes) with joint_blocks = true, and change bias_force, before
// articulated_backward_pass; nothing else changes.
//
// No allocation per step: every buffer is sized once by resize_articulated_data.
// Units: kg, kg m^2, N, N m, rig units, s, rad.
#pragma once

#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include "physik/model/kinematics.h"
#include "physik/model/rig.h"

namespace physik {

// What the recursion reads of a state (state.h body_motion): the bodies' derived kinematics and
// the wrench on them, as references into the state, which outlives the view.
struct BodyMotion {
  const BoneFrames& frames;               // world, rig units
  const std::vector<Vec3>& com_world;     // (nbone) rig units
  const std::vector<Vec3>& vel_world;     // (nbone) rig units/s
  const std::vector<Vec3>& omega_world;   // (nbone) rad/s
  const std::vector<Vec3>& force_world;   // (nbone) N, at the centre of mass
  const std::vector<Vec3>& torque_world;  // (nbone) N m, about it
};

using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;

// A spatial inertia about a point, world axes, by 3x3 blocks [A B; B^T C] (A angular,
// C translational): contiguous blocks for the recursion's 3x3 algebra. Symmetric as built and as
// augmented (add, implicit_step.h); with joint blocks the backward pass makes the articulated
// inertias general, their lower-left block in ArticulatedBodyData::inertia_lower (then matrix(),
// which assumes B^T there, does not describe them).
struct SpatialInertia {
  Mat3 A = Mat3::Zero();  // kg m^2
  Mat3 B = Mat3::Zero();  // kg m
  Mat3 C = Mat3::Zero();  // kg
  Mat6 matrix() const;
  void add(const Mat6& I);  // I symmetric: adds its blocks
};

struct ArticulatedBodyData {
  // --- inputs besides the state ---
  // the joint model: the rig's locked axes removed (the exact and implicit schemes) or every
  // bone that is not welded a ball (the gauss-seidel scheme's, for damping auto's modes)
  LockedAxes locked_axes = LockedAxes::kRemoved;
  double torque_per_omega = 0.0;   // 1/s: torque torque_per_omega * I w on every body
  bool cancel_gyroscopic = false;  // add +w x I w on every body (gyroscopic term off)
  bool joint_blocks = false;       // add joint_block[i] to D_i (the implicit step's K)
  std::vector<Mat3> joint_block;   // (nbone) 3x3, world axes, read when joint_blocks; need
                                   //         not be symmetric

  // --- pass 1 (velocity pass) ---
  std::vector<Mat3> inertia_com_world;  // (nbone) R diag(I_local) R^T, kg m^2
  std::vector<Vec3> axis0_world;        // (nbone) a hinge's or universal's s0, world
  std::vector<Vec3> axis1_world;        // (nbone) a universal's s1 (joint_coordinates.h)
  std::vector<Vec3> point_world;  // (nbone) o_i: head (i > 0) or centre of mass (root), rig units
  std::vector<Vec6> bias_accel;   // (nbone) c_i, rad/s^2; rig units/s^2
  std::vector<SpatialInertia> inertia_art;  // (nbone) I^A_i about o_i; rigid after pass 1
  std::vector<Vec6> bias_force;             // (nbone) p^A_i about o_i, (N m; N)
  std::vector<Vec3> torque_ext_world;       // (nbone) the external torque about the centre, N m
                                            //         (torque_world + the damper [+ w x I w])

  // --- pass 2 (backward pass) ---
  std::vector<Mat3> D_inv;          // (nbone) (S'^T I^A S' + J)^-1, a hinge's or universal's
                                    //         projector P; the forward pass reads
                                    //         the row S'^T I^A = [A B] from inertia_art
  std::vector<Vec3> u;              // (nbone) -S'^T p^A
  std::vector<Mat3> inertia_lower;  // (nbone) E, I^A's lower-left block, kg m; written only
                                    //         with joint_blocks (else E = B^T)
  // --- the implicit step's pose terms (implicit_linearisation full; implicit_pose_terms.h) ---
  // With pose_terms the backward and forward passes solve, per joint i (S' = [1; 0]),
  //   S'^T (I^A_i a_i + I^Z_i z_i + p^A_i) + G_i a_i + J_i qdd'_i = joint_torque_i
  //   a_i = X a_p + c_i + S' qdd'_i,   z_i = X z_p + T_i qdd'_i,   T_i = [[alpha]x; [a]x]
  // where G_i = [row_ang, row_lin] is a term of joint i's own row only (not handed to the
  // parent), z a second motion vector carried root to leaves (its inertia I^Z, handed to the
  // parent as I^A is), (alpha; a) = z_accel[i] about o_i. The root:
  //   (I^A_0 + [G_0; 0] + I^Z_0 T_0) a_0 = -p^A_0 + [joint_torque_0; 0],  z_0 = T_0 a_0,
  //   T_0 = [[alpha]x, 0; [a]x, 0]
  // (T_0 c_0 = 0: the root's bias acceleration has no angular part). The caller sets
  // inertia_lower (E, every body: the pass does not start it from B^T), inertia_z and its
  // lower block, row_ang, row_lin, joint_torque and z_accel. With every one of them zero this is
  // the general pass above.
  bool pose_terms = false;
  // the last pass with pose_terms: every pivot's symmetric part, and the root 6x6's, positive
  // definite
  bool pose_terms_positive = true;
  std::vector<SpatialInertia> inertia_z;  // (nbone) I^Z_i about o_i: A, B, C blocks, kg m^2 ...
  std::vector<Mat3> inertia_z_lower;      // (nbone) its lower-left block, kg m
  std::vector<Mat3> row_ang, row_lin;     // (nbone) G_i = [row_ang row_lin], N m; N m/(rig unit)
  std::vector<Vec3> joint_torque;         // (nbone) world axes, N m
  std::vector<Vec6> z_accel;              // (nbone) (alpha; a) of T_i, rad/s^2; rig units/s^2
  std::vector<Vec3> z_axis_turn;          // (nbone) a universal joint's T_i angular block adds
                                          //   z_axis_turn s1^T (implicit_pose_terms.h), rad/s^2
  std::vector<Vec6> z_spatial;            // (nbone) z_i (forward pass), same units

  // --- pass 3 (forward pass): MuJoCo's qacc layout ---
  std::vector<Vec6> accel_spatial;       // (nbone) a_i about o_i
  Vec3 root_accel_world = Vec3::Zero();  // classical acceleration of the root's centre of mass
  std::vector<Vec3> joint_accel_local;   // (nbone) root: R^T alpha; ball: u_dot; hinge,
                                         //   universal: (t0'', t1'', 0), rad/s^2
};

void resize_articulated_data(int nbone, ArticulatedBodyData& data);

// Pass 1 from the state's derived kinematics (frames, com_world, vel_world, omega_world) and
// wrench (force_world, torque_world), with the inputs above.
void articulated_velocity_pass(const Rig& rig, const BodyMotion& state, ArticulatedBodyData& data);
// Pass 2: leaves to root.
void articulated_backward_pass(const Rig& rig, ArticulatedBodyData& data);
// Pass 3: root to leaves; the joint accelerations in MuJoCo's coordinates.
void articulated_forward_pass(const Rig& rig, const BodyMotion& state, ArticulatedBodyData& data);

// The three passes.
inline void articulated_accelerations(const Rig& rig, const BodyMotion& state,
                                      ArticulatedBodyData& data) {
  articulated_velocity_pass(rig, state, data);
  articulated_backward_pass(rig, data);
  articulated_forward_pass(rig, state, data);
}

// P = S (S^T M S)^-1 S^T for a joint's world axes s0 (and s1 unless `one`), M = A (+ J) (3x3):
// the hinge's or universal's D^-1 (above); M's quadratic form on the axes must be invertible.
Mat3 axis_projector(const Mat3& M, const Vec3& s0, const Vec3& s1, bool one);

// Rigid-body spatial inertia about a point o, world axes; e = com - o.
SpatialInertia spatial_inertia(double mass, const Mat3& inertia_com_world, const Vec3& e);

}  // namespace physik
