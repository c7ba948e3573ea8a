// Target interpolation (eq. 12): exact endpoints, monotone polar radius, linear fallback.
#include "physik/engine/interpolation.h"

#include <gtest/gtest.h>

#include "physik/engine/engine.h"
#include "tests/engine_test_util.h"
#include "tests/test_util.h"

namespace physik {
namespace {

std::vector<Vec3> path(Interpolation scheme, const Vec3& from, const Vec3& to, const Vec3& origin,
                       int steps, double fallback = 1e-3) {
  std::vector<Vec3> pts{from};
  Vec3 t = from;
  for (int left = steps; left >= 1; --left) {
    t = interpolate_step(scheme, t, to, origin, 1.0 / left, fallback);
    pts.push_back(t);
  }
  return pts;
}

TEST(Interpolation, EndpointsAreExact) {
  const Vec3 from(1, 0, 0), to(-0.3, 2.0, 0.5), origin(0.1, 0.1, 0.1);
  for (Interpolation s :
       {Interpolation::kLinear, Interpolation::kPolarHead, Interpolation::kPolarCom}) {
    const auto p = path(s, from, to, origin, 17);
    EXPECT_EQ(p.front(), from);
    EXPECT_EQ(p.back(), to);  // the last step has alpha = 1: exact
  }
}

TEST(Interpolation, LinearMovesAtConstantSpeed) {
  const Vec3 from(1, 0, 0), to(-1, 3, 2);
  const auto p = path(Interpolation::kLinear, from, to, Vec3::Zero(), 10);
  for (std::size_t i = 1; i < p.size(); ++i) {
    EXPECT_NEAR((p[i] - p[i - 1]).norm(), (to - from).norm() / 10, 1e-12);
  }
}

TEST(Interpolation, PolarRadiusChangesMonotonicallyAndAngleUniformly) {
  const Vec3 origin(0.5, -0.2, 1.0);
  const Vec3 from = origin + Vec3(2.0, 0, 0), to = origin + Vec3(0, 0.5, 0.0);
  const auto p = path(Interpolation::kPolarCom, from, to, origin, 20);
  for (std::size_t i = 1; i < p.size(); ++i) {
    EXPECT_LT((p[i] - origin).norm(), (p[i - 1] - origin).norm());  // 2.0 -> 0.5, shrinking
    // constant angular speed: 90 deg in 20 steps
    const Vec3 a = (p[i - 1] - origin).normalized(), b = (p[i] - origin).normalized();
    EXPECT_NEAR(std::acos(std::clamp(a.dot(b), -1.0, 1.0)), kPi / 2 / 20, 1e-9);
  }
  // and the radius is the linear blend of eq. 12
  EXPECT_NEAR((p[10] - origin).norm(), 2.0 + 0.5 * (0.5 - 2.0), 1e-9);
}

TEST(Interpolation, LinearFallbackNearTheOrigin) {
  const Vec3 origin(0, 0, 0);
  // the goal sits on the origin: polar is undefined, the step must be the linear one
  const Vec3 from(1, 1, 0), to(0, 0, 0);
  const Vec3 polar = interpolate_step(Interpolation::kPolarHead, from, to, origin, 0.25, 1e-3);
  const Vec3 linear = interpolate_step(Interpolation::kLinear, from, to, origin, 0.25, 1e-3);
  EXPECT_EQ(polar, linear);
  // the start near the origin too
  const Vec3 near_start(1e-4, 0, 0);
  EXPECT_EQ(
      interpolate_step(Interpolation::kPolarCom, near_start, Vec3(1, 2, 3), origin, 0.5, 1e-3),
      interpolate_step(Interpolation::kLinear, near_start, Vec3(1, 2, 3), origin, 0.5, 1e-3));
  // away from it polar differs from linear
  EXPECT_GT(
      (interpolate_step(Interpolation::kPolarCom, Vec3(2, 0, 0), Vec3(0, 2, 0), origin, 0.5, 1e-3) -
       interpolate_step(Interpolation::kLinear, Vec3(2, 0, 0), Vec3(0, 2, 0), origin, 0.5, 1e-3))
          .norm(),
      0.1);
}

TEST(Interpolation, ScheduledJumpIsSpreadOverTheSetSteps) {
  Scene scene = test::scene_for(test::one_rod(), test::bare_params(), 40);
  scene.params.interpolation = Interpolation::kLinear;
  scene.params.interpolation_steps = 10;
  scene.control_points.push_back(test::control(0, 1.0, Vec3(0, 0, 1), 0.0));  // at the tip already
  scene.schedule.push_back({5, 0, Vec3(3, 0, 1)});
  SimState s;
  init_state(scene, s);
  std::vector<Vec3> eff;
  for (int n = 0; n < 20; ++n) {
    step(scene, s);
    eff.push_back(s.target_effective_world[0]);
  }
  EXPECT_TRUE(test::near(eff[4], Vec3(0, 0, 1), 1e-12));    // before the jump
  EXPECT_TRUE(test::near(eff[5], Vec3(0.3, 0, 1), 1e-12));  // first of 10 steps
  EXPECT_TRUE(test::near(eff[14], Vec3(3, 0, 1), 1e-12));   // the tenth lands
  EXPECT_TRUE(test::near(eff[19], Vec3(3, 0, 1), 1e-12));
}

}  // namespace
}  // namespace physik
