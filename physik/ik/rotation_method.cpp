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
  if (shape == ConeShape::kNone) return q;
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

namespace {

// One joint's turn toward one goal (the header's equations): bone j of pose p turning about its
// head, carrying the goal's selected point along.
class JointTurn {
 public:
  JointTurn(const Rig& rig, const IkOptions& opt, const BoneFrames& f, Pose& p, int j,
            const IkGoal& goal, double weight, Vec3& point)
      : rig_(rig),
        opt_(opt),
        f_(f),
        p_(p),
        j_(j),
        goal_(goal),
        weight_(weight),
        point_(point),
        P_(rest_frame_world(rig, f, j)),
        h_(f.head_world[j]),
        L_(rig.bone_length[j]) {}

  // bend joint: the one free axis, fixed in the parent
  void bend(int axis_index) {
    const Vec3 a = P_ * Vec3::Unit(axis_index);
    apply(a, amount(a, goal_vec()));
  }

  // socket joint, twist then bend (the author's fix)
  void twist_then_bend(bool twist_free) {
    Vec3 g = goal_vec();
    const Vec3 y = P_ * (p_.bone_local_rotation[j_] * Vec3::UnitY());
    if (twist_free) {
      Vec3 e = point_ - h_, t = point_ + g - h_;
      e -= y * y.dot(e);
      t -= y * y.dot(t);
      if (e.norm() > 1e-9 * L_ && t.norm() > 1e-9 * L_) {
        const double phi = std::atan2(y.dot(e.cross(t)), e.dot(t));
        apply(y, opt_.rotation_gain * weight_ * phi);
        g = goal_vec();
      }
    }
    const Vec3 y2 = P_ * (p_.bone_local_rotation[j_] * Vec3::UnitY());
    Vec3 a = (point_ - h_).cross(g);
    a -= y2 * y2.dot(a);
    if (a.norm() < 1e-12) return;
    a.normalize();
    apply(a, amount(a, g));
  }

  // socket joint as shipped: the axis normal to the virtual bone and the goal vector
  void virtual_bone() {
    const Vec3 g = goal_vec();
    Vec3 a = (point_ - h_).cross(g);
    if (a.norm() < 1e-12) return;  // virtual bone and goal vector aligned: no rotation
    a.normalize();
    apply(a, amount(a, g));
  }

 private:
  // turn by theta (clamped) about a world axis through the head, within the limits
  void apply(const Vec3& axis, double theta) {
    theta = std::clamp(theta, -opt_.max_angle_step, opt_.max_angle_step);
    const Quat q_old = p_.bone_local_rotation[j_];
    Quat q = rotate_local(rig_, f_, j_, q_old, Quat(Eigen::AngleAxisd(theta, axis)));
    if (opt_.respect_limits) {
      q = clamp_to_limits(rig_, j_, clamp_to_cone(rig_, j_, q, opt_.cone_shape));
    }
    const Quat delta = (P_ * q * q_old.conjugate() * P_.conjugate()).normalized();
    point_ = h_ + delta * (point_ - h_);
    p_.bone_local_rotation[j_] = q;
  }

  // the goal vector with springiness toward the natural (rest) position
  Vec3 goal_vec() const {
    const Vec3 g = goal_.target_world - point_;
    if (opt_.springiness <= 0.0) return g;
    const Vec3 natural_tail = h_ + P_ * Vec3(0, L_, 0);
    const Vec3 tail = h_ + P_ * (p_.bone_local_rotation[j_] * Vec3(0, L_, 0));
    return Vec3(g + opt_.springiness * std::min(1.0, g.norm() / L_) * (natural_tail - tail));
  }

  // the rotation amount about axis a for goal vector g
  double amount(const Vec3& a, const Vec3& g) const {
    const Vec3 r = point_ - h_;
    const Vec3 ra = r - a * a.dot(r);
    const double r2 = ra.squaredNorm();
    return r2 > 1e-24 ? opt_.rotation_gain * weight_ * a.dot(ra.cross(g)) / r2 : 0.0;
  }

  const Rig& rig_;
  const IkOptions& opt_;
  const BoneFrames& f_;
  Pose& p_;
  const int j_;
  const IkGoal& goal_;
  const double weight_;
  Vec3& point_;
  const Quat P_;
  const Vec3 h_;
  const double L_;
};

}  // namespace

IkReport solve_rotation_method(const IkProblem& pb, Pose& pose) {
  const Rig& rig = *pb.rig;
  const IkOptions& opt = pb.options;
  // free axes per bone: 1 = bend joint (that axis), more = socket
  std::vector<std::vector<int>> free_axes(rig.nbone);
  for (int i = 0; i < rig.nbone; ++i) {
    for (int k = 0; k < 3; ++k) {
      // a bone the world holds has none; the root's limits count like any bone's
      const bool locked = opt.respect_limits && rig.bone_limit[i][k].locked();
      if (!locked && pb.active[i]) free_axes[i].push_back(k);
    }
  }
  auto iterate = [&](Pose& p, BoneFrames& f) {
    for (const IkGoal& goal : pb.goals) {
      Vec3 point = point_on_bone(f, goal.bone, goal.alpha);
      double weight = 1.0;  // damping^k
      for (int j = goal.bone; j >= 0; j = rig.bone_parent[j], weight *= opt.rotation_damping) {
        if (free_axes[j].empty() || weight == 0.0) continue;
        JointTurn turn(rig, opt, f, p, j, goal, weight, point);
        if (free_axes[j].size() == 1) {
          turn.bend(free_axes[j][0]);
        } else if (opt.socket_mode == SocketMode::kTwistBend) {
          const auto& axes = free_axes[j];
          turn.twist_then_bend(std::find(axes.begin(), axes.end(), 1) != axes.end());
        } else {
          turn.virtual_bone();
        }
      }
      forward_kinematics(rig, p, f);  // the next goal starts from the updated pose
    }
  };
  return run_ik_loop("rotation", pb, pose, iterate);
}

}  // namespace physik
