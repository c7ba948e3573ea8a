// Joint-limit files: application by bone name, round trip, and every bad input.
#include "physik/io/joint_limits.h"

#include <gtest/gtest.h>

#include "physik/io/rig_io.h"
#include "physik/model/errors.h"
#include "test_util.h"
#include "tests/engine_test_util.h"

namespace physik {
namespace {

Rig elbow() {
  return load_rig(test::model_path("rigs/elbow.json"));
}

TEST(JointLimits, AppliedByNameReplacingTheListedBonesOnly) {
  Rig rig = load_rig(test::model_path("rigs/pinhead.json"));
  const Rig before = rig;
  const JointLimits lim =
      joint_limits_from_json(parse_json_text(R"({"comment": "test", "limits_deg": {
        "forearm.L": {"x": [-90, 0]},
        "torso": "locked",
        "upper_arm.L": "free"}})",
                                             "l.json"),
                             "l.json");
  apply_joint_limits(rig, lim);
  const int fa = rig.find_bone("forearm.L");
  EXPECT_TRUE(rig.bone_limit[fa][0].limited);
  EXPECT_DOUBLE_EQ(rig.bone_limit[fa][0].min, -kPi / 2);
  EXPECT_DOUBLE_EQ(rig.bone_limit[fa][0].max, 0.0);
  EXPECT_FALSE(rig.bone_limit[fa][1].limited);  // absent axis: free
  EXPECT_FALSE(rig.bone_limit[fa][2].limited);
  EXPECT_EQ(rig.bone_dof(rig.find_bone("torso")), 0);
  EXPECT_EQ(rig.bone_dof(rig.find_bone("upper_arm.L")), 3);
  for (int a = 0; a < 3; ++a) EXPECT_FALSE(rig.bone_limit[rig.find_bone("upper_arm.L")][a].limited);
  // unlisted bones keep theirs
  const int fr = rig.find_bone("forearm.R");
  for (int a = 0; a < 3; ++a) {
    EXPECT_EQ(rig.bone_limit[fr][a].limited, before.bone_limit[fr][a].limited);
    EXPECT_EQ(rig.bone_limit[fr][a].min, before.bone_limit[fr][a].min);
  }
}

// a free root turns against nothing, a welded bone has nothing to turn: limits on either are
// refused, naming the file and the bone
TEST(JointLimits, NoneOnAFreeRootOrAWeldedBone) {
  Rig rig = load_rig(test::model_path("rigs/pinhead.json"));
  const auto refused = [&](const char* text, const char* fragment) {
    try {
      apply_joint_limits(rig, joint_limits_from_json(parse_json_text(text, "l.json"), "l.json"));
      ADD_FAILURE() << "accepted " << text;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  };
  refused(R"({"limits_deg": {"head": "locked"}})",
          "l.json: limits_deg 'head': the rig's root is free");
  rig = test::welded_figure();
  refused(R"({"limits_deg": {"hip.L": {"x": [-10, 10]}}})",
          "l.json: limits_deg 'hip.L': welded to 'spine'");
  // "free" on a welded bone asks for nothing
  apply_joint_limits(
      rig, joint_limits_from_json(parse_json_text(R"({"limits_deg": {"hip.L": "free"}})", "l.json"),
                                  "l.json"));
}

TEST(JointLimits, WrittenLimitsReapplyToTheSameRig) {
  const Rig src = load_rig(test::model_path("rigs/pinhead.json"));
  Rig free_rig = src;
  for (auto& l : free_rig.bone_limit) l = {};
  apply_joint_limits(free_rig, joint_limits_from_json(joint_limits_to_json(src), "mem"));
  for (int i = 0; i < src.nbone; ++i) {
    for (int a = 0; a < 3; ++a) {
      EXPECT_EQ(free_rig.bone_limit[i][a].limited, src.bone_limit[i][a].limited);
      EXPECT_NEAR(free_rig.bone_limit[i][a].min, src.bone_limit[i][a].min, 1e-12);
      EXPECT_NEAR(free_rig.bone_limit[i][a].max, src.bone_limit[i][a].max, 1e-12);
    }
  }
}

TEST(JointLimits, UnknownBoneIsAnErrorAndLeavesTheRigUnchanged) {
  Rig rig = elbow();
  const Rig before = rig;
  const JointLimits lim = joint_limits_from_json(
      parse_json_text(R"({"limits_deg": {"forearm": {"x": [-10, 0]}, "shin": {"x": [0, 90]}}})",
                      "l.json"),
      "l.json");
  try {
    apply_joint_limits(rig, lim);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("l.json: limits_deg 'shin': unknown bone"),
              std::string::npos)
        << e.what();
  }
  const int f = rig.find_bone("forearm");
  EXPECT_EQ(rig.bone_limit[f][0].min, before.bone_limit[f][0].min);
}

TEST(JointLimits, EveryBadFileIsAnInputErrorNamingBoneAndField) {
  const struct {
    const char* text;
    const char* expect;
  } cases[] = {
      {R"({"limits_deg": {"a": {"w": [0, 1]}}})", "limits_deg 'a': field 'w': unknown axis"},
      {R"({"limits_deg": {"a": {"x": [10, 0]}}})",
       "field 'x': min 10 deg is greater than max 0 deg"},
      {R"({"limits_deg": {"a": {"x": [-200, 0]}}})", "within [-180, 180]"},
      {R"({"limits_deg": {"a": {"x": [0, "b"]}}})", "field 'x[1]': expected a number"},
      {R"({"limits_deg": {"a": {"x": [0]}}})", "expected [min, max]"},
      {R"({"limits_deg": {"a": "stiff"}})", "unknown value 'stiff'"},
      {R"({"limits_deg": {"a": 3}})", "limits_deg 'a'"},
      {R"({"limits_deg": [1, 2]})", "field 'limits_deg': expected an object"},
      {R"({"limit_deg": {}})", "field 'limit_deg': unknown field"},
      {R"({"comment": "no limits"})", "field 'limits_deg': missing required field"},
      {R"({"limits_deg": {"a": {"x": [0, 1e999]}}})", "l.json"},
      {R"({"limits_deg": {"a": {"x": [NaN, 0]}}})", "invalid JSON"},
      // a bone name with a control character, named by position, never echoed
      {R"({"limits_deg": {"a": {}, "b\u0000": "free"}})",
       "limits_deg: a bone name: control character 0x00 at offset 1"},
      {R"({"rig": "r\u0007", "limits_deg": {}})", "field 'rig': control character 0x07"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.text);
    try {
      joint_limits_from_json(parse_json_text(c.text, "l.json"), "l.json");
      ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(c.expect), std::string::npos) << e.what();
      EXPECT_EQ(std::string(e.what()).rfind("l.json", 0), 0u) << e.what();
    }
  }
  EXPECT_THROW(load_joint_limits("/nonexistent/limits.json"), InputError);
}

}  // namespace
}  // namespace physik
