// FABRIK: forward and backward reaching inverse kinematics, on a tree with several effectors.
//
// Source: the IK guide (seed 001), "Fabrik Solver" (Aristidou and Lasenby's FABRIK), extended to
// trees in the usual multi-end way. Positions are world, rig units. Nodes are the root's head
// (the anchor) and every bone's tail; bone i joins head_i = tail_parent(i) to tail_i with
// |tail_i - head_i| = L_i. Only the bones on a root-to-effector path take part.
//
//   backward (reverse DFS, leaves first): the tail of bone i goes to the average of its wishes:
//     - for each goal on bone i (point at alpha along it, target t):
//         u = normalize(t - head_i),  wish = t + (1 - alpha) L_i u      (alpha = 1: wish = t)
//     - for each active child c: the head c wants after its own backward step;
//     then the head follows the guide's ordering so that no change simplifies to a + (b - a):
//         head_i' = tail_i + L_i normalize(head_i - tail_i)
//   forward (DFS, root first): head_i = tail_parent (the root's = the anchor),
//         tail_i = head_i + L_i normalize(tail_i - head_i)
//     done together with the rotations (guide: "you absolutely need to compute the rotations in
//     local space"): each active bone turns by the smallest rotation, in its rest frame, that
//     aims it from its head at its backward tail (aim_bones_at); this keeps its twist (FABRIK
//     has no concept of roll). Limits are applied right there by clamping the rotation vector,
//     so children start from the clamped parent; FABRIK itself knows no limits (the guide warns
//     that it "has issues with rotation constraints").
// Several goals on one path (a mid-chain effector and the tip) are averaged, as the guide
// suggests; that average is a compromise, not the joint solution (measured in tests).
// One iteration = backward + forward; the next starts from FK of the pose, so the reported pose
// always has the exact bone lengths.
#include <cmath>

#include "physik/ik/ik_solver.h"

namespace physik {

namespace {

Vec3 direction_or(const Vec3& v, const Vec3& fallback) {
  const double n = v.norm();
  return n > 1e-12 ? Vec3(v / n) : fallback;
}

}  // namespace

IkReport solve_fabrik(const IkProblem& pb, Pose& pose) {
  const Rig& rig = *pb.rig;
  const int n = rig.nbone;
  std::vector<Vec3> tail(n), head_wish(n), wish_sum(n);
  std::vector<int> wish_count(n);
  std::vector<std::vector<int>> goals_on(n);
  for (std::size_t k = 0; k < pb.goals.size(); ++k) goals_on[pb.goals[k].bone].push_back(k);

  auto iterate = [&](Pose& p, BoneFrames& f) {
    const Vec3 anchor = p.root_head_world;
    for (int i = 0; i < n; ++i) {
      tail[i] = f.tail_world[i];
      wish_sum[i].setZero();
      wish_count[i] = 0;
    }
    // backward: leaves first
    for (int i = n - 1; i >= 0; --i) {
      if (!pb.active[i]) continue;
      const int par = rig.bone_parent[i];
      const Vec3 head = par < 0 ? anchor : tail[par];
      const double L = rig.bone_length[i];
      const Vec3 dir_now = direction_or(tail[i] - head, f.orient_world[i] * Vec3::UnitY());
      Vec3 goal_sum = Vec3::Zero();
      for (int k : goals_on[i]) {
        const IkGoal& g = pb.goals[k];
        const Vec3 u = direction_or(g.target_world - head, dir_now);
        goal_sum += g.target_world + (1.0 - g.alpha) * L * u;
      }
      wish_sum[i] += goal_sum;
      wish_count[i] += static_cast<int>(goals_on[i].size());
      if (wish_count[i] > 0) tail[i] = wish_sum[i] / wish_count[i];
      head_wish[i] = tail[i] + L * direction_or(head - tail[i], -dir_now);
      if (par >= 0) {
        wish_sum[par] += head_wish[i];
        ++wish_count[par];
      }
    }
    // forward: root first. Each head sits where FK of the (clamped) parents puts it and the bone
    // aims at its backward tail: aim_bones_at is the forward pass and the rotation recovery at
    // once, so a limit clamped in a parent is seen by its children in the same pass.
    aim_bones_at(rig, pb.active, tail, pb.options.respect_limits, p, f);
  };
  return run_ik_loop("fabrik", pb, pose, iterate);
}

}  // namespace physik
