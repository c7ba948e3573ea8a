// The scale-target distributor: spread a goal scale for the effector over the local scales of a
// chain of N nodes so that their product (the effector's global scale) meets the goal.
//
// Source: the IK guide (seed 001), "Scale Target Solver". Scales are per-axis factors (1), applied
// component-wise; pow, clamp and division are component-wise too.
//   constrained (min_scale and max_scale given for every node), root to leaf so that what is
//   redistributed is focused towards the effector:
//       share = goal^(1/N), remaining = goal
//       for i = 0..N-1:  s_i = clamp(share, min_i, max_i);  remaining /= s_i;
//                        if s_i != share: share = remaining^(1/(N-1-i))   (the nodes still left)
//     (the guide writes 1/max(N - i, 1), which counts node i again; with N - 1 - i the remaining
//     nodes exactly absorb what is left). The guide notes it does not handle negative scales:
//     a component <= 0 in the goal falls through to the negative branch here.
//   unconstrained (every goal component > 0): s_i = goal^(1/N) for every node.
//   negative (a component <= 0): the global scale is interpolated linearly from the root's
//       current scale s_0 to the goal, G_i = lerp(s_0, goal, i / (N - 1)), and converted to local
//       scales s_i = G_i / G_(i-1) (erratum: the guide divides by the next node's global scale,
//       which inverts the chain). Where G_(i-1) is 0 the product is undefined; that component is
//       set to G_i itself (the guide: "check for div by 0").
#include <algorithm>
#include <cmath>

#include "physik/ik/ik_solver.h"
#include "physik/model/errors.h"

namespace physik {

namespace {

Vec3 cw_pow(const Vec3& v, double e) {
  return Vec3(std::pow(v.x(), e), std::pow(v.y(), e), std::pow(v.z(), e));
}

}  // namespace

ScaleBranch distribute_scale(const Vec3& goal, std::vector<Vec3>& scales,
                             const std::vector<Vec3>& min_scale,
                             const std::vector<Vec3>& max_scale) {
  const int n = static_cast<int>(scales.size());
  if (n == 0) throw_input_error("scale", "scales", "", "no nodes to distribute over");
  const bool positive = (goal.array() > 0.0).all();
  const bool constrained =
      !min_scale.empty() && min_scale.size() == scales.size() && max_scale.size() == scales.size();
  if (!min_scale.empty() && !constrained) {
    throw_input_error("scale", "min_scale/max_scale", "", "need one entry per node");
  }
  if (positive && constrained) {
    Vec3 share = cw_pow(goal, 1.0 / n);
    Vec3 remaining = goal;
    for (int i = 0; i < n; ++i) {
      scales[i] = share.cwiseMax(min_scale[i]).cwiseMin(max_scale[i]);
      remaining = remaining.cwiseQuotient(scales[i]);
      if (scales[i] != share && i + 1 < n) share = cw_pow(remaining, 1.0 / (n - 1 - i));
    }
    return ScaleBranch::kConstrained;
  }
  if (positive) {
    const Vec3 share = cw_pow(goal, 1.0 / n);
    for (Vec3& s : scales) s = share;
    return ScaleBranch::kUnconstrained;
  }
  const Vec3 s0 = scales[0];
  auto global = [&](int i) {
    const double f = n > 1 ? static_cast<double>(i) / (n - 1) : 1.0;
    return Vec3(s0 + f * (goal - s0));
  };
  if (n == 1) {
    scales[0] = goal;
    return ScaleBranch::kNegative;
  }
  for (int i = 1; i < n; ++i) {
    const Vec3 gi = global(i), gp = global(i - 1);
    for (int c = 0; c < 3; ++c) scales[i][c] = std::abs(gp[c]) > 1e-12 ? gi[c] / gp[c] : gi[c];
  }
  return ScaleBranch::kNegative;
}

}  // namespace physik
