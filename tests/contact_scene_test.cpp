// The scene and rig format's contact fields (physik/io/scene_io.h, rig_io.h): gravity, ground,
// self-collision, exclusions and collision radii read and written back, and each bad value refused
// naming its field.
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "physik/io/scene_io.h"
#include "physik/model/errors.h"

namespace physik {
namespace {

const char* kRig =
    R"({"bones": [{"name": "a", "parent": null, "head": [0,0,0], "tail": [0,0,1]},
                  {"name": "b", "parent": "a", "head": [0,0,1], "tail": [0,0,2],
                   "collision_radius": 0.2}]})";

Scene scene_text(const std::string& fields) {
  const auto doc = nlohmann::json::parse("{\"rig\": " + std::string(kRig) + fields + "}");
  return scene_from_json(doc, "s.json", ".");
}

std::string error_of(const std::string& fields) {
  try {
    scene_text(fields);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(ContactScene, FieldsReadAndWrittenBack) {
  const Scene s = scene_text(
      R"(, "gravity": [0, 0, -9.81], "ground": {"height": 0.5, "normal": [0, 0, 2]},
         "self_collision": true, "collision_exclude": [["b", "a"]])");
  EXPECT_EQ(s.gravity_world, Vec3(0, 0, -9.81));
  ASSERT_TRUE(s.collision.ground.has_value());
  EXPECT_EQ(s.collision.ground->normal_world, Vec3::UnitZ());
  EXPECT_EQ(s.collision.ground->height, 0.5);
  EXPECT_EQ(s.collision.excluded_pairs, (std::vector<std::pair<int, int>>{{0, 1}}));
  EXPECT_NEAR(s.rig.bone_collision_radius[0], kCollisionRadiusPerLength, 1e-15);
  EXPECT_EQ(s.rig.bone_collision_radius[1], 0.2);
  const Scene back = scene_from_json(scene_to_json(s, true), "back.json", ".");
  EXPECT_EQ(back.gravity_world, s.gravity_world);
  EXPECT_EQ(back.collision.excluded_pairs, s.collision.excluded_pairs);
  EXPECT_EQ(back.rig.bone_collision_radius, s.rig.bone_collision_radius);
  const Scene plain = scene_text("");
  EXPECT_FALSE(plain.collision.any());
  EXPECT_TRUE(plain.gravity_world.isZero(0.0));
}

TEST(ContactScene, ObstaclesReadAndWrittenBack) {
  const Scene s = scene_text(
      R"(, "obstacles": [{"name": "seat", "box": {"center": [0, 1, -0.5],
                          "half_extents": [0.6, 0.4, 0.25], "rotation_deg": [0, 0, 90]}},
                         {"name": "step", "box": {"center": [2, 0, 0], "half_extents": [1, 1, 1]}}])");
  ASSERT_EQ(s.collision.obstacles.size(), 2u);
  EXPECT_TRUE(s.collision.any());
  const BoxObstacle& seat = s.collision.obstacles[0];
  EXPECT_EQ(seat.name, "seat");
  EXPECT_EQ(seat.center_world, Vec3(0, 1, -0.5));
  EXPECT_EQ(seat.half_extents, Vec3(0.6, 0.4, 0.25));
  EXPECT_NEAR((seat.orient_world * Vec3::UnitX() - Vec3::UnitY()).norm(), 0.0, 1e-12);
  EXPECT_TRUE(s.collision.obstacles[1].orient_world.isApprox(Quat::Identity(), 0.0));
  const Scene back = scene_from_json(scene_to_json(s, true), "back.json", ".");
  ASSERT_EQ(back.collision.obstacles.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    const BoxObstacle &a = s.collision.obstacles[i], &b = back.collision.obstacles[i];
    EXPECT_EQ(a.name, b.name);
    EXPECT_EQ(a.center_world, b.center_world);
    EXPECT_EQ(a.half_extents, b.half_extents);
    EXPECT_LT(a.orient_world.angularDistance(b.orient_world), 1e-12);
  }
}

TEST(ContactScene, BadObstaclesNameTheField) {
  const auto error_with = [](const std::string& obstacle) {
    return error_of(R"(, "obstacles": [)" + obstacle + "]");
  };
  const std::string box = R"("box": {"center": [0, 0, 0], "half_extents": [1, 1, 1]})";
  EXPECT_NE(error_of(R"(, "obstacles": {})").find("field 'obstacles': expected an array"),
            std::string::npos);
  EXPECT_NE(error_with("{" + box + "}").find("obstacles[0]: field 'name': missing"),
            std::string::npos);
  EXPECT_NE(error_with(R"({"name": "", )" + box + "}").find("field 'name': must not be empty"),
            std::string::npos);
  EXPECT_NE(error_with(R"({"name": "a", )" + box + R"(}, {"name": "a", )" + box + "}")
                .find("obstacles[1]: field 'name': duplicate obstacle name 'a'"),
            std::string::npos);
  EXPECT_NE(error_with(R"({"name": "a", "sphere": {"radius": 1}})")
                .find("obstacles[0]: field 'sphere': unknown shape"),
            std::string::npos);
  EXPECT_NE(error_with(R"({"name": "a"})").find("obstacles[0]: field 'box': missing"),
            std::string::npos);
  EXPECT_NE(error_with(R"({"name": "a", "box": {"center": [0, 0, 0]}})")
                .find("obstacles[0] box: field 'half_extents': missing"),
            std::string::npos);
  EXPECT_NE(error_with(R"({"name": "a", "box": {"center": [0, 0, 0], "half_extents": [1, -1, 1]}})")
                .find("field 'half_extents': each must be positive"),
            std::string::npos);
  EXPECT_NE(error_with(R"({"name": "a", "box": {"center": [0, 0, 0], "half_extents": [1, 0, 1]}})")
                .find("field 'half_extents': each must be positive"),
            std::string::npos);
  EXPECT_NE(
      error_with(R"({"name": "a", "box": {"center": [0, 0, 0], "half_extents": [1, 1e300, 1]}})")
          .find("field 'half_extents': a coordinate beyond"),
      std::string::npos);
  EXPECT_NE(
      error_with(R"({"name": "a", "box": {"center": [0, 1e300, 0], "half_extents": [1, 1, 1]}})")
          .find("field 'center': a coordinate beyond"),
      std::string::npos);
  EXPECT_NE(error_with(R"({"name": "a", "box": {"center": [0, 0], "half_extents": [1, 1, 1]}})")
                .find("field 'center'"),
            std::string::npos);
  EXPECT_NE(error_of(R"(, "params": {"contact_k": 5})").find("ground, obstacles or"),
            std::string::npos);
  // an obstacle alone makes the contact params apply
  EXPECT_EQ(error_with(R"({"name": "a", )" + box + "}"), "");
}

TEST(ContactScene, BadFieldsNameTheField) {
  EXPECT_NE(error_of(R"(, "ground": {"normal": [0, 0, 0]})").find("field 'normal': zero length"),
            std::string::npos);
  EXPECT_NE(error_of(R"(, "gravity": [0, 0, 1e300])").find("field 'gravity'"), std::string::npos);
  EXPECT_NE(error_of(R"(, "self_collision": true, "collision_exclude": [["a", "z"]])")
                .find("field 'collision_exclude[0]': unknown bone 'z'"),
            std::string::npos);
  EXPECT_NE(error_of(R"(, "ground": {}, "params": {"contact_k": -5})").find("field 'contact_k'"),
            std::string::npos);
  EXPECT_NE(error_of(R"(, "params": {"friction": 0.5})").find("field 'friction': applies only"),
            std::string::npos);
}

}  // namespace
}  // namespace physik
