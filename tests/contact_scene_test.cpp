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
