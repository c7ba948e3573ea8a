// The rotation method: "Inverse Kinematics using Simple Physics" (seed 002, Min Zhong, CS 838,
// 2000), sections "Rotation Method", "Looking Natural", "Joint Constraints" and "Major Stumble
// Blocks", on the rig's bones. World frame, rig units, radians.
//
// One iteration serves every goal in DFS order. For a goal (selected point p on bone b, target t)
// the joints from b up to the root are visited in turn (closest first, "we try to move the bones
// closer to the selected joint first"); joint j is bone j turning about its head h_j, at depth
// k = number of joints between it and b (k = 0 for b itself):
//   goal vec        g = t - p
//   springiness     g' = g + s min(1, |g| / L_j) (n_j - tail_j), n_j = the tail at the bone's
//                   natural (rest) orientation under its parent ("adding to the goal vector a
//                   fraction of the distance vector from the joint to its natural position");
//                   the min(...) fades it out at the goal so a reachable goal is still met
//   virtual bone    r = p - h_j
//   bend joint (one free axis k): axis a = P_j e_k (fixed in the parent)
//   socket joint, as shipped: axis a = normalize(r x g'), perpendicular to the goal vector and
//                   the virtual bone
//   socket joint, twist then bend (the author's fix, "decompose any socket joint into a twist
//                   followed by a bend"): first a twist about the bone's own axis y_j (the
//                   CCD angle of p towards p + g' in the plane normal to y_j), then a bend about
//                   a = normalize((r x g') projected normal to y_j), which moves the bone
//                   without twisting it, so the virtual bone cannot drag the orientation along
//   amount          theta = gain damping^k (a . (r_a x g')) / |r_a|^2,  r_a = r - a (a . r):
//                   proportional to the distance from the goal, zero when the (virtual) bone and
//                   the goal vector are aligned ("the proportion constant makes sure the rotation
//                   amount is zero in that case"); damping^k is the exponential damping up the
//                   hierarchy (damping 0: only the selected bone moves); |theta| <= max_angle_step
//   limits          socket: the cone (circular or elliptical) on the swing and the twist range
//                   (clamp_to_cone); then the rig's box limits, which are authoritative
// The selected point is carried along by each turn, so the next joint up sees the effect.
#include <algorithm>
#include <cmath>

#include "physik/ik/ik_solver.h"

