// Pins (physik/engine/pins.h): a pinned bone stays within the stated tolerance under a pull; the
// force is minus the potential's gradient; the scene fields and their errors.
#include "physik/engine/pins.h"

#include <cmath>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "physik/engine/engine.h"
#include "physik/engine/potential.h"
#include "physik/io/json_fields.h"
#include "physik/io/rig_io.h"
#include "physik/io/scene_io.h"
#include "physik/model/errors.h"
#include "tests/engine_test_util.h"
#include "tests/test_util.h"

namespace physik {
namespace {

// A rod pinned at its head, its tail pulled sideways by a control spring: the pin gives way by
// |F| / k_pin, F the force on it (pins.h). At rest the pin's force balances the control spring's,
// so the head lies |F_c| / k_pin from the pin's point; on the way there it stays within twice the
// largest control force over k_pin (a suddenly applied load on a spring overshoots at most 2x).
TEST(Pins, PinnedBoneStaysWithinTheStatedTolerance) {
  for (Scheme scheme : {Scheme::kExact, Scheme::kImplicit, Scheme::kGaussSeidel}) {
    EngineParams p = preset_params("original");
    p.scheme = scheme;
    p.dt = 0.01;
    Scene scene = test::scene_for(test::one_rod(1.0, 1.0, 0.1), p, 1);
    scene.control_points.push_back(test::control(0, 1.0, Vec3(1.5, 0.0, 0.5), 10.0));
    Pin pin;
    pin.bone = 0;
    pin.alpha = 0.0;
    pin.point_world = Vec3::Zero();
    scene.pins.push_back(pin);
    const double k_pin = pin.k_in(scene.params);
    ASSERT_EQ(k_pin, kPinStiffnessPerControlK * 10.0);
    SimState s;
    init_state(scene, s);
    double worst = 0.0, worst_force = 0.0;
    for (int n = 0; n < 3000; ++n) {
      step(scene, s);
      worst = std::max(worst, s.frames.head_world[0].norm());
      worst_force = std::max(worst_force, s.control_force_world[0].norm());
    }
    const double force = s.control_force_world[0].norm();
    ASSERT_GT(force, 1.0) << to_string(scheme);  // the pull is on at the end
    EXPECT_NEAR(s.frames.head_world[0].norm(), force / k_pin, 0.02 * force / k_pin)
        << to_string(scheme);
    EXPECT_LE(worst, 2.0 * worst_force / k_pin) << to_string(scheme);
    // the rod turned toward the pull about its pinned head
    EXPECT_GT((s.frames.tail_world[0] - s.frames.head_world[0]).normalized().x(), 0.9)
        << to_string(scheme);
  }
}

TEST(Pins, ForceIsMinusThePotentialsGradient) {
  Scene scene = test::scene_for(test::one_rod(), test::bare_params(), 1);
  Pin pin;
  pin.bone = 0;
  pin.alpha = 0.3;
  pin.point_world = Vec3(0.2, -0.4, 0.1);
  pin.k = 50.0;
  scene.pins.push_back(pin);
  SimState s;
  init_state(scene, s);
  for (Vec3& f : s.force_world) f.setZero();
  apply_pins(scene, s);
  const double eps = 1e-6;
  Vec3 grad;
  for (int a = 0; a < 3; ++a) {
    SimState t = s;
    for (Vec3* p : {&t.frames.head_world[0], &t.frames.tail_world[0]}) (*p)[a] += eps;
    const double up = pins_potential(scene, t);
    for (Vec3* p : {&t.frames.head_world[0], &t.frames.tail_world[0]}) (*p)[a] -= 2.0 * eps;
    grad[a] = (up - pins_potential(scene, t)) / (2.0 * eps);
  }
  EXPECT_TRUE(test::near(s.force_world[0], -grad, 1e-6));
  EXPECT_NEAR(potential_energy(scene, s),
              0.5 * 50.0 * (point_on_bone(s.frames, 0, 0.3) - pin.point_world).squaredNorm(),
              1e-12);
}

Scene parse(const std::string& pins, const std::string& rig = "elbow.json",
            const std::string& extra = "") {
  const std::string text = R"({"rig": ")" + rig + R"(", "pins": [)" + pins + "]" + extra + "}";
  return scene_from_json(parse_json_text(text, "bad_scene.json"), "bad_scene.json",
                         test::model_path("rigs"));
}

void expect_error(const std::string& pins, std::initializer_list<const char*> fragments,
                  const std::string& rig = "elbow.json", const std::string& extra = "") {
  try {
    parse(pins, rig, extra);
    FAIL() << "no error for " << pins;
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.rfind("bad_scene.json: ", 0), 0u) << msg;
    for (const char* f : fragments)
      EXPECT_NE(msg.find(f), std::string::npos) << msg << " lacks " << f;
  }
}

TEST(Pins, SceneFieldsRoundTripAndBadInputIsNamed) {
  // a pin with no point holds the point where the initial pose puts it
  const Scene s = parse(R"({"bone": "forearm", "alpha": 1})");
  ASSERT_EQ(s.pins.size(), 1u);
  const BoneFrames f = forward_kinematics(s.rig, s.initial_pose);
  EXPECT_TRUE(test::near(s.pins[0].point_world, f.tail_world[s.pins[0].bone], 1e-15));
  const Json back = scene_to_json(s, true, "");
  EXPECT_EQ(back["pins"][0]["alpha"], 1.0);
  EXPECT_EQ(back["pins"][0]["point"].size(), 3u);
  expect_error(R"({"bone": "wing"})", {"pins[0]", "'bone'", "unknown bone 'wing'"});
  expect_error(R"({"bone": "forearm", "alpha": 2})", {"'alpha'"});
  expect_error(R"({"bone": "forearm", "k": 0})", {"'k'", "above 0"});
  expect_error(R"({"bone": "forearm", "k": -5})", {"'k'"});
  expect_error(R"({"bone": "forearm", "point": [0, 2e9, 0]})", {"'point'", "1e9"});
  // a welded bone moves with its weld: the weld is the body to pin
  const std::string welded =
      (std::filesystem::temp_directory_path() / "physik_pins_test_welded.json").string();
  std::ofstream(welded) << rig_to_json(test::welded_figure()).dump();
  expect_error(R"({"bone": "hip.L"})", {"'bone'", "'hip.L' is welded to 'spine'"}, welded);
  expect_error(R"({"bone": "forearm"}, {"bone": "forearm", "alpha": 1})",
               {"pins[1]", "a second target for bone 'forearm'"});
  EXPECT_EQ(parse(R"({"bone": "spine"})", welded).pins.size(), 1u);
}

}  // namespace
}  // namespace physik
