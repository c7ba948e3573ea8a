// Orientation targets (physik/engine/orientation_springs.h): a lone rod's small-angle oscillation
// at the analytic frequency in every scheme; the capped torque's size; the torque as minus the
// potential's gradient; the modes damping auto sees; the scene fields and their errors.
#include "physik/engine/orientation_springs.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "physik/engine/engine.h"
#include "physik/engine/linear_modes.h"
#include "physik/engine/linear_modes_dense.h"
#include "physik/engine/potential.h"
#include "physik/engine/run_monitor.h"
#include "physik/io/json_fields.h"
#include "physik/io/scene_io.h"
#include "physik/io/scene_warnings.h"
#include "physik/model/errors.h"
#include "tests/engine_test_util.h"
#include "tests/test_util.h"

namespace physik {
namespace {

Quat turn(const Vec3& v) {
  return v.norm() == 0.0 ? Quat::Identity() : Quat(Eigen::AngleAxisd(v.norm(), v.normalized()));
}

OrientationTarget target_of(int bone, const Quat& q, double k, SpringLaw law = SpringLaw::kLinear,
                            double cap = 1.0) {
  OrientationTarget t;
  t.bone = bone;
  t.target_world = q;
  t.k = k;
  t.spring = law;
  t.cap = cap;
  return t;
}

// A free rod, its target turned by theta0 about world x (across the rod, which lies along z):
// with no damping the rod turns about its centre of mass as theta0 cos(w t), w = sqrt(k / I_x),
// I_x its moment about a diameter through the centre (Rig::bone_inertia_local, local x).
TEST(OrientationSprings, SmallAngleOscillationHasTheAnalyticFrequency) {
  const double k = 2.0, theta0 = 0.01, dt = 1e-3;
  for (Scheme scheme : {Scheme::kGaussSeidel, Scheme::kExact, Scheme::kImplicit}) {
    EngineParams p = test::bare_params(dt);
    p.scheme = scheme;
    Scene scene = test::scene_for(test::one_rod(1.0, 1.0, 0.05), p, 1);
    const Quat rest = scene.rig.bone_rest_orient_world[0];
    scene.orientation_targets.push_back(target_of(0, turn(Vec3(theta0, 0, 0)) * rest, k));
    const double inertia = scene.rig.bone_inertia_local[0].x();  // kg m^2, about a diameter
    const double w = std::sqrt(k / inertia);
    const double period = 2.0 * kPi / w;
    SimState s;
    init_state(scene, s);
    // the times phi_x crosses zero going down, interpolated within the step
    std::vector<double> downs;
    double prev =
        orientation_error(s.frames.orient_world[0], scene.orientation_targets[0].target_world).x();
    const int steps = static_cast<int>(4.3 * period / dt);
    for (int n = 0; n < steps; ++n) {
      step(scene, s);
      const double phi =
          orientation_error(s.frames.orient_world[0], scene.orientation_targets[0].target_world)
              .x();
      if (prev > 0.0 && phi <= 0.0) downs.push_back(s.time - dt * phi / (phi - prev));
      prev = phi;
      ASSERT_LT(std::abs(phi), 1.01 * theta0) << to_string(scheme) << ": no energy gained";
    }
    ASSERT_GE(downs.size(), 4u) << to_string(scheme);
    const double measured = (downs.back() - downs.front()) / static_cast<double>(downs.size() - 1);
    // first-order schemes at w dt = 0.005: the period within 1e-3 of 2 pi / w
    EXPECT_NEAR(measured, period, 1e-3 * period) << to_string(scheme);
    // the centre of mass stays put: a couple moves no point
    EXPECT_LT((s.com_world[0] - Vec3(0, 0, 0.5)).norm(), 1e-9) << to_string(scheme);
  }
}

TEST(OrientationSprings, CappedTorqueIsCappedAndLinearWithinTheCap) {
  Scene scene = test::scene_for(test::one_rod(), test::bare_params(), 1);
  SimState s;
  init_state(scene, s);
  const Quat rest = s.frames.orient_world[0];
  const double k = 3.0, cap = 0.3;
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-1.8, 1.8);
  for (int n = 0; n < 200; ++n) {
    const Vec3 v(u(rng), u(rng), u(rng));
    scene.orientation_targets = {target_of(0, turn(v) * rest, k, SpringLaw::kCapped, cap)};
    for (Vec3& t : s.torque_world) t.setZero();
    apply_orientation_springs(scene, s);
    const Vec3 phi = orientation_error(rest, scene.orientation_targets[0].target_world);
    const Vec3& tau = s.torque_world[0];
    ASSERT_LE(tau.norm(), k * cap * (1.0 + 1e-12));
    ASSERT_GE(tau.dot(phi), 0.0);  // toward the target
    if (phi.norm() > cap) {
      ASSERT_NEAR(tau.norm(), k * cap, 1e-12 * k * cap);
    } else {
      ASSERT_TRUE(test::near(tau, k * phi, 1e-12));
    }
  }
}

// tau = -dU/dr, r the bone's turn in world axes, by central differences, linear and capped, up to
// turns near pi (where phi's direction is still defined)
TEST(OrientationSprings, TorqueIsMinusThePotentialsGradient) {
  Scene scene = test::scene_for(test::one_rod(), test::bare_params(), 1);
  SimState s;
  init_state(scene, s);
  const Quat rest = s.frames.orient_world[0];
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1.7, 1.7);
  for (SpringLaw law : {SpringLaw::kLinear, SpringLaw::kCapped}) {
    for (int n = 0; n < 50; ++n) {
      const Vec3 v(u(rng), u(rng), u(rng));
      scene.orientation_targets = {target_of(0, turn(v) * rest, 2.5, law, 0.4)};
      s.frames.orient_world[0] = rest;
      for (Vec3& t : s.torque_world) t.setZero();
      apply_orientation_springs(scene, s);
      const Vec3 tau = s.torque_world[0];
      Vec3 grad;
      const double eps = 1e-6;
      for (int a = 0; a < 3; ++a) {
        const Vec3 e = eps * Vec3::Unit(a);
        s.frames.orient_world[0] = turn(e) * rest;
        const double up = orientation_springs_potential(scene, s);
        s.frames.orient_world[0] = turn(-e) * rest;
        const double down = orientation_springs_potential(scene, s);
        grad[a] = (up - down) / (2.0 * eps);
      }
      ASSERT_TRUE(test::near(tau, -grad, 1e-7)) << to_string(law) << " turn " << v.transpose();
    }
  }
}

