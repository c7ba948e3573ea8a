// Jacobian transpose and damped least squares, with an analytic or a memoised finite-difference
// Jacobian, and clamping to joint limits.
//
// Source: the IK guide (seed 001), "Jacobian solver" (a. transpose, b. J^T e, c. J J^T,
// d. the solver); step length of the transpose method and DLS as in Buss, "Introduction to
// inverse kinematics with Jacobian transpose, pseudoinverse and damped least squares methods"
// (2004). World frame, rig units, radians.
//
// Unknowns: one angle per free local axis k of every active bone j (locked axes left out); a
// change theta turns the bone about a = P_j e_k through its head h_j (q_j <- exp(theta e_k) q_j).
// Stacked goal points p (3 per goal), error e = t - p.
//   analytic column:   dp_g/dtheta = a x (p_g - h_j)   if bone j is on goal g's path, else 0
//   finite difference (the guide's memoised secant): the subtree below joint j is rigid, so the
//     perturbed effector is h_j + exp(eps a)(p_g - h_j) -- the guide's _0ToI * joint * _iToN
//     without re-running FK -- and the column is (that - p_g) / eps. O(n) per column pass.
//   transpose: dtheta = alpha J^T e,  alpha = <e, J J^T e> / |J J^T e|^2  (Buss eq. 7)
//   DLS:       dtheta = J^T (J J^T + lambda^2 I)^-1 e      (guide d.; 3m x 3m for m goals)
//              = (J^T J + lambda^2 I)^-1 J^T e            (n x n for n unknowns: used when 3m > n)
//   error clamping (Buss Sec. 6, D_max): each goal's error is shortened to at most
//     max_error_fraction of the reach, so a far (unreachable) target does not throw DLS's
//     linearisation far out of its range; the step then follows the clamped error;
//   line search: the step is halved (at most max_step_halvings times) while it does not lower
//     sum_g |t_g - p_g|^2; without it DLS on a 50-bone chain oscillates for far targets;
//   step: scaled so that max |dtheta| <= max_angle_step; applied per bone as the rotation
//     vector (dtheta_x, dtheta_y, dtheta_z) in its rest frame; then clamped to the rig's limits
//     (guide: "apply the adjustment and clamp to the joint limits").
// lambda is in rig units (J has units of length per radian); default 0.02 of the reach.
//
// Orientation rows (a goal with a target orientation R_t, world<-bone): error phi = log(R_t R^T)
// (world axes, rad; the orientation targets' error, physik/engine/orientation_springs.h), rows
// the angular Jacobian: a turn theta about a = P_j e_k turns every bone below j, so
//   d(orientation)/dtheta = a   if bone j is on the goal's path (itself included), else 0
// (the finite difference gives the same column: log(exp(eps a)) / eps = a). phi changes by
// -J_r^-1(phi) a, which is -a to first order in phi (Sola et al., arXiv:1812.01537): the usual
// Gauss-Newton approximation of the rotation error, exact at the solution. Rows and error are
// scaled by a length L (IkOptions::orientation_length, default the chain's reach) into rig
// units, so a turn phi of the goal's frame weighs as the displacement L |phi| of the chain's far
// end: position and orientation rows mix in one least-squares problem, and lambda, the error
// clamp and the line search's squared error (sum |t - p|^2 + L^2 |phi|^2) read both alike.
// Position rows come first (3 per goal with a position), then the orientation rows (3 per goal
// with one): a position-only problem is the one above, bit for bit.
#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

#include "physik/ik/ik_solver.h"

