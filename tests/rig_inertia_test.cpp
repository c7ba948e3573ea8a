// The optional explicit per-bone inertia (BoneSpec::inertia_local, rig field "inertia_local").
#include <gtest/gtest.h>

#include "physik/io/rig_io.h"
#include "physik/model/errors.h"
#include "test_util.h"

namespace physik {
namespace {

TEST(RigInertia, ExplicitMomentsReplaceTheCylinderAndRoundTrip) {
  const Rig rig = rig_from_json_text(
      R"({"bones": [{"name": "a", "parent": null, "head": [0,0,0], "tail": [0,0,2], "mass": 3,
                     "inertia_local": [0.5, 0.2, 0.4]},
                    {"name": "b", "parent": "a", "head": [0,0,2], "tail": [0,0,3]}]})",
      "i.json");
  EXPECT_TRUE(test::near(rig.bone_inertia_local[0], Vec3(0.5, 0.2, 0.4), 0.0));
  EXPECT_TRUE(test::near(rig.bone_inertia_local[1], cylinder_inertia(1.0, 0.5, 1.0), 1e-15));
  const Json doc = rig_to_json(rig);
  EXPECT_TRUE(doc["bones"][0].contains("inertia_local"));
  EXPECT_FALSE(doc["bones"][1].contains("inertia_local"));  // cylinder: not written
  const Rig back = rig_from_json(doc, "back.json");
  EXPECT_TRUE(test::near(back.bone_inertia_local[0], Vec3(0.5, 0.2, 0.4), 1e-15));
}

TEST(RigInertia, ImpossibleMomentsAreRejected) {
  for (const char* in : {"[0.5, 0.1, 0.1]", "[0, 1, 1]", "[-1, 1, 1]", "[1, 1]"}) {
    SCOPED_TRACE(in);
    const std::string text =
        std::string(
            R"({"bones": [{"name": "a", "parent": null, "head": [0,0,0], "tail": [0,0,1], "inertia_local": )") +
        in + "}]}";
    try {
      rig_from_json_text(text, "i.json");
      ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("i.json: bones[0] 'a': field 'inertia_local'"),
                std::string::npos)
          << e.what();
    }
  }
}

}  // namespace
}  // namespace physik