// damping auto's modes: a free rod held by an orientation target at its target has three zero
// modes (it translates) and turns at w^2 = k / I about each principal axis; the O(n) path finds
// the dense path's slowest mode
TEST(OrientationSprings, ModesSeeTheCouple) {
  Scene scene = test::scene_for(test::one_rod(1.0, 1.0, 0.05), test::bare_params(), 1);
  const double k = 2.0;
  scene.orientation_targets.push_back(target_of(0, scene.rig.bone_rest_orient_world[0], k));
  SimState s;
  init_state(scene, s);
  const DenseLinearModes dense = linear_modes_dense(scene, s, {});
  ASSERT_EQ(dense.omega.size(), 6u);
  std::vector<double> expect;
  for (int a = 0; a < 3; ++a) expect.push_back(std::sqrt(k / scene.rig.bone_inertia_local[0][a]));
  std::sort(expect.begin(), expect.end());
  for (int i = 0; i < 3; ++i) EXPECT_LT(dense.omega[i], 1e-6);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(dense.omega[3 + i], expect[i], 1e-9 * expect[i]);
  const LinearModes it = linear_modes(scene, s, {});
  ASSERT_TRUE(it.found);
  EXPECT_NEAR(it.slowest_omega, dense.modes.slowest_omega, 1e-8 * dense.modes.slowest_omega);
}

