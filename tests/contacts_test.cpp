// Contacts and gravity in the engine (physik/engine/ground_contacts.h, self_contacts.h): a bone
// resting on the floor (and on a box) at the analytic penetration in every scheme, the energy of a
// bone dropped on the floor, two bones driven into each other with and without self-collision.
#include <algorithm>
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "physik/engine/collision.h"
#include "physik/engine/contact_data.h"
#include "physik/engine/engine.h"
#include "physik/engine/gravity.h"
#include "physik/engine/ground_contacts.h"
#include "physik/engine/implicit_advance.h"
#include "physik/engine/measures.h"
#include "physik/engine/self_contacts.h"
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

// A 1 kg rod lying along x on the floor (or a box top), gravity tilted by theta about y: a slope
// of theta down +x. Each end carries N = m g cos(theta) / 2 and a pull T = m g sin(theta) / 2
// along the slope. Returns the rod's centre's travel along x over `seconds` after it settled
// (1 s) and its speed then, rig units and rig units/s.
struct SlopeRun {
  double travel = 0.0;
  double speed = 0.0;
};

SlopeRun rod_on_slope(Scheme scheme, double dt, double tan_theta, double friction_stiffness,
                      bool on_box, double seconds) {
  const double theta = std::atan(tan_theta);
  Scene s = floor_scene(lying_rod(on_box ? 0.56 : 0.06), scheme, dt);
  if (on_box) {
    s.collision.ground.reset();
    s.collision.obstacles = {
        BoxObstacle{"seat", Vec3(0.5, 0, 0.25), Vec3(5.0, 0.5, 0.25), Quat::Identity()}};
  }
  s.gravity_world = 9.81 * Vec3(std::sin(theta), 0, -std::cos(theta));
  s.params.friction_stiffness = friction_stiffness;
  SimState st;
  init_state(s, st);
  const auto steps = [dt](double t) { return static_cast<int>(std::lround(t / dt)); };
  for (int k = 0; k < steps(1.0); ++k) step(s, st);
  const double x0 = st.com_world[0].x();
  for (int k = 0; k < steps(seconds); ++k) step(s, st);
  return {st.com_world[0].x() - x0, st.vel_world[0].x()};
}

// Below the friction angle (tan theta = 0.5 < mu = 1) static friction holds the rod: each end's
// anchor spring stretches by T / k_t and no further. The regularised law alone (friction_stiffness
// 0) has no static part: the rod creeps at the speed where mu N v / v_s = T, v = v_s tan(theta) /
// mu, for ever.
TEST(Contacts, StaticFrictionHoldsARodOnASlopeBelowTheFrictionAngle) {
  const double tan_theta = 0.5, mu = 1.0, v_s = 0.01, k_t = 1e4;
  for (const bool on_box : {false, true}) {
    for (const Scheme scheme : {Scheme::kImplicit, Scheme::kExact, Scheme::kGaussSeidel}) {
      SCOPED_TRACE(std::string(to_string(scheme)) + (on_box ? " on a box" : " on the floor"));
      const double dt = scheme == Scheme::kImplicit ? 0.05 : 0.002;
      const SlopeRun held = rod_on_slope(scheme, dt, tan_theta, k_t, on_box, 3.0);
      EXPECT_LT(std::abs(held.travel), 1e-7);
      EXPECT_LT(std::abs(held.speed), 1e-7);
      // the explicit schemes take the creep's viscous friction, mu N / v_s = 439 N s/m at each
      // end, stably only for dt < 2 m_eff / c (m_eff = m / 4 at an end: 0.0011 s)
      const double creep_dt = scheme == Scheme::kImplicit ? dt : 2e-4;
      const SlopeRun crept = rod_on_slope(scheme, creep_dt, tan_theta, 0.0, on_box, 3.0);
      const double creep = v_s * tan_theta / mu;
      EXPECT_NEAR(crept.speed, creep, 1e-3 * creep);
      EXPECT_NEAR(crept.travel, 3.0 * creep, 1e-2 * 3.0 * creep);
    }
  }
}

// The stretch that holds it is the analytic one: at rest the two ends' anchor springs carry the
// rod's weight along the slope, k_t (s_1 + s_2) = m g sin(theta), about half each (the friction
// acts a radius below the centre of mass, so the lower end presses a little harder). How the two
// share it is not fixed by statics (two springs in parallel hold one load): it is set by how the
// rod landed. The implicit step lands it in its first step, retaken with the contacts it reached
// (implicit_advance.h), where the energy guard used to halve its fall into the floor: the ends'
// shares are 48.3 : 51.7 of the load now, within 1% of half each then.
TEST(Contacts, StaticFrictionStretchesByTheLoadOverItsStiffness) {
  const double tan_theta = 0.5, k_t = 1e4;
  const double theta = std::atan(tan_theta);
  const double total = 9.81 * std::sin(theta) / k_t;
  for (const Scheme scheme : {Scheme::kImplicit, Scheme::kExact}) {
    SCOPED_TRACE(to_string(scheme));
    // explicit: below 2 m_eff / c for the stuck contact's viscous share, (mu N - T) / v_s
    const double dt = scheme == Scheme::kImplicit ? 0.05 : 5e-4;
    Scene s = floor_scene(lying_rod(0.06), scheme, dt);
    s.gravity_world = 9.81 * Vec3(std::sin(theta), 0, -std::cos(theta));
    s.params.friction_stiffness = k_t;
    SimState st;
    init_state(s, st);
    for (int k = 0; k < static_cast<int>(std::lround(3.0 / dt)); ++k) step(s, st);
    EXPECT_LT(kinetic_energy(s.rig, st), 1e-12);
    ASSERT_EQ(st.contact.anchors.size(), 2u);
    const Vec3 sum = st.contact.anchors[0].stretch_world + st.contact.anchors[1].stretch_world;
    EXPECT_NEAR(sum.x(), total, 1e-6 * total);
    EXPECT_NEAR(sum.y(), 0.0, 1e-9 * total);
    for (const FrictionAnchor& a : st.contact.anchors) {
      EXPECT_NEAR(a.stretch_world.x(), total / 2.0, 0.05 * total / 2.0);
    }
  }
}

// Above it (tan theta = 2 > mu = 1) the rod slides, with kinetic Coulomb friction: it accelerates
// at g (sin theta - mu cos theta), the static spring at its limit and the viscous share gone.
TEST(Contacts, StaticFrictionLetsARodSlideAboveTheFrictionAngle) {
  const double tan_theta = 2.0, mu = 1.0;
  const double theta = std::atan(tan_theta);
  const double a = 9.81 * (std::sin(theta) - mu * std::cos(theta));
  for (const Scheme scheme : {Scheme::kImplicit, Scheme::kExact}) {
    SCOPED_TRACE(to_string(scheme));
    const double dt = scheme == Scheme::kImplicit ? 0.01 : 0.002;
    const SlopeRun t1 = rod_on_slope(scheme, dt, tan_theta, 1e4, false, 0.5);
    const SlopeRun t2 = rod_on_slope(scheme, dt, tan_theta, 1e4, false, 1.0);
    EXPECT_NEAR((t2.speed - t1.speed) / 0.5, a, 1e-3 * a);
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
    out.deepest = std::max(out.deepest, penetration(s, st.contact.found).max_depth_fraction);
  }
  out.tail_world = st.frames.tail_world[2];
  out.final = penetration(s, contacts_at_pose(s, st.frames)).max_depth_fraction;
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