namespace physik {

Quat clamp_to_cone(const Rig& rig, int bone, const Quat& q, ConeShape shape) {
  if (shape == ConeShape::kNone || rig.bone_parent[bone] < 0) return q;
  const AxisLimit& lx = rig.bone_limit[bone][0];
  const AxisLimit& ly = rig.bone_limit[bone][1];
  const AxisLimit& lz = rig.bone_limit[bone][2];
  if (!lx.limited || !lz.limited || lx.locked() || lz.locked()) return q;
  // swing-twist: twist = projection of q onto rotations about y; swing = q twist^-1
  Quat twist(q.w(), 0.0, q.y(), 0.0);
  if (twist.norm() < 1e-12) twist = Quat::Identity();
  twist.normalize();
  const Quat swing = (q * twist.conjugate()).normalized();
  Vec3 sv = rotation_vector(swing);
  double ty = rotation_vector(twist).y();
  const double cx = 0.5 * (lx.min + lx.max), cz = 0.5 * (lz.min + lz.max);
  double ax = 0.5 * (lx.max - lx.min), az = 0.5 * (lz.max - lz.min);
  if (shape == ConeShape::kCircular) ax = az = std::min(ax, az);
  const double u = (sv.x() - cx) / ax, w = (sv.z() - cz) / az;
  const double rho = std::sqrt(u * u + w * w);
  bool changed = false;
  if (rho > 1.0) {
    sv = Vec3(cx + ax * u / rho, 0.0, cz + az * w / rho);
    changed = true;
  }
  if (ly.limited && (ty < ly.min || ty > ly.max)) {
    ty = std::clamp(ty, ly.min, ly.max);
    changed = true;
  }
  if (!changed) return q;
  return (quat_from_rotation_vector(sv) * Quat(Eigen::AngleAxisd(ty, Vec3::UnitY()))).normalized();
}

IkReport solve_rotation_method(const IkProblem& pb, Pose& pose) {
  const Rig& rig = *pb.rig;
  const IkOptions& opt = pb.options;
  // free axes per bone: 1 = bend joint (that axis), more = socket
  std::vector<std::vector<int>> free_axes(rig.nbone);
  for (int i = 0; i < rig.nbone; ++i) {
    for (int k = 0; k < 3; ++k) {
      const bool locked = opt.respect_limits && rig.bone_parent[i] >= 0 &&
                          rig.bone_limit[i][k].locked();
      if (!locked) free_axes[i].push_back(k);
    }
  }
  const double cap = opt.max_angle_step;

  auto iterate = [&](Pose& p, BoneFrames& f) {
    for (const IkGoal& goal : pb.goals) {
      Vec3 point = point_on_bone(f, goal.bone, goal.alpha);
      double weight = 1.0;  // damping^k
      for (int j = goal.bone; j >= 0; j = rig.bone_parent[j], weight *= opt.rotation_damping) {
        if (free_axes[j].empty() || weight == 0.0) continue;
        const Quat P = rest_frame_world(rig, f, j);
        const Vec3& h = f.head_world[j];
        const double L = rig.bone_length[j];
        auto apply = [&](const Vec3& axis, double theta) {
          theta = std::clamp(theta, -cap, cap);
          const Quat q_old = p.bone_local_rotation[j];
          Quat q = rotate_local(rig, f, j, q_old, Quat(Eigen::AngleAxisd(theta, axis)));
          if (opt.respect_limits) {
            q = clamp_to_limits(rig, j, clamp_to_cone(rig, j, q, opt.cone_shape));
          }
          const Quat delta = (P * q * q_old.conjugate() * P.conjugate()).normalized();
          point = h + delta * (point - h);
          p.bone_local_rotation[j] = q;
        };
        auto goal_vec = [&]() {
          const Vec3 g = goal.target_world - point;
          if (opt.springiness <= 0.0) return g;
          const Vec3 natural_tail = h + P * Vec3(0, L, 0);
          const Vec3 tail = h + P * (p.bone_local_rotation[j] * Vec3(0, L, 0));
          return Vec3(g + opt.springiness * std::min(1.0, g.norm() / L) * (natural_tail - tail));
        };
        auto amount = [&](const Vec3& a, const Vec3& g) {
          const Vec3 r = point - h;
          const Vec3 ra = r - a * a.dot(r);
          const double r2 = ra.squaredNorm();
          return r2 > 1e-24 ? opt.rotation_gain * weight * a.dot(ra.cross(g)) / r2 : 0.0;
        };
        Vec3 g = goal_vec();
        if (free_axes[j].size() == 1) {  // bend joint: the fixed axis
          const Vec3 a = P * Vec3::Unit(free_axes[j][0]);
          apply(a, amount(a, g));
          continue;
        }
        if (opt.socket_mode == SocketMode::kTwistBend) {
          const Vec3 y = P * (p.bone_local_rotation[j] * Vec3::UnitY());
          const bool twist_free = std::find(free_axes[j].begin(), free_axes[j].end(), 1) !=
                                  free_axes[j].end();
          if (twist_free) {
            Vec3 e = point - h, t = point + g - h;
            e -= y * y.dot(e);
            t -= y * y.dot(t);
            if (e.norm() > 1e-9 * L && t.norm() > 1e-9 * L) {
              const double phi = std::atan2(y.dot(e.cross(t)), e.dot(t));
              apply(y, opt.rotation_gain * weight * phi);
              g = goal_vec();
            }
          }
          const Vec3 y2 = P * (p.bone_local_rotation[j] * Vec3::UnitY());
          Vec3 a = (point - h).cross(g);
          a -= y2 * y2.dot(a);
          if (a.norm() < 1e-12) continue;
          a.normalize();
          apply(a, amount(a, g));
        } else {
          Vec3 a = (point - h).cross(g);
          if (a.norm() < 1e-12) continue;  // virtual bone and goal vector aligned: no rotation
          a.normalize();
          apply(a, amount(a, g));
        }
      }
      forward_kinematics(rig, p, f);  // the next goal starts from the updated pose
    }
  };
  return run_ik_loop("rotation", pb, pose, iterate);
}

}  // namespace physik