// the ledger counts the orientation springs' potential at the start as the rig's (their targets
// hold still through a run; forces.h toward_targets is the control springs'), so a target that
// starts away from its bone releases energy the rig was given: the run does not read that as a
// divergence
TEST(OrientationSprings, PotentialIsTheListsAndTheLedgerCountsIt) {
  Scene scene = test::scene_for(test::one_rod(), test::bare_params(), 1);
  scene.orientation_targets.push_back(
      target_of(0, turn(Vec3(0.5, 0, 0)) * scene.rig.bone_rest_orient_world[0], 2.0));
  SimState s;
  init_state(scene, s);
  EXPECT_NEAR(potential_energy(scene, s), 0.5 * 2.0 * 0.25, 1e-14);
  EXPECT_NEAR(potential_energy(scene, s, PotentialOf::kAllButTargetSprings), 0.5 * 2.0 * 0.25,
              1e-14);
  EXPECT_NEAR(initial_energy(scene), 0.5 * 2.0 * 0.25, 1e-14);
}

// pinhead's left forearm given a target frame a quarter turn from where it starts, at the
// default stiffness, on the default preset: the run settles on it. Its spring's energy at the
// start, most of what the rig is given, was read as a divergence at step 1 while the ledger left
// it out.
TEST(OrientationSprings, ATargetAwayFromItsBoneIsNoDivergence) {
  Scene scene = load_scene(test::model_path("scenes/pinhead_two_hands.json"),
                           parse_param_overrides({"preset=robust"}, "test"));
  const int b = scene.rig.find_bone("forearm.L");
  OrientationTarget t;
  t.bone = b;
  t.target_world = Quat(std::sqrt(0.5), std::sqrt(0.5), 0.0, 0.0);
  scene.orientation_targets.push_back(t);
  scene.steps = 2000;  // it settles in about 600
  SimState s;
  init_state(scene, s);
  // the target's spring holds most of the energy the rig is given
  const double u = orientation_springs_potential(scene, s), given = initial_energy(scene);
  EXPECT_GT(u, 10.0 * (given - u)) << u << " J of " << given << " J";
  const RunSummary sum = run_scene(scene);
  EXPECT_FALSE(sum.diverged) << sum.divergence_reason;
  EXPECT_TRUE(sum.converged);
  SimState end;
  init_state(scene, end);
  set_pose(scene, end, sum.final_pose);
  EXPECT_LT(orientation_error(end.frames.orient_world[b], t.target_world).norm(), 0.05);
}

Scene parse(const std::string& targets, const std::string& params = "{}") {
  const std::string text = R"({"rig": "elbow.json", "params": )" + params +
                           R"(, "orientation_targets": [)" + targets + "]}";
  return scene_from_json(parse_json_text(text, "bad_scene.json"), "bad_scene.json",
                         test::model_path("rigs"));
}

void expect_error(const std::string& targets, std::initializer_list<const char*> fragments,
                  const std::string& params = "{}") {
  try {
    parse(targets, params);
    FAIL() << "no error for " << targets;
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.rfind("bad_scene.json: ", 0), 0u) << msg;
    for (const char* f : fragments)
      EXPECT_NE(msg.find(f), std::string::npos) << msg << " lacks " << f;
  }
}

