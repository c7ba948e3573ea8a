// Cyclic coordinate descent, one rotation axis at a time, with limits and the colinearity bump.
//
// Source: the IK guide (seed 001), "Cyclic Coordinate Descent Solver" and "Advice". World frame,
// rig units, angles in radians.
//
// One iteration is one sweep over the active bones from the effectors towards the root (reverse
// DFS order), and for each bone over its free local axes k = x, y, z (locked axes are skipped).
// For axis k of bone i the rotation axis is a = P_i e_k (P_i = the bone's rest frame under its
// parent's current orientation) through the bone's head h_i. Every goal below the bone
// (effector point p_j, target t_j) is projected onto the plane normal to a:
//     e_j = (p_j - h_i) - a (a . (p_j - h_i)),   g_j = (t_j - h_i) - a (a . (t_j - h_i))
// and the angle is the guide's GetTheta generalised to several effectors, which is the exact
// minimiser of sum_j |R_a(theta) e_j - g_j|^2:
//     theta = atan2( sum_j a . (e_j x g_j),  sum_j e_j . g_j )
// (one effector: the guide's atan2(sin, cos) of the 2D projections; no effector length: skip).
// The bone turns by theta about a (q_i <- exp(theta e_k) q_i), then
//   - min/max limits: the rotation vector of q_i is clamped to the rig's box (clamp_to_limits);
//   - colinearity (guide: "store the angle that would make the joint colinear with its parent and
//     bump the result if it is equal to this value"): if the bone ends colinear with its parent,
//     theta gets `colinear_bump` added before clamping.
// The effector points below the bone are rotated with it, so the next axis and the next bone up
// see the effect at once; ancestors' frames do not change until their own turn.
#include <cmath>

#include "physik/ik/ik_solver.h"

namespace physik {

IkReport solve_ccd(const IkProblem& pb, Pose& pose) {
  const Rig& rig = *pb.rig;
  const int n = rig.nbone;
  const int ng = static_cast<int>(pb.goals.size());
  // goals_below[i]: goals whose bone is i or a descendant of i
  std::vector<std::vector<int>> goals_below(n);
  for (int k = 0; k < ng; ++k) {
    for (int b = pb.goals[k].bone; b >= 0; b = rig.bone_parent[b]) goals_below[b].push_back(k);
  }
  std::vector<Vec3> point(ng);
  const double bump = pb.options.colinear_bump;

  auto iterate = [&](Pose& p, BoneFrames& f) {
    for (int k = 0; k < ng; ++k) point[k] = point_on_bone(f, pb.goals[k].bone, pb.goals[k].alpha);
    for (int i = n - 1; i >= 0; --i) {
      if (!pb.active[i]) continue;
      const int par = rig.bone_parent[i];
      const Quat P = rest_frame_world(rig, f, i);
      const Vec3& h = f.head_world[i];
      for (int axis = 0; axis < 3; ++axis) {
        const bool limited = pb.options.respect_limits;  // the root's limits too
        if (limited && rig.bone_limit[i][axis].locked()) continue;
        const Vec3 a = P * Vec3::Unit(axis);
        double s = 0.0, c = 0.0;
        for (int k : goals_below[i]) {
          Vec3 e = point[k] - h, g = pb.goals[k].target_world - h;
          e -= a * a.dot(e);
          g -= a * a.dot(g);
          s += a.dot(e.cross(g));
          c += e.dot(g);
        }
        if (s == 0.0 && c == 0.0) continue;
        double theta = std::atan2(s, c);
        const Quat q_old = p.bone_local_rotation[i];
        auto turned = [&](double th) {
          Quat q = (Quat(Eigen::AngleAxisd(th, Vec3::Unit(axis))) * q_old).normalized();
          return limited ? clamp_to_limits(rig, i, q) : q;
        };
        Quat q_new = turned(theta);
        if (par >= 0 && axis != 1 && bump > 0.0) {
          const Vec3 d = P * (q_new * Vec3::UnitY());
          const Vec3 d_parent = f.orient_world[par] * Vec3::UnitY();
          if (d.cross(d_parent).norm() < 1e-6 && d.dot(d_parent) > 0.0)
            q_new = turned(theta + bump);
        }
        // world rotation actually applied (after clamping): delta = P q_new q_old^-1 P^-1
        const Quat delta = (P * q_new * q_old.conjugate() * P.conjugate()).normalized();
        for (int k : goals_below[i]) point[k] = h + delta * (point[k] - h);
        p.bone_local_rotation[i] = q_new;
      }
    }
  };
  return run_ik_loop("ccd", pb, pose, iterate);
}

}  // namespace physik
