// Control-point springs: linear and capped laws.
#include "physik/engine/control_springs.h"

#include <random>

#include <gtest/gtest.h>

#include "tests/test_util.h"

namespace physik {
namespace {

TEST(ControlSprings, CappedForceNeverExceedsKTimesCap) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-5.0, 5.0);
  for (int n = 0; n < 10000; ++n) {
    const Vec3 d(u(rng), u(rng), u(rng));
    const double k = 30.0, cap = 0.5 + 0.1 * std::abs(u(rng));
    const Vec3 f = spring_force(SpringLaw::kCapped, k, cap, d);
    ASSERT_LE(f.norm(), k * cap * (1 + 1e-12));
    // it points along the displacement
    ASSERT_GT(f.dot(d), 0.0);
    // within the cap it is the linear law
    if (d.norm() <= cap) {
      ASSERT_TRUE(test::near(f, k * d, 1e-12));
    }
  }
}

TEST(ControlSprings, LinearIsHookesLawWithZeroRestLength) {
  const Vec3 d(0.3, -2.0, 4.0);
  EXPECT_TRUE(test::near(spring_force(SpringLaw::kLinear, 10.0, 1.0, d), 10.0 * d, 1e-15));
  EXPECT_TRUE(
      test::near(spring_force(SpringLaw::kCapped, 10.0, 1.0, Vec3::Zero()), Vec3::Zero(), 0));
  // far away the capped force has magnitude k c
  EXPECT_NEAR(spring_force(SpringLaw::kCapped, 10.0, 1.0, d).norm(), 10.0, 1e-12);
}

}  // namespace
}  // namespace physik