TEST(OrientationSprings, SceneFieldsRoundTripAndBadInputIsNamed) {
  const Scene s = parse(R"({"bone": "forearm", "quaternion": [0, 1, 0, 0], "k": 4, "spring":
                        "capped", "cap": 0.2, "name": "palm"})");
  ASSERT_EQ(s.orientation_targets.size(), 1u);
  const OrientationTarget& t = s.orientation_targets[0];
  EXPECT_EQ(s.rig.bone_name[t.bone], "forearm");
  EXPECT_TRUE(t.target_world.isApprox(Quat(0, 1, 0, 0), 1e-15));
  EXPECT_EQ(*t.k, 4.0);
  EXPECT_EQ(*t.cap, 0.2);
  const Json back = scene_to_json(s, true, "");
  EXPECT_EQ(back["orientation_targets"][0]["quaternion"], Json({0.0, 1.0, 0.0, 0.0}));
  EXPECT_EQ(back["orientation_targets"][0]["name"], "palm");
  // unset k and cap follow the params through the bone's length
  const Scene d = parse(R"({"bone": "forearm", "quaternion": [1, 0, 0, 0]})",
                        R"({"control_k": 5, "control_cap": 0.5})");
  const double L = d.rig.bone_length[d.orientation_targets[0].bone];
  EXPECT_NEAR(d.orientation_targets[0].k_in(d.params, d.rig), 5.0 * L * L, 1e-12);
  EXPECT_NEAR(d.orientation_targets[0].cap_in(d.params, d.rig), 0.5 / L, 1e-12);

  expect_error(R"({"bone": "wing", "quaternion": [1, 0, 0, 0]})",
               {"orientation_targets[0]", "'bone'", "unknown bone 'wing'"});
  expect_error(R"({"bone": "forearm", "quaternion": [0, 0, 0, 0]})",
               {"'quaternion'", "zero quaternion"});
  expect_error(R"({"bone": "forearm", "quaternion": [1, 0.1, 0, 0]})",
               {"orientation_targets[0]", "'quaternion'", "not a unit quaternion (norm 1.0049876",
                "more than 1e-3 from 1"});
  expect_error(R"({"bone": "forarm", "quaternion": [1, 0, 0, 0]})",
               {"unknown bone 'forarm' (did you mean 'forearm'?)"});
  expect_error(R"({"bone": "forearm", "quaternion": [1, 0, 0]})", {"'quaternion'", "[w, x, y, z]"});
  expect_error(R"({"bone": "forearm"})", {"'quaternion'"});
  expect_error(R"({"bone": "forearm", "quaternion": [1, 0, 0, 0]},
                  {"bone": "forearm", "quaternion": [0, 1, 0, 0]})",
               {"orientation_targets[1]", "'bone'", "a second target for bone 'forearm'",
                "one of a kind per bone"});
  expect_error(R"({"bone": "forearm", "quaternion": [1, 0, 0, 0], "k": -1})", {"'k'"});
  expect_error(R"({"bone": "forearm", "quaternion": [1, 0, 0, 0], "axis": [1, 0, 0]})", {"axis"});
}

// a quaternion a person types (norm 0.99999) is normalised, with one warning naming the file,
// the element, the field and the norm; 1e-3 from unit is the edge (a qBVH file's), past it refused
TEST(OrientationSprings, TypedQuaternionWithinATenthOfAPercentIsNormalisedWithAWarning) {
  const std::string text =
      R"({"rig": "elbow.json", "orientation_targets": [{"bone": "forearm",
          "quaternion": [0.7071, 0.7071, 0, 0]}, {"bone": "upper_arm", "quaternion": [1, 0, 0, 0]}]})";
  std::vector<std::string> warnings;
  const Scene s = scene_from_json(parse_json_text(text, "typed.json"), "typed.json",
                                  test::model_path("rigs"), {}, warnings);
  const Quat q = s.orientation_targets[0].target_world;
  EXPECT_NEAR(q.norm(), 1.0, 1e-15);
  EXPECT_NEAR(q.w(), std::sqrt(0.5), 1e-15);  // the typed direction, exactly unit
  EXPECT_NEAR(q.x(), std::sqrt(0.5), 1e-15);
  ASSERT_EQ(warnings.size(), 1u);  // the unit one says nothing
  EXPECT_EQ(warnings[0],
            "typed.json: orientation_targets[0]: field 'quaternion': norm 0.99999041 (within "
            "1e-3 of 1): normalised to unit");
  EXPECT_EQ(
      parse(R"({"bone": "forearm", "quaternion": [1.000999, 0, 0, 0]})").orientation_targets.size(),
      1u);
  expect_error(R"({"bone": "forearm", "quaternion": [1.001001, 0, 0, 0]})",
               {"not a unit quaternion (norm 1.001001, more than 1e-3 from 1)"});
  expect_error(R"({"bone": "forearm", "quaternion": [0.998, 0, 0, 0]})",
               {"not a unit quaternion (norm 0.998, more than 1e-3 from 1)"});
}

}  // namespace
}  // namespace physik
