// The per-step path allocates nothing: count global allocations around step().
#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <new>

#include <gtest/gtest.h>

#include "physik/engine/engine.h"
#include "physik/io/scene_io.h"
#include "physik/model/scaled_scene.h"
#include "physik/posing/posing_session.h"
#include "tests/engine_test_util.h"
#include "tests/test_util.h"

namespace {
std::atomic<bool> g_counting{false};
std::atomic<long> g_allocations{0};
}  // namespace

void* operator new(std::size_t n) {
  if (g_counting.load(std::memory_order_relaxed)) g_allocations.fetch_add(1);
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
// the nothrow form too (std::stable_sort's temporary buffer takes it): otherwise the runtime's
// own would allocate what the free() above releases (AddressSanitizer: alloc-dealloc-mismatch)
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  if (g_counting.load(std::memory_order_relaxed)) g_allocations.fetch_add(1);
  return std::malloc(n ? n : 1);
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}
void operator delete(void* p, const std::nothrow_t&) noexcept {
  std::free(p);
}

namespace physik {
namespace {

TEST(EngineAllocations, StepAllocatesNothing) {
  for (const char* integration : {"articulated", "free-rods", "exact", "implicit"}) {
    Scene scene = load_scene(test::model_path("scenes/pinhead_two_hands.json"));
    scene.params.free_rods = std::string(integration) == "free-rods";
    if (std::string(integration) == "exact") scene.params.scheme = Scheme::kExact;
    if (std::string(integration) == "implicit") {
      scene.params.scheme = Scheme::kImplicit;
      scene.params.torsion_spring = SpringLaw::kCapped;
    }
    scene.params.interpolation = Interpolation::kPolarCom;
    scene.schedule.push_back({20, 0, Vec3(1.0, -1.0, 0.5)});
    SimState s;
    init_state(scene, s);
    step(scene, s);  // warm up
    g_allocations = 0;
    g_counting = true;
    for (int n = 0; n < 100; ++n) step(scene, s);
    g_counting = false;
    EXPECT_EQ(g_allocations.load(), 0) << integration;
  }
}

// The implicit step's energy guard splits a step without allocating: its snapshots are sized by
// init_state (the 0.1x pinhead at c = 100, its locks held by springs, splits its first steps,
// implicit_advance_test.cpp).
TEST(EngineAllocations, ASplitImplicitStepAllocatesNothing) {
  Scene scene =
      scaled_scene(load_scene(test::model_path("scenes/pinhead_two_hands.json")), 0.1, 1.0);
  scene.rig = test::with_spring_locks(scene.rig);
  scene.params.scheme = Scheme::kImplicit;
  scene.params.interpolation = Interpolation::kNone;
  scene.params.damping = 100.0;
  SimState s;
  init_state(scene, s);
  g_allocations = 0;
  g_counting = true;
  for (int n = 0; n < 10; ++n) step(scene, s);
  g_counting = false;
  EXPECT_EQ(g_allocations.load(), 0);
  EXPECT_GT(s.implicit.split_steps, 0) << "the case must split to test the split";
}

// Contacts in every scheme: pinhead's feet in a floor and a foot on a block under gravity, its
// hands pulled toward its torso with self-collision, so that ground and box contacts are found
// every step (the box's through FCL's sphere-box routine) and FCL's broad phase is refitted and its
// capsule distances asked (for the pairs whose boxes overlap). The contact lists are reserved by
// init_state; FCL's tree update and distance queries must not allocate either. With static
// friction on too: the anchors (and the energy guard's copies of them) are reserved with the
// contacts. The locks are held by springs (test::with_spring_locks): with its knees hinges the
// pinhead's feet do not reach the block within the run in the exact and implicit schemes.
TEST(EngineAllocations, ContactStepsAllocateNothing) {
  for (const double friction_stiffness : {0.0, 1e4})
    for (const Scheme scheme : {Scheme::kGaussSeidel, Scheme::kExact, Scheme::kImplicit}) {
      SCOPED_TRACE("friction_stiffness " + std::to_string(friction_stiffness));
      Scene scene = load_scene(test::model_path("scenes/pinhead_two_hands.json"));
      scene.rig = test::with_spring_locks(scene.rig);
      scene.params.friction_stiffness = friction_stiffness;
      scene.params.scheme = scheme;
      scene.params.dt = scheme == Scheme::kImplicit ? 0.05 : 0.002;
      scene.params.interpolation = Interpolation::kNone;
      scene.gravity_world = Vec3(0, 0, -9.81);
      scene.collision.ground = GroundPlane{Vec3::UnitZ(), -2.45};  // the feet sink at once
      // a block under the right foot, its top level with the floor (FCL's sphere-box,
      // the deepest-point search)
      scene.collision.obstacles = {
          BoxObstacle{"block", Vec3(-0.43, 0, -2.95), Vec3(0.3, 0.3, 0.5), Quat::Identity()}};
      scene.collision.self_collision = true;
      for (ControlPoint& c : scene.control_points) c.target_world = Vec3(0.0, 0.0, 1.0);
      SimState s;
      init_state(scene, s);
      for (int n = 0; n < 20; ++n) step(scene, s);  // warm up
      g_allocations = 0;
      g_counting = true;
      int box_steps = 0;  // steps that found a contact with the box
      for (int n = 0; n < 50; ++n) {
        step(scene, s);
        box_steps += std::any_of(s.contact.found.begin(), s.contact.found.end(),
                                 [](const Contact& c) { return c.obstacle == 0; });
      }
      g_counting = false;
      EXPECT_GT(s.contact.found.size(), 0u) << to_string(scheme);
      EXPECT_GT(box_steps, 0) << to_string(scheme) << ": the box must be touched to test it";
      if (friction_stiffness > 0.0) {
        EXPECT_GT(s.contact.anchors.size(), 0u) << to_string(scheme);
      }
      EXPECT_EQ(g_allocations.load(), 0) << to_string(scheme);
    }
}

// The embedding API's per-frame calls allocate nothing either: a target moved, a few steps, and
// a physics-only solve.
TEST(EngineAllocations, PosingSessionCallsAllocateNothing) {
  PosingSession session(load_scene(test::model_path("scenes/pinhead_two_hands.json")));
  const Vec3 start = session.state().target_goal_world[0];
  session.advance(1);  // warm up
  g_allocations = 0;
  g_counting = true;
  for (int frame = 0; frame < 20; ++frame) {
    session.set_target(0, start + Vec3(0.0, 0.0, 0.01 * frame));
    session.advance(3);
  }
  const SolveResult r = session.solve();
  g_counting = false;
  EXPECT_EQ(g_allocations.load(), 0);
  EXPECT_TRUE(r.converged);
}

// Bone targets set between steps (the scene's lists grow: allocations outside the step): the
// steps after them, under every scheme, allocate nothing; moving a target to another place
// (replaced in its list) allocates nothing either.
TEST(EngineAllocations, PosingSessionStepsWithBoneTargetsAllocateNothing) {
  for (Scheme scheme : {Scheme::kGaussSeidel, Scheme::kExact, Scheme::kImplicit}) {
    Scene scene = load_scene(test::model_path("scenes/pinhead_two_hands.json"));
    scene.params.scheme = scheme;
    PosingSession session(scene);
    const Rig& rig = session.scene().rig;
    const int head = rig.find_bone("head"), elbow = rig.find_bone("forearm.L");
    OrientationTarget turn;
    turn.bone = head;
    turn.target_world = session.frames().orient_world[head];
    AimTarget aim;
    aim.bone = rig.find_bone("hand.R");
    aim.point_world = Vec3(-2.0, -1.0, 1.0);
    Pin pin;
    pin.bone = elbow;
    pin.point_world = session.frames().head_world[elbow];
    session.set_orientation_target(turn);
    session.set_aim_target(aim);
    session.set_pin(pin);
    session.advance(1);  // warm up
    g_allocations = 0;
    g_counting = true;
    for (int frame = 0; frame < 10; ++frame) {
      pin.point_world.z() += 0.001;
      session.set_pin(pin);
      session.advance(3);
    }
    g_counting = false;
    EXPECT_EQ(g_allocations.load(), 0) << to_string(scheme);
    EXPECT_EQ(session.scene().pins.size(), 1u);
    EXPECT_TRUE(session.clear_pin(elbow));
    EXPECT_FALSE(session.clear_pin(elbow));
  }
}

// The solve modes' calls as ik_comparison makes them: the pose reset, a target moved along the
// interpolation, then the equilibrium solve (physik) or a lengthening implicit solve
// (physik-steps). With implicit_linearisation full too, whose retakes as Gauss-Newton
// (implicit_step.h) must happen in the counted time-stepping solves.
TEST(EngineAllocations, SolveModeCallsAllocateNothing) {
  for (const SolveRule& rule : {solve_mode_rule(), steps_mode_rule()}) {
    for (ImplicitLinearisation lin :
         {ImplicitLinearisation::kGaussNewton, ImplicitLinearisation::kFull}) {
      Scene scene = load_scene(test::model_path("scenes/pinhead_two_hands.json"));
      use_solve_mode(scene.params);
      scene.params.implicit_linearisation = lin;
      PosingSession session(scene);
      const Vec3 start = session.state().target_goal_world[0];
      session.solve(rule);  // warm up
      int retakes = 0;
      g_allocations = 0;
      g_counting = true;
      for (int k = 1; k <= 5; ++k) {
        session.set_pose(scene.initial_pose);
        session.set_target(0, start + Vec3(0.4 * k, 0.0, -0.4 * k), true);
        session.solve(rule);
        retakes += session.state().implicit.gauss_newton_steps;
      }
      g_counting = false;
      const bool steps = rule.method == SolveMethod::kSteps;
      EXPECT_EQ(g_allocations.load(), 0) << to_string(lin) << (steps ? " steps" : "");
      if (steps && lin == ImplicitLinearisation::kFull) {
        EXPECT_GT(retakes, 0) << "the retake must be tested";
      }
      EXPECT_TRUE(session.solve(rule).converged) << to_string(lin) << (steps ? " steps" : "");
    }
  }
}

}  // namespace
}  // namespace physik
