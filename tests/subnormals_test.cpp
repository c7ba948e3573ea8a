// Subnormal numbers flushed for the duration of a step (physik/engine/subnormals.h, the parameter
// flush_subnormals): the step sets the processor's flush modes and gives the caller's back; a long
// pulled chain, whose far end decays through subnormals without them, then holds none; and the
// trajectory differs from IEEE gradual underflow's by nothing a rig unit can show.
#include <cmath>

#include <gtest/gtest.h>

#include "physik/engine/engine.h"
#include "physik/engine/subnormals.h"
#include "physik/model/params.h"
#include "physik/model/rig_generators.h"
#include "tests/engine_test_util.h"

namespace physik {
namespace {

// the scaling experiment's scenario (experiments/scaling.cpp): a chain pulled at its last tail
Scene pulled_chain(int nbone, Scheme scheme, bool flush) {
  const Rig rig = make_chain_rig(nbone);
  EngineParams params = preset_params("original");
  params.scheme = scheme;
  params.flush_subnormals = flush;
  Scene s = test::scene_for(rig, params, 0);
  ControlPoint c =
      test::control(nbone - 1, 1.0, rig.bone_rest_tail_world[nbone - 1] + Vec3(3.0, 1.0, 0.0), 10.0,
                    SpringLaw::kCapped);
  s.control_points.push_back(c);
  return s;
}

int count_subnormal(const std::vector<Vec3>& v) {
  int n = 0;
  for (const Vec3& x : v) {
    for (int k = 0; k < 3; ++k) n += std::fpclassify(x[k]) == FP_SUBNORMAL;
  }
  return n;
}

int subnormals_in(const SimState& s) {
  return count_subnormal(s.vel_world) + count_subnormal(s.omega_world) +
         count_subnormal(s.force_world) + count_subnormal(s.torque_world) +
         count_subnormal(s.joint_force_world);
}

TEST(Subnormals, FlushModesHoldForTheObjectsLifetimeOnly) {
  if (!flush_subnormals_supported()) GTEST_SKIP() << "no flush modes known on this processor";
  ASSERT_FALSE(subnormals_flushed());
  {
    const FlushSubnormals off(false);
    EXPECT_FALSE(subnormals_flushed());
  }
  {
    const FlushSubnormals on(true);
    EXPECT_TRUE(subnormals_flushed());
    volatile double tiny = 1e-300;
    volatile double product = tiny * 1e-10;  // 1e-310, subnormal under IEEE
    EXPECT_EQ(product, 0.0);
    {
      const FlushSubnormals nested(true);  // already set: nothing to undo at its end
      EXPECT_TRUE(subnormals_flushed());
    }
    EXPECT_TRUE(subnormals_flushed());
  }
  EXPECT_FALSE(subnormals_flushed());
  volatile double tiny = 1e-300;
  volatile double product = tiny * 1e-10;
  EXPECT_EQ(std::fpclassify(product), FP_SUBNORMAL);
}

TEST(Subnormals, StepGivesTheCallersModesBack) {
  if (!flush_subnormals_supported()) GTEST_SKIP() << "no flush modes known on this processor";
  for (Scheme scheme : {Scheme::kExact, Scheme::kImplicit, Scheme::kGaussSeidel}) {
    Scene scene = pulled_chain(20, scheme, true);
    SimState s;
    init_state(scene, s);
    step(scene, s);
    EXPECT_FALSE(subnormals_flushed()) << "scheme " << static_cast<int>(scheme);
    if (scheme == Scheme::kImplicit) {  // a step of another length (the implicit scheme's only)
      step(scene, s, 0.5 * scene.params.dt);
      EXPECT_FALSE(subnormals_flushed());
    }
  }
  // a caller that computes with the modes set (a program built with -ffast-math) keeps them
  const FlushSubnormals callers(true);
  Scene scene = pulled_chain(20, Scheme::kExact, true);
  SimState s;
  init_state(scene, s);
  step(scene, s);
  EXPECT_TRUE(subnormals_flushed());
}

// Without the flush, a 400-bone chain's far end holds subnormal velocities and forces after a
// few steps (the test would prove nothing otherwise); with it, none, and every bone's head
// agrees with the IEEE run's to 1e-12 rig units: what is flushed is below 2.2e-308.
TEST(Subnormals, LongChainFarEndHoldsNoneAndMovesTheSame) {
  if (!flush_subnormals_supported()) GTEST_SKIP() << "no flush modes known on this processor";
  for (Scheme scheme : {Scheme::kExact, Scheme::kImplicit}) {
    Scene ieee = pulled_chain(400, scheme, false);
    Scene flushed = pulled_chain(400, scheme, true);
    SimState a, b;
    init_state(ieee, a);
    init_state(flushed, b);
    int subnormals_ieee = 0;
    for (int i = 0; i < 30; ++i) {
      step(ieee, a);
      step(flushed, b);
      subnormals_ieee += subnormals_in(a);
      ASSERT_EQ(subnormals_in(b), 0) << "step " << i;
    }
    EXPECT_GT(subnormals_ieee, 0) << "the scenario no longer reaches subnormals";
    double worst = 0.0;
    for (std::size_t k = 0; k < a.frames.head_world.size(); ++k) {
      worst = std::max(worst, (a.frames.head_world[k] - b.frames.head_world[k]).norm());
    }
    EXPECT_LT(worst, 1e-12) << "scheme " << static_cast<int>(scheme);
  }
}

}  // namespace
}  // namespace physik
