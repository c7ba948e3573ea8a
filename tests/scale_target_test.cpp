// scale_target.cpp: the three branches of the guide's scale distributor.
#include <cmath>

#include <gtest/gtest.h>

#include "physik/ik/ik_solver.h"
#include "physik/model/errors.h"
#include "tests/test_util.h"

namespace physik {
namespace {

Vec3 product(const std::vector<Vec3>& s) {
  Vec3 p = Vec3::Ones();
  for (const Vec3& v : s) p = p.cwiseProduct(v);
  return p;
}

TEST(ScaleTarget, UnconstrainedGivesEveryNodeTheNthRoot) {
  std::vector<Vec3> s(4, Vec3::Ones());
  const Vec3 goal(16.0, 1.0, 0.0625);
  EXPECT_EQ(distribute_scale(goal, s), ScaleBranch::kUnconstrained);
  for (const Vec3& v : s) EXPECT_TRUE(test::near(v, Vec3(2.0, 1.0, 0.5), 1e-12));
  EXPECT_TRUE(test::near(product(s), goal, 1e-12));
}

TEST(ScaleTarget, ConstrainedRedistributesTowardsTheEffector) {
  // goal 8 over 3 nodes: share 2, but node 0 may not exceed 1.5; the rest (8 / 1.5) is spread
  // over the two remaining nodes: sqrt(16/3) each
  std::vector<Vec3> s(3, Vec3::Ones());
  const std::vector<Vec3> lo(3, Vec3::Constant(0.1));
  std::vector<Vec3> hi(3, Vec3::Constant(10.0));
  hi[0] = Vec3::Constant(1.5);
  const Vec3 goal = Vec3::Constant(8.0);
  EXPECT_EQ(distribute_scale(goal, s, lo, hi), ScaleBranch::kConstrained);
  EXPECT_TRUE(test::near(s[0], Vec3::Constant(1.5), 1e-12));
  EXPECT_TRUE(test::near(s[1], Vec3::Constant(std::sqrt(16.0 / 3.0)), 1e-12));
  EXPECT_TRUE(test::near(s[2], s[1], 1e-12));
  EXPECT_TRUE(test::near(product(s), goal, 1e-12));
}

TEST(ScaleTarget, ConstrainedKeepsEveryNodeInRangeWhenTheGoalIsInfeasible) {
  std::vector<Vec3> s(3, Vec3::Ones());
  const std::vector<Vec3> lo(3, Vec3::Constant(0.5)), hi(3, Vec3::Constant(2.0));
  distribute_scale(Vec3::Constant(100.0), s, lo, hi);
  for (const Vec3& v : s) EXPECT_TRUE(test::near(v, Vec3::Constant(2.0), 1e-12));  // 8 < 100
}

TEST(ScaleTarget, NegativeGoalInterpolatesTheGlobalScale) {
  // root at 1, goal -2 over 4 nodes: global scales 1, 0, ... would divide by zero; with 3 nodes
  // the globals are 1, -0.5, -2 and the locals their ratios
  std::vector<Vec3> s(3, Vec3::Ones());
  const Vec3 goal(-2.0, 3.0, 1.0);
  EXPECT_EQ(distribute_scale(goal, s), ScaleBranch::kNegative);
  EXPECT_TRUE(test::near(s[0], Vec3::Ones(), 1e-12));  // the root keeps its scale
  EXPECT_TRUE(test::near(s[1], Vec3(-0.5, 2.0, 1.0), 1e-12));
  EXPECT_TRUE(test::near(product(s), goal, 1e-12));
}

TEST(ScaleTarget, NegativeBranchThroughZeroGivesNoNaN) {
  std::vector<Vec3> s(3, Vec3::Ones());
  distribute_scale(Vec3(-1.0, 1.0, 1.0), s);  // globals in x: 1, 0, -1
  for (const Vec3& v : s) EXPECT_TRUE(v.allFinite());
}

TEST(ScaleTarget, BadInputIsAnError) {
  std::vector<Vec3> none;
  EXPECT_THROW(distribute_scale(Vec3::Ones(), none), InputError);
  std::vector<Vec3> s(3, Vec3::Ones());
  EXPECT_THROW(distribute_scale(Vec3::Ones(), s, {Vec3::Ones()}, {Vec3::Ones()}), InputError);
}

}  // namespace
}  // namespace physik
