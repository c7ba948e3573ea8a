// Aim targets (physik/engine/aim_springs.h): the couple and the head's force as minus the
// potential's gradient; at rest the axis points at the target; the scene fields and their errors.
#include "physik/engine/aim_springs.h"

#include <cmath>
#include <random>
#include <sstream>

#include <gtest/gtest.h>

#include "physik/engine/engine.h"
#include "physik/engine/potential.h"
#include "physik/io/json_fields.h"
#include "physik/io/scene_io.h"
#include "physik/model/bone_targets.h"
#include "physik/model/errors.h"
#include "tests/engine_test_util.h"
#include "tests/test_util.h"

namespace physik {
namespace {

Quat turn(const Vec3& v) {
  return v.norm() == 0.0 ? Quat::Identity() : Quat(Eigen::AngleAxisd(v.norm(), v.normalized()));
}

AimTarget aim_of(int bone, const Vec3& point, double k, SpringLaw law = SpringLaw::kLinear,
                 double cap = 1.0, const Vec3& axis = Vec3::UnitY()) {
  AimTarget t;
  t.bone = bone;
  t.point_world = point;
  t.axis_bone = axis.normalized();
  t.k = k;
  t.spring = law;
  t.cap = cap;
  return t;
}

// the bone's frames moved rigidly: turned by r about its centre, then shifted by x
void place(const Rig& rig, const Vec3& r, const Vec3& x, SimState& s) {
  const Quat q = turn(r) * rig.bone_rest_orient_world[0];
  const Vec3 c = 0.5 * (rig.bone_rest_head_world[0] + rig.bone_rest_tail_world[0]);
  s.frames.orient_world[0] = q;
  s.frames.head_world[0] = c + x + turn(r) * (rig.bone_rest_head_world[0] - c);
  s.frames.tail_world[0] = c + x + turn(r) * (rig.bone_rest_tail_world[0] - c);
  s.com_world[0] = c + x;
}

// the aim's couple and force, as a wrench about the centre of mass, are minus the gradient of its
// potential in the bone's turn about the centre and its translation: both laws, axes off the bone
TEST(AimSprings, WrenchIsMinusThePotentialsGradient) {
  Scene scene = test::scene_for(test::one_rod(), test::bare_params(), 1);
  SimState s;
  init_state(scene, s);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  for (SpringLaw law : {SpringLaw::kLinear, SpringLaw::kCapped}) {
    for (int n = 0; n < 50; ++n) {
      const Vec3 point(u(rng), u(rng), u(rng));
      const Vec3 axis(u(rng), u(rng), u(rng));
      scene.aim_targets = {aim_of(0, point, 1.5, law, 0.5, axis)};
      const Vec3 r0(0.3 * u(rng), 0.3 * u(rng), 0.3 * u(rng));
      place(scene.rig, r0, Vec3::Zero(), s);
      if ((point - s.frames.head_world[0]).norm() < 0.3) continue;
      for (Vec3& f : s.force_world) f.setZero();
      for (Vec3& t : s.torque_world) t.setZero();
      apply_aim_springs(scene, s);
      const Vec3 force = s.force_world[0], torque = s.torque_world[0];
      Vec3 grad_turn, grad_move;
      const double eps = 1e-6;
      for (int a = 0; a < 3; ++a) {
        const Vec3 e = eps * Vec3::Unit(a);
        const auto u_at = [&](const Vec3& r, const Vec3& x) {
          // a turn e about the centre after r0: turn(e) turn(r0) = turn(r) to first order is not
          // exact, so compose the frames directly
          SimState t = s;
          const Vec3 c = s.com_world[0];
          const Quat q = turn(r);
          t.frames.orient_world[0] = q * s.frames.orient_world[0];
          t.frames.head_world[0] = c + x + q * (s.frames.head_world[0] - c);
          t.frames.tail_world[0] = c + x + q * (s.frames.tail_world[0] - c);
          return aim_springs_potential(scene, t);
        };
        grad_turn[a] = (u_at(e, Vec3::Zero()) - u_at(-e, Vec3::Zero())) / (2.0 * eps);
        grad_move[a] = (u_at(Vec3::Zero(), e) - u_at(Vec3::Zero(), -e)) / (2.0 * eps);
      }
      ASSERT_TRUE(test::near(torque, -grad_turn, 1e-6)) << to_string(law) << " case " << n;
      ASSERT_TRUE(test::near(force, -grad_move, 1e-6)) << to_string(law) << " case " << n;
    }
  }
}

// an aim's rest is its axis on the target: a damped free rod aimed at a point off its axis comes
// to rest with the axis pointing at it, in every scheme
TEST(AimSprings, RestIsTheAlignedAxis) {
  for (Scheme scheme : {Scheme::kGaussSeidel, Scheme::kExact, Scheme::kImplicit}) {
    EngineParams p = preset_params("original");
    p.scheme = scheme;
    p.dt = 0.01;
    Scene scene = test::scene_for(test::one_rod(1.0, 1.0, 0.1), p, 1);
    scene.aim_targets = {aim_of(0, Vec3(2.0, 1.0, 0.5), 2.0, SpringLaw::kCapped, 0.5)};
    SimState s;
    init_state(scene, s);
    const double start = aim_turn(s.frames, scene.aim_targets[0]).turn.norm();
    ASSERT_GT(start, 1.0);
    for (int n = 0; n < 4000; ++n) step(scene, s);
    const AimTurn at = aim_turn(s.frames, scene.aim_targets[0]);
    EXPECT_LT(at.turn.norm(), 1e-3 * start) << to_string(scheme);
    EXPECT_GT(at.axis_world.dot(at.direction_world), 1.0 - 1e-6) << to_string(scheme);
  }
}

Scene parse(const std::string& aims, const std::string& extra = "") {
  const std::string text = R"({"rig": "elbow.json", "aim_targets": [)" + aims + "]" + extra + "}";
  return scene_from_json(parse_json_text(text, "bad_scene.json"), "bad_scene.json",
                         test::model_path("rigs"));
}

void expect_error(const std::string& aims, std::initializer_list<const char*> fragments,
                  const std::string& extra = "") {
  try {
    parse(aims, extra);
    FAIL() << "no error for " << aims;
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.rfind("bad_scene.json: ", 0), 0u) << msg;
    for (const char* f : fragments)
      EXPECT_NE(msg.find(f), std::string::npos) << msg << " lacks " << f;
  }
}

TEST(AimSprings, SceneFieldsRoundTripAndBadInputIsNamed) {
  const Scene s = parse(R"({"bone": "forearm", "point": [1, 2, 3], "axis": [0, 0, 2], "k": 3})");
  ASSERT_EQ(s.aim_targets.size(), 1u);
  EXPECT_TRUE(test::near(s.aim_targets[0].axis_bone, Vec3(0, 0, 1), 0.0));
  EXPECT_TRUE(test::near(s.aim_targets[0].point_world, Vec3(1, 2, 3), 0.0));
  const Json back = scene_to_json(s, true, "");
  EXPECT_EQ(back["aim_targets"][0]["axis"], Json({0.0, 0.0, 1.0}));
  EXPECT_EQ(back["aim_targets"][0]["k"], 3.0);
  const int forearm = s.rig.find_bone("forearm");
  const Vec3 head = s.rig.bone_rest_head_world[forearm];
  const std::string on_head = "[" + std::to_string(head.x()) + ", " + std::to_string(head.y()) +
                              ", " + std::to_string(head.z()) + "]";
  expect_error(R"({"bone": "forearm", "point": )" + on_head + "}",
               {"aim_targets[0]", "'point'", "head"});
  expect_error(R"({"bone": "wing", "point": [1, 0, 0]})", {"'bone'", "unknown bone 'wing'"});
  expect_error(R"({"bone": "forearm", "point": [1, 0, 0], "axis": [0, 0, 0]})", {"'axis'", "zero"});
  expect_error(R"({"bone": "forearm"})", {"'point'"});
  expect_error(
      R"({"bone": "forearm", "point": [1, 0, 0]}, {"bone": "forearm", "point": [0, 1, 0]})",
      {"aim_targets[1]", "a second target for bone 'forearm'"});
  expect_error(R"({"bone": "forearm", "point": [1e10, 0, 0]})",
               {"aim_targets[0]", "'point'", "beyond +-1e9"});
  expect_error(R"({"bone": "forearm", "point": [1, 0, 0], "cap": -1})", {"'cap'"});
  expect_error(R"({"bone": "forarm", "point": [1, 0, 0]})",
               {"'bone'", "unknown bone 'forarm' (did you mean 'forearm'?)"});
}

// an axis whose squared norm overflows (1e155^2 = inf) or underflows (1e-170^2 = 0) is still a
// direction: normalised after scaling, it is the unit axis, and the aim turns the bone toward it
TEST(AimSprings, AxisOfExtremeScaleIsNormalisedNotZeroed) {
  for (const char* axis : {"[0, 1e155, 0]", "[0, 0, -1e300]", "[1e-170, 0, 0]"}) {
    const Scene s =
        parse(std::string(R"({"bone": "forearm", "point": [1, 2, 3], "axis": )") + axis + "}");
    const Vec3 a = s.aim_targets[0].axis_bone;
    EXPECT_NEAR(a.norm(), 1.0, 1e-15) << axis;
    EXPECT_EQ(a.cwiseAbs().maxCoeff(), 1.0) << axis;  // the one nonzero component, +-1
    SimState st;
    init_state(s, st);
    EXPECT_GT(aim_turn(st.frames, s.aim_targets[0]).turn.norm(), 1e-3) << axis;  // it pulls
  }
}

// a point nearer the head than kAimMinDistancePerLength of the bone's length is refused, with
// the distance and the minimum; just past the minimum it is accepted
TEST(AimSprings, PointNearerTheHeadThanATenthOfTheBoneIsRefused) {
  const Scene s = parse(R"({"bone": "forearm", "point": [1, 2, 3]})");
  const int forearm = s.rig.find_bone("forearm");
  const Vec3 head = s.rig.bone_rest_head_world[forearm];
  const double least = kAimMinDistancePerLength * s.rig.bone_length[forearm];
  const auto at = [&](double d) {
    const Vec3 p = head + Vec3(0, 0, d);
    std::ostringstream o;
    o.precision(17);
    o << R"({"bone": "forearm", "point": [)" << p.x() << ", " << p.y() << ", " << p.z() << "]}";
    return o.str();
  };
  expect_error(at(1e-5), {"aim_targets[0]", "'point'",
                          "lies 1e-05 rig units from the head of "
                          "bone 'forearm'",
                          "at least 0.1 of its bone's length"});
  expect_error(at(0.99 * least), {"'point'", "at least 0.1 of its bone's length"});
  EXPECT_EQ(parse(at(1.01 * least)).aim_targets.size(), 1u);
}

}  // namespace
}  // namespace physik