namespace physik {

void goal_jacobian(const IkProblem& pb, const BoneFrames& f, const std::vector<int>& dof_bone,
                   const std::vector<int>& dof_axis, JacobianKind kind, double fd_step,
                   Eigen::MatrixXd& J) {
  const Rig& rig = *pb.rig;
  const int ng = static_cast<int>(pb.goals.size());
  const int nd = static_cast<int>(dof_bone.size());
  int npos = 0, nori = 0;
  for (const IkGoal& g : pb.goals) {
    npos += g.has_position ? 1 : 0;
    nori += g.has_orientation ? 1 : 0;
  }
  J.setZero(3 * (npos + nori), nd);
  for (int c = 0; c < nd; ++c) {
    const int j = dof_bone[c];
    const Vec3 a = rest_frame_world(rig, f, j) * Vec3::Unit(dof_axis[c]);
    const Vec3& h = f.head_world[j];
    const Quat step(Eigen::AngleAxisd(fd_step, a));
    int prow = 0, orow = 3 * npos;
    for (int g = 0; g < ng; ++g) {
      const IkGoal& goal = pb.goals[g];
      const int p_at = goal.has_position ? prow : -1;
      const int o_at = goal.has_orientation ? orow : -1;
      prow += goal.has_position ? 3 : 0;
      orow += goal.has_orientation ? 3 : 0;
      // bone j must be on goal g's root path
      int b = goal.bone;
      while (b > j) b = rig.bone_parent[b];
      if (b != j) continue;
      if (p_at >= 0) {
        const Vec3 r = point_on_bone(f, goal.bone, goal.alpha) - h;
        J.block<3, 1>(p_at, c) =
            kind == JacobianKind::kAnalytic ? Vec3(a.cross(r)) : Vec3((step * r - r) / fd_step);
      }
      if (o_at >= 0) J.block<3, 1>(o_at, c) = pb.orientation_length * a;
    }
  }
}

namespace {

// the goals' squared error at frames f (rig units^2): positions, then L^2 |phi|^2
double sq_error(const IkProblem& pb, const BoneFrames& f) {
  double s = 0.0;
  for (const IkGoal& g : pb.goals)
    if (g.has_position) s += (g.target_world - point_on_bone(f, g.bone, g.alpha)).squaredNorm();
  if (!pb.any_orientation) return s;
  const double L2 = pb.orientation_length * pb.orientation_length;
  for (const IkGoal& g : pb.goals)
    if (g.has_orientation) s += L2 * goal_orientation_error(f, g).squaredNorm();
  return s;
}

// the step in joint angles: damped least squares (damped) or the Jacobian transpose scaled by
// Buss's optimal alpha = <e, J J^T e> / |J J^T e|^2
void joint_step(const Eigen::MatrixXd& J, const Eigen::VectorXd& e, bool damped, double lambda,
                Eigen::VectorXd& dtheta) {
  const int nd = static_cast<int>(J.cols());
  if (damped && J.rows() > nd && lambda > 0.0) {
    // more goal rows than unknowns: the same step from the nd x nd system (push-through
    // identity J^T (J J^T + l^2 I)^-1 = (J^T J + l^2 I)^-1 J^T), so 20,000 goals do not ask for
    // a 60,000^2 matrix
    Eigen::MatrixXd JtJ = J.transpose() * J;
    JtJ.diagonal().array() += lambda * lambda;
    dtheta = JtJ.ldlt().solve(J.transpose() * e);
  } else if (damped) {
    Eigen::MatrixXd JJt = J * J.transpose();
    JJt.diagonal().array() += lambda * lambda;
    dtheta = J.transpose() * JJt.ldlt().solve(e);
  } else {
    const Eigen::VectorXd Jte = J.transpose() * e;
    const Eigen::VectorXd JJte = J * Jte;
    const double den = JJte.squaredNorm();
    dtheta = den > 0.0 ? Eigen::VectorXd(Jte * (e.dot(JJte) / den)) : Eigen::VectorXd(Jte * 0.0);
  }
}

// The step per bone onto `p` (from its value on entry), clamped to the limits; halved while it
// makes the goals' squared error worse (a backtracking line search: far from the goal the
// linearisation overshoots). turn and trial are scratch.
void apply_step(const IkProblem& pb, const std::vector<int>& dof_bone,
                const std::vector<int>& dof_axis, const BoneFrames& f, Eigen::VectorXd& dtheta,
                Pose& p, std::vector<Vec3>& turn, BoneFrames& trial) {
  const Rig& rig = *pb.rig;
  const IkOptions& opt = pb.options;
  const int nd = static_cast<int>(dof_bone.size());
  const Pose start = p;
  const double err0 = sq_error(pb, f);
  for (int halving = 0; halving <= opt.max_step_halvings; ++halving) {
    p = start;
    for (int c = 0; c < nd; ++c) turn[dof_bone[c]].setZero();
    for (int c = 0; c < nd; ++c) turn[dof_bone[c]][dof_axis[c]] = dtheta[c];
    for (int c = 0; c < nd; ++c) {
      const int j = dof_bone[c];
      if (c > 0 && dof_bone[c - 1] == j) continue;  // once per bone
      Quat q = (quat_from_rotation_vector(turn[j]) * p.bone_local_rotation[j]).normalized();
      if (opt.respect_limits) q = clamp_to_limits(rig, j, q);
      p.bone_local_rotation[j] = q;
    }
    if (opt.max_step_halvings == 0) break;
    forward_kinematics(rig, p, trial);
    if (sq_error(pb, trial) < err0) break;
    dtheta *= 0.5;
  }
}

}  // namespace

IkReport solve_jacobian(const IkProblem& pb, bool damped, Pose& pose) {
  const Rig& rig = *pb.rig;
  const IkOptions& opt = pb.options;
  std::vector<int> dof_bone, dof_axis;
  ik_dofs(rig, pb.active, opt.respect_limits, dof_bone, dof_axis);
  const int ng = static_cast<int>(pb.goals.size());
  const int nd = static_cast<int>(dof_bone.size());
  const double lambda = opt.lambda > 0.0 ? opt.lambda : opt.lambda_fraction * pb.reach;
  int nrow = 0;
  for (const IkGoal& g : pb.goals)
    nrow += 3 * ((g.has_position ? 1 : 0) + (g.has_orientation ? 1 : 0));
  Eigen::MatrixXd J(nrow, nd);
  Eigen::VectorXd e(nrow), dtheta(nd);
  std::vector<Vec3> turn(rig.nbone);
  BoneFrames trial;
  auto iterate = [&](Pose& p, BoneFrames& f) {
    const double cap = opt.max_error_fraction * pb.reach;
    int row = 0;
    for (int g = 0; g < ng; ++g) {
      if (!pb.goals[g].has_position) continue;
      Vec3 err = pb.goals[g].target_world - point_on_bone(f, pb.goals[g].bone, pb.goals[g].alpha);
      if (cap > 0.0 && err.norm() > cap) err *= cap / err.norm();  // Buss's error clamping
      e.segment<3>(row) = err;
      row += 3;
    }
    for (int g = 0; g < ng; ++g) {  // L phi, clamped alike
      if (!pb.goals[g].has_orientation) continue;
      Vec3 err = pb.orientation_length * goal_orientation_error(f, pb.goals[g]);
      if (cap > 0.0 && err.norm() > cap) err *= cap / err.norm();
      e.segment<3>(row) = err;
      row += 3;
    }
    goal_jacobian(pb, f, dof_bone, dof_axis, opt.jacobian, opt.fd_step, J);
    joint_step(J, e, damped, lambda, dtheta);
    const double biggest = nd > 0 ? dtheta.cwiseAbs().maxCoeff() : 0.0;
    if (biggest > opt.max_angle_step) dtheta *= opt.max_angle_step / biggest;
    apply_step(pb, dof_bone, dof_axis, f, dtheta, p, turn, trial);
  };
  return run_ik_loop(damped ? "dls" : "jt", pb, pose, iterate);
}

}  // namespace physik
