// Contacts and gravity in the engine (physik/engine/contacts.h): a bone resting on the floor (and
// on a box) at the analytic penetration in every scheme, the energy of a bone dropped on the floor,
// two bones driven into each other with and without self-collision.
#include <algorithm>
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "physik/engine/collision.h"
#include "physik/engine/contacts.h"
#include "physik/engine/engine.h"
#include "physik/engine/implicit_advance.h"
#include "physik/engine/measures.h"
#include "tests/contact_test_util.h"

namespace physik {
namespace {

using test::bone;
using test::floor_scene;
using test::lying_rod;
using test::u_rig;

// the two end contacts' depths after `steps`
std::pair<double, double> settled_depths(Scene s, int steps) {
  SimState st;
  init_state(s, st);
  for (int k = 0; k < steps; ++k) step(s, st);
  EXPECT_LT(kinetic_energy(s.rig, st), 1e-12);
  std::vector<Contact> c;
  CollisionWorld world;
  world.detect(s, st.frames, c);
  EXPECT_EQ(c.size(), 2u);
  if (c.size() != 2u) return {0.0, 0.0};
  return {c[0].depth, c[1].depth};
}

TEST(Contacts, RodRestsAtTheAnalyticPenetrationInEveryScheme) {
  // a 1 kg rod lying on the floor: each end carries m g / 2, so it sinks by m g / (2 k)
  const double k = 1e4, expected = 1.0 * 9.81 / (2.0 * k);
  for (const Scheme scheme : {Scheme::kImplicit, Scheme::kExact, Scheme::kGaussSeidel}) {
    SCOPED_TRACE(to_string(scheme));
    const double dt = scheme == Scheme::kImplicit ? 0.05 : 0.002;  // explicit: dt < 0.01
    Scene s = floor_scene(lying_rod(0.06), scheme, dt);
    s.params.contact_k = k;
    const auto [d0, d1] = settled_depths(s, static_cast<int>(std::lround(3.0 / dt)));
    EXPECT_NEAR(d0, expected, 1e-6 * expected);
    EXPECT_NEAR(d1, expected, 1e-6 * expected);
  }
}

TEST(Contacts, RodRestsOnABoxTopAtTheAnalyticPenetration) {
  // the same rod on a box (top at z = 0.5, no ground): each end carries m g / 2 as on the floor,
  // and the box's contacts take the floor's path through every scheme
  const double k = 1e4, expected = 1.0 * 9.81 / (2.0 * k);
  for (const Scheme scheme : {Scheme::kImplicit, Scheme::kExact}) {
    SCOPED_TRACE(to_string(scheme));
    const double dt = scheme == Scheme::kImplicit ? 0.05 : 0.002;
    Scene s = floor_scene(lying_rod(0.56), scheme, dt);
    s.collision.ground.reset();
    s.collision.obstacles = {
        BoxObstacle{"seat", Vec3(0.5, 0, 0.25), Vec3(0.75, 0.5, 0.25), Quat::Identity()}};
    s.params.contact_k = k;
    const auto [d0, d1] = settled_depths(s, static_cast<int>(std::lround(3.0 / dt)));
    EXPECT_NEAR(d0, expected, 1e-6 * expected);
    EXPECT_NEAR(d1, expected, 1e-6 * expected);
  }
}

TEST(Contacts, DroppedRodLosesEnergyWithDampingOn) {
  // dropped from 0.5 with a tilt, only the contacts' damper and friction act; the energy
  // (KE + gravity + contact springs) never rises above its start by more than the onset of a
  // contact within one step (k (v h)^2 / 2, 1e-4 of E at dt 1e-4 explicit) and ends far below
  for (const Scheme scheme : {Scheme::kExact, Scheme::kImplicit}) {
    SCOPED_TRACE(to_string(scheme));
    const double dt = scheme == Scheme::kImplicit ? 0.01 : 1e-4;
    Scene s = floor_scene(lying_rod(0.5), scheme, dt);
    s.params.angular_velocity_factor = 1.0;
    s.initial_pose.bone_local_rotation[0] = Quat(Eigen::AngleAxisd(0.2, Vec3::UnitY()));
    SimState st;
    init_state(s, st);
    const double e0 = mechanical_energy(s, st);
    EXPECT_NEAR(e0, 9.81 * st.com_world[0].z(), 1e-12);  // m g z above the floor, at rest
    double e_max = e0, e = e0;
    for (int n = 0; n < static_cast<int>(std::lround(2.0 / dt)); ++n) {
      step(s, st);
      e = mechanical_energy(s, st);
      e_max = std::max(e_max, e);
    }
    EXPECT_LE(e_max, e0 * (1.0 + 1e-3));
    EXPECT_LT(kinetic_energy(s.rig, st), 1e-9);
    // at rest lying on the floor: the centre one radius up, less the sinking, and the springs'
    // tiny energy (m g)^2 / (4 k): E = m g (0.06 - d) + (m g)^2 / (4 k)
    const double d = 9.81 / 2e4;
    EXPECT_NEAR(e, 9.81 * (0.06 - d) + 9.81 * 9.81 / 4e4, 1e-6);
  }
}

// the U rig's leg pulled through its post (the post and the bar's tail held): where the leg's tail
// ends up, and the deepest contact between bones over the run (over the thinner radius). Without
// contacts the leg points from its pivot (0.5, 0, 1) at the target (-0.5, 0, 0.2), 1.28 away:
// its tail settles near (-0.28, 0, 0.38).
struct PulledLeg {
  Vec3 tail_world;
  double deepest = 0.0;  // over the run
  double final = 0.0;    // at the end
};

PulledLeg pull_leg(bool self_collision) {
  EngineParams p = preset_params("robust");
  p.damping_auto = false;
  p.damping = 3.0;
  Scene s = test::scene_for(u_rig(0.5, -2.0, 0.05), p, 400);
  s.collision.self_collision = self_collision;
  s.control_points = {test::control(0, 0.0, Vec3(0, 0, -2), 1000.0),
                      test::control(0, 1.0, Vec3(0, 0, 1), 1000.0),
                      test::control(1, 1.0, Vec3(0.5, 0, 1), 1000.0),
                      test::control(2, 1.0, Vec3(-0.5, 0, 0.2), 30.0)};
  SimState st;
  init_state(s, st);
  PulledLeg out;
  for (int k = 0; k < s.steps; ++k) {
    step(s, st);
    out.deepest = std::max(out.deepest, penetration(s, st.contacts).max_depth_fraction);
  }
  out.tail_world = st.frames.tail_world[2];
  out.final = penetration(s, st.frames).max_depth_fraction;
  return out;
}

// The leg meets the post head on, a balance the round post cannot keep: the regularised friction
// has no static part, so the leg may slide around the post, but never through it.
TEST(Contacts, SelfCollisionStopsALegPulledThroughItsPost) {
  EXPECT_LT(pull_leg(false).tail_world.x(), -0.2);  // without: through the post, to the target
  const PulledLeg with = pull_leg(true);
  // with: never half a radius deep (through would be two), a tenth at most at the end
  EXPECT_LT(with.deepest, 0.5);
  EXPECT_LT(with.final, 0.1);
  EXPECT_GT(with.deepest, 0.0);  // and it did press on the post
}

}  // namespace
}  // namespace physik
