// The matrices of the linearised dynamics at a pose (linear_modes.h) as O(n) operators on the
// tree, for the iterative linear modes: the products M x, K x, D1 x, Dr x, and the solve
// (K + s M) x = b by the articulated-body recursion with augmented inertias, as the implicit step
// solves M + h D + h^2 K (implicit_step.h, articulated_body.h). No dense matrix is formed.
//
// Sources: R. Featherstone, Rigid Body Dynamics Algorithms, Springer 2008: ch. 7 (the
// articulated-body algorithm), and the products J^T A J x as one outward velocity pass and one
// inward force pass (ch. 5, the recursive Newton-Euler algorithm's two passes).
//
// Coordinates x (Rig::velocity_count of the scheme's joint model, rig.h "Locked axes"): the
// root's centre-of-mass velocity (world) and angular velocity (world axes), then every ball's
// relative angular velocity w_i - w_parent (world axes), every hinge's or universal's angle
// rates (joint_coordinates.h: w_i - w_parent = S t'). A ball's differ from the dense path's
// (linear_modes_dense.h: local axes) by a rotation per joint, which leaves the modes' w^2 and the
// quadratic forms phi^T D phi of M-normalised modes unchanged (the same orthogonal change of
// coordinates on M, K, D1 and Dr); a hinge's are the dense path's.
//
// Every matrix is J^T E J over bodies, E_i a symmetric 6x6 element about the body's point o_i
// (head, or the root's centre of mass), plus, for K, a 3x3 block per ball:
//   M   E_i = the rigid spatial inertia: f = m (v + w x e), n = I_com w + e x f, e = com - o
//   K   every force's stiffness (forces.h mode_stiffness): point elements on their bodies (the
//       control springs': a point p = o + r moves at v + w x r, pulled by f = K_c (v + w x r),
//       n = r x f), couples on their bodies' own turns (n = K w: the orientation springs') and
//       blocks on the balls' own coordinates (the torsion springs')
//   D1  unit dampers at the head and the tail, the same point elements with K_c = 1
//   Dr  n = (1 - f) / dt I_com w
// Product: velocities outward, V_i = X_i V_parent + (u_i; 0), V_0 = (w_0; v_0); wrenches
// W_i = E_i V_i, summed inward, W_parent += X_i^* W_i; then y_i = W_i.torque (+ the ball block
// times u_i), y_0 = (W_0.force; W_0.torque). One pass each way: O(n), no allocation.
// Solve: (K + s M) x = b is s (M + K / s) x = b: the rigid inertias plus the point elements of K
// over s (add_point_inertia; a couple's K / s joins the angular block), and the balls' blocks over
// s as joint blocks, in articulated_body.h's backward and forward passes at zero velocity (every
// bias acceleration 0); b enters as external torques, b_i on bone i and -b_i on its parent (so that
// J^T of them is b), and the root's (force; torque); x is read from the spatial accelerations. A
// negative s is allowed: the recursion needs only invertible pivots. Count: the backward pass
// eliminates each ball's coordinates in turn, leaves first, and passes the Schur complement of its
// pivot on to the parent (articulated_body.h, pass 2), so H = L diag(P) L^T with unit
// block-triangular L and the pivots P: each ball's 3x3 D_i and the root's 6x6 I^A_0. By Sylvester's
// law of inertia H has as many negative eigenvalues as the pivots together; with H = M - K / sigma
// this counts the modes below sigma (the Wittrick-Williams count: W. H. Wittrick, F. W. Williams,
// Q. J. Mech. Appl. Math. 24(3), 1971; B. N. Parlett, The Symmetric Eigenvalue Problem, 1998,
// sec. 3.3, spectrum slicing).
//
// The buffers live in a ModeWorkspace, which the state keeps (SimState::modes): sized at the
// first update, reused at every later one (the rig does not change during a run).
// Units: kg, N/m, N s/m, rig units, s.
#pragma once

#include <utility>
#include <vector>

#include <Eigen/Core>

#include "physik/engine/mode_workspace.h"
#include "physik/model/scene.h"

namespace physik {

struct SimState;

class ModeOperators {
 public:
  enum class Matrix { kMass, kStiffness, kEndDampers, kFactorDamper };

  // The operators at the state's pose (frames, com_world, pose) with the control springs
  // pulling toward `targets_world` (one per control point). Sizes the workspace (allocates only
  // when it is not sized for this rig yet). The state and workspace must outlive the operators.
  ModeOperators(const Scene& scene, const SimState& state, const std::vector<Vec3>& targets_world,
                ModeWorkspace& workspace);

  int size() const { return nv_; }
  // y = A x for the chosen matrix; no allocation once y has the size
  void multiply(Matrix which, const VecX& x, VecX& y);
  // the shift s > 0 of the solve
  void set_shift(double s);
  double shift() const { return shift_; }
  // x = (K + s M)^-1 b; no allocation once x has the size. s < 0 is allowed (inverse
  // iteration) as long as no pivot is singular
  void solve(const VecX& b, VecX& x);
  // the number of modes with w^2 < sigma (sigma > 0; zero modes included), by the signs of the
  // recursion's pivots of K - sigma M (see the header); keeps the shift
  int count_below(double sigma);
  // the largest diagonal entry of D1 in the dense path's coordinates (linear_modes_dense.h): the
  // scale of its rule "the end dampers do not reach this mode"
  double end_damper_scale() const { return end_damper_scale_; }
  // true when K has no element at all (no control point or bone target, no engaged torsion
  // spring)
  bool stiffness_empty() const {
    return ws_.springs.empty() && ws_.couples.empty() && ws_.torsion.empty();
  }
  ModeWorkspace& workspace() { return ws_; }

 private:
  void element_wrenches(Matrix which);
  // joint i's relative angular velocity (world) from its coordinates in x: a ball's three, a
  // hinge's or universal's angle rates along their axes (joint_coordinates.h); 0 for a weld
  Vec3 rate(int i, const VecX& x) const;
  // S^T torque into joint i's coordinates of y (added, or set)
  void put_torque(int i, const Vec3& torque, bool add, VecX& y) const;
  // the negative eigenvalues of joint i's pivot from its symmetric inverse (count_below)
  int negative_pivots(JointType type, int i, const Mat3& inverse) const;
  void load_inertias();
  void compute_end_damper_scale();

  const Rig& rig_;
  const SimState& state_;
  ModeWorkspace& ws_;
  LockedAxes locked_;  // the scheme's joint model (rig.h "Locked axes")
  int nv_ = 0;
  double shift_ = 1.0;
  double factor_damper_ = 0.0;  // (1 - f) / dt, 1/s
  double end_damper_scale_ = 0.0;
};

}  // namespace physik
