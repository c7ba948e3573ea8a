// Bad rig files: each gets one InputError that names the file, the bone and the field.
#include "physik/io/rig_io.h"

#include <gtest/gtest.h>

#include "physik/model/errors.h"
#include "tests/test_util.h"

namespace physik {
namespace {

// Expect an InputError whose message contains every fragment.
void expect_error(const std::string& text, std::initializer_list<const char*> fragments) {
  try {
    rig_from_json_text(text, "bad.json");
    FAIL() << "no error for: " << text;
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.rfind("bad.json: ", 0), 0u) << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << "one line: " << msg;
    for (const char* f : fragments)
      EXPECT_NE(msg.find(f), std::string::npos) << msg << " lacks " << f;
  }
}

const char* kRoot = R"({"name": "a", "parent": null, "head": [0,0,0], "tail": [0,0,1]})";

std::string rig_with(const std::string& second_bone) {
  return std::string(R"({"bones": [)") + kRoot + "," + second_bone + "]}";
}

TEST(RigInput, Cycle) {
  expect_error(R"({"bones": [
      {"name": "r", "parent": null, "head": [0,0,-1], "tail": [0,0,0]},
      {"name": "a", "parent": "b", "head": [0,0,0], "tail": [0,0,1]},
      {"name": "b", "parent": "a", "head": [0,0,1], "tail": [0,0,0]}]})",
               {"'a'", "parent", "cycle"});
}

TEST(RigInput, AllBonesHaveParentsIsACycle) {
  expect_error(R"({"bones": [
      {"name": "a", "parent": "b", "head": [0,0,0], "tail": [0,0,1]},
      {"name": "b", "parent": "a", "head": [0,0,1], "tail": [0,0,0]}]})",
               {"parent", "cycle"});
}

TEST(RigInput, UnknownParent) {
  expect_error(rig_with(R"({"name": "b", "parent": "nobody", "head": [0,0,1], "tail": [0,0,2]})"),
               {"'b'", "parent", "unknown bone 'nobody'"});
  expect_error(rig_with(R"({"name": "b", "parent": "aa", "head": [0,0,1], "tail": [0,0,2]})"),
               {"'b'", "parent", "unknown bone 'aa' (did you mean 'a'?)"});
}

TEST(RigInput, DuplicateName) {
  expect_error(rig_with(R"({"name": "a", "parent": "a", "head": [0,0,1], "tail": [0,0,2]})"),
               {"bones[1] 'a'", "name", "duplicate"});
}

TEST(RigInput, TwoRoots) {
  expect_error(rig_with(R"({"name": "b", "parent": null, "head": [0,0,1], "tail": [0,0,2]})"),
               {"'b'", "parent", "second root"});
}

TEST(RigInput, ZeroLengthBone) {
  expect_error(rig_with(R"({"name": "b", "parent": "a", "head": [0,0,1], "tail": [0,0,1]})"),
               {"'b'", "tail", "zero-length"});
}

TEST(RigInput, MinGreaterThanMax) {
  expect_error(rig_with(R"({"name": "b", "parent": "a", "head": [0,0,1], "tail": [0,0,2],
                            "limits_deg": {"x": [30, 10]}})"),
               {"'b'", "limits_deg.x", "greater than max"});
}

TEST(RigInput, LimitOutsidePlusMinus180FailsAtLoad) {
  // caught by the shared parser (axis_limits.h) as the file is read, one message naming the field
  expect_error(
      rig_with(R"({"name": "b", "parent": "a", "head": [0,0,1], "tail": [0,0,2],
                            "limits_deg": {"z": [-200, 10]}})"),
      {"bad.json: bones[1] 'b': field 'limits_deg.z': limits must lie within [-180, 180]"});
  expect_error(rig_with(R"({"name": "b", "parent": "a", "head": [0,0,1], "tail": [0,0,2],
                            "limits_deg": {"x": [0, 180.5]}})"),
               {"'b'", "field 'limits_deg.x'", "[-180, 180]"});
  // the bounds themselves are allowed
  const Rig rig = rig_from_json_text(rig_with(R"({"name": "b", "parent": "a", "head": [0,0,1],
      "tail": [0,0,2], "limits_deg": {"y": [-180, 180]}})"),
                                     "ok.json");
  EXPECT_DOUBLE_EQ(rig.bone_limit[1][1].min, -kPi);
  EXPECT_DOUBLE_EQ(rig.bone_limit[1][1].max, kPi);
}

// a forward axis whose square overflows ([0, 1e155, 0]) is +Y, not the zero vector that its
// plain normalisation gave (an aim without an axis and --look-at then did nothing)
TEST(RigInput, AForwardAxisTooLargeToSquareIsItsDirection) {
  const Rig rig = rig_from_json_text(rig_with(R"({"name": "b", "parent": "a", "head": [0,0,1],
      "tail": [0,0,2], "forward": [0, 1e155, 0]})"),
                                     "ok.json");
  EXPECT_TRUE(test::near(rig.bone_forward_local[1], Vec3(0, 1, 0), 1e-15))
      << rig.bone_forward_local[1].transpose();
}

TEST(RigInput, LimitEntryChecksMatchTheLimitFile) {
  expect_error(rig_with(R"({"name": "b", "parent": "a", "head": [0,0,1], "tail": [0,0,2],
                            "limits_deg": {"w": [0, 1]}})"),
               {"'b'", "field 'limits_deg.w'", "unknown axis"});
  expect_error(rig_with(R"({"name": "b", "parent": "a", "head": [0,0,1], "tail": [0,0,2],
                            "limits_deg": {"x": [0, "b"]}})"),
               {"'b'", "field 'limits_deg.x[1]'", "expected a number"});
  expect_error(rig_with(R"({"name": "b", "parent": "a", "head": [0,0,1], "tail": [0,0,2],
                            "limits_deg": {"x": [0]}})"),
               {"'b'", "field 'limits_deg.x'", "expected [min, max]"});
  expect_error(rig_with(R"({"name": "b", "parent": "a", "head": [0,0,1], "tail": [0,0,2],
                            "limits_deg": [0, 1]})"),
               {"'b'", "field 'limits_deg'", "expected an object"});
}

TEST(RigInput, MissingField) {
  expect_error(rig_with(R"({"name": "b", "parent": "a", "head": [0,0,1]})"),
               {"'b'", "'tail'", "missing"});
  expect_error(rig_with(R"({"name": "b", "head": [0,0,1], "tail": [0,0,2]})"),
               {"'b'", "'parent'", "missing"});
  expect_error(R"({"rig": []})", {"'rig'", "unknown field"});
}

TEST(RigInput, NonNumber) {
  expect_error(rig_with(R"({"name": "b", "parent": "a", "head": [0,0,"one"], "tail": [0,0,2]})"),
               {"'b'", "head[2]", "expected a number"});
  expect_error(rig_with(R"({"name": "b", "parent": "a", "head": [0,0,1], "tail": [0,0,2],
                            "mass": "heavy"})"),
               {"'b'", "mass", "expected a number"});
}

TEST(RigInput, NaNIsRejected) {
  // JSON has no NaN literal: the parser rejects it with a line and column
  expect_error(rig_with(R"({"name": "b", "parent": "a", "head": [0,0,NaN], "tail": [0,0,2]})"),
               {"invalid JSON", "line 1"});
  // an overflowing literal is not a finite number either
  expect_error(rig_with(R"({"name": "b", "parent": "a", "head": [0,0,1e999], "tail": [0,0,2]})"),
               {"invalid JSON", "overflow", "1e999"});
}

TEST(RigInput, ChildMustMeetParentTail) {
  expect_error(rig_with(R"({"name": "b", "parent": "a", "head": [0,0,1.5], "tail": [0,0,2]})"),
               {"'b'", "'head'", "does not meet the tail"});
}

TEST(RigInput, BadFrameAndMisspelledField) {
  expect_error(rig_with(R"({"name": "b", "parent": "a", "head": [0,0,1], "tail": [0,0,2],
                            "rest_frame": [[1,0,0],[0,1,0],[0,0,1]]})"),
               {"'b'", "rest_frame", "y axis"});
  expect_error(rig_with(R"({"name": "b", "parent": "a", "head": [0,0,1], "tail": [0,0,2],
                            "limit_deg": {}})"),
               {"'b'", "'limit_deg'", "unknown field"});
}

TEST(RigInput, MissingFileIsNamed) {
  try {
    load_rig("/nonexistent/rig.json");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/rig.json: cannot open"), std::string::npos);
  }
}

TEST(RigInput, RoundTripThroughJson) {
  const Rig a = load_rig(test::model_path("rigs/pinhead.json"));
  const Rig b = rig_from_json(rig_to_json(a), "roundtrip");
  ASSERT_EQ(a.nbone, b.nbone);
  for (int i = 0; i < a.nbone; ++i) {
    EXPECT_EQ(a.bone_name[i], b.bone_name[i]);
    EXPECT_TRUE(test::near(a.bone_rest_tail_world[i], b.bone_rest_tail_world[i], 1e-12));
    EXPECT_NEAR(a.bone_mass[i], b.bone_mass[i], 1e-12);
    EXPECT_LT(a.bone_rest_orient_world[i].angularDistance(b.bone_rest_orient_world[i]), 1e-9);
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(a.bone_limit[i][k].limited, b.bone_limit[i][k].limited);
      EXPECT_NEAR(a.bone_limit[i][k].min, b.bone_limit[i][k].min, 1e-12);
    }
  }
}

// ---------------------------------------------------------------- robustness

TEST(RigInput, ValuesWhoseProductsOverflowFailAtLoadNamingTheField) {
  // a radius of 1e200 made the inertia (m r^2 / 2) overflow: rig info printed null
  expect_error(rig_with(R"({"name": "b", "parent": "a", "head": [0,0,1], "tail": [0,0,2],
                            "radius": 1e200})"),
               {"bones[1] 'b'", "field 'radius'", "out of range"});
  expect_error(rig_with(R"({"name": "b", "parent": "a", "head": [0,0,1], "tail": [0,0,2],
                            "radius": 1e-200})"),
               {"field 'radius'", "out of range"});
  expect_error(rig_with(R"({"name": "b", "parent": "a", "head": [0,0,1], "tail": [0,0,2],
                            "mass": 1e300})"),
               {"field 'mass'", "out of range"});
  expect_error(rig_with(R"({"name": "b", "parent": "a", "head": [0,0,1], "tail": [0,0,1e12]})"),
               {"field 'tail'", "beyond"});
  expect_error(rig_with(R"({"name": "b", "parent": "a", "head": [0,0,1], "tail": [0,0,2],
                            "inertia_local": [1e40, 1e40, 1e40]})"),
               {"field 'inertia_local'", "must lie in"});
  // the edges of the ranges are fine
  const Rig rig = rig_from_json_text(rig_with(R"({"name": "b", "parent": "a", "head": [0,0,1],
                                                  "tail": [0,0,2], "radius": 1e9, "mass": 1e-9})"),
                                     "ok.json");
  EXPECT_TRUE(rig.bone_inertia_local[1].allFinite());
  EXPECT_GT(rig.bone_inertia_local[1].minCoeff(), 0.0);
}

TEST(RigInput, BoneNamesMustBePrintable) {
  // JSON strings are UTF-8 already (the parser checks); control characters would split BVH and
  // CSV lines
  expect_error(rig_with(R"({"name": "b\nc", "parent": "a", "head": [0,0,1], "tail": [0,0,2]})"),
               {"bones[1]", "field 'name'", "control character 0x0a"});
  expect_error(
      rig_with("{\"name\": \"b\xff\", \"parent\": \"a\", \"head\": [0,0,1], \"tail\": [0,0,2]}"),
      {"invalid JSON"});
  // quotes, commas and '<' are names like any other
  const Rig rig = rig_from_json_text(
      rig_with(R"({"name": "b\"<,c", "parent": "a", "head": [0,0,1], "tail": [0,0,2]})"),
      "ok.json");
  EXPECT_EQ(rig.bone_name[1], "b\"<,c");
}

// the rig's own name and a parent's name go into MJCF, CSV and messages like the bones' names
TEST(RigInput, RigNameAndParentNamesMustBePrintable) {
  expect_error(std::string(R"({"name": "r\u0000", "bones": [)") + kRoot + "]}",
               {"field 'name'", "control character 0x00 at offset 1"});
  expect_error(rig_with(R"({"name": "b", "parent": "a\u0001", "head": [0,0,1], "tail": [0,0,2]})"),
               {"bones[1]", "field 'parent'", "control character 0x01 at offset 1"});
  // a bone whose name is bad is named by its index alone, whatever else is wrong with it
  try {
    rig_from_json_text(R"({"bones": [{"name": "a\u0000", "parent": null, "head": [0,0,0]}]})",
                       "bad.json");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).find('\0'), std::string::npos) << e.what();
  }
}

TEST(RigInput, JsonNestedTooDeepIsRejectedBeforeParsing) {
  // a 200,000-deep array overflowed the stack when the document was copied
  const std::string deep =
      R"({"bones": )" + std::string(200000, '[') + std::string(200000, ']') + "}";
  expect_error(deep, {"line 1", "nested deeper than 256"});
  // brackets inside strings do not count, nor do escaped quotes end a string
  std::string name(300, '[');
  const Rig rig = rig_from_json_text(
      R"({"comment": ")" + name + R"(\"[[", "bones": [)" + std::string(kRoot) + "]}", "ok.json");
  EXPECT_EQ(rig.nbone, 1);
  // the limit itself is allowed
  const std::string at_limit = std::string(kMaxJsonDepth, '[') + std::string(kMaxJsonDepth, ']');
  EXPECT_NO_THROW(parse_json_text(at_limit, "limit.json"));
  EXPECT_THROW(parse_json_text("[" + at_limit + "]", "over.json"), InputError);
}

// ---------------------------------------------------------------- welds and the root's joint

// a root with three children at its tail: "a" and "b" siblings, "c" a child of "a"
std::string replaced(std::string s, const std::string& from, const std::string& to) {
  return s.replace(s.find(from), from.size(), to);
}

std::string weld_rig(const std::string& b_extra, const std::string& c_extra = "",
                     const std::string& top = "") {
  return std::string(R"({)") + top + R"("bones": [
      {"name": "r", "parent": null, "head": [0,0,0], "tail": [0,0,1])" +
         (top.find("pinned") != std::string::npos ? R"(, "limits_deg": {"x": [-10, 10]})" : "") +
         R"(},
      {"name": "a", "parent": "r", "head": [0,0,1], "tail": [0,0,2]},
      {"name": "b", "parent": "r", "head": [0,0,1], "tail": [1,0,1])" +
         b_extra + R"(},
      {"name": "c", "parent": "a", "head": [0,0,2], "tail": [0,0,3])" +
         c_extra + R"(}]})";
}

TEST(RigInput, WeldsToAParentOrAnEarlierSiblingAndRoundTrip) {
  const Rig rig = rig_from_json_text(weld_rig(R"(, "weld": "a")", R"(, "weld": "a")"), "w.json");
  EXPECT_EQ(rig.bone_weld[rig.find_bone("b")], rig.find_bone("a"));
  EXPECT_EQ(rig.bone_weld[rig.find_bone("c")], rig.find_bone("a"));
  EXPECT_EQ(rig.bone_body[rig.find_bone("c")], rig.find_bone("a"));
  EXPECT_EQ(rig.nv, 6 + 3);
  const Rig back = rig_from_json(rig_to_json(rig), "back");
  EXPECT_EQ(back.bone_weld, rig.bone_weld);
  const Rig pinned = rig_from_json_text(weld_rig("", "", R"("root": "pinned", )"), "p.json");
  EXPECT_EQ(pinned.root_joint, RootJoint::kPinned);
  EXPECT_EQ(rig_from_json(rig_to_json(pinned), "back").root_joint, RootJoint::kPinned);
  EXPECT_EQ(rig_to_json(rig).contains("root"), false);  // free is the default, left out
}

TEST(RigInput, BadWeldsNameTheBoneAndField) {
  // on the root
  expect_error(R"({"bones": [{"name": "r", "parent": null, "head": [0,0,0], "tail": [0,0,1],
                              "weld": "r"}]})",
               {"'r'", "weld", "root has no parent"});
  // a cycle of siblings
  expect_error(replaced(weld_rig(R"(, "weld": "a")"), R"("name": "a", "parent": "r",)",
                        R"("name": "a", "parent": "r", "weld": "b",)"),
               {"weld", "weld cycle"});
  // a welded bone with limits
  expect_error(weld_rig(R"(, "weld": "a", "limits_deg": {"x": [-10, 10]})"),
               {"'b'", "limits_deg", "welded"});
  // neither parent nor sibling
  expect_error(weld_rig("", R"(, "weld": "b")"), {"'c'", "weld", "neither"});
  // a sibling listed after it
  expect_error(replaced(weld_rig(""), R"("name": "a", "parent": "r",)",
                        R"("name": "a", "parent": "r", "weld": "b",)"),
               {"'a'", "weld", "must come before"});
  expect_error(weld_rig(R"(, "weld": "nobody")"), {"'b'", "weld", "unknown bone 'nobody'"});
  expect_error(weld_rig(R"(, "weld": "rr")"),
               {"'b'", "weld", "unknown bone 'rr' (did you mean 'r'?)"});
  expect_error(weld_rig(R"(, "weld": "b")"), {"'b'", "weld", "itself"});
  expect_error(weld_rig(R"(, "weld": "")"), {"'b'", "weld", "empty"});
}

TEST(RigInput, BadRootJointsNameTheField) {
  expect_error(weld_rig("", "", R"("root": "hinged", )"), {"root", "\"pinned\""});
  // limits on a free root hold against nothing
  expect_error(R"({"bones": [{"name": "r", "parent": null, "head": [0,0,0], "tail": [0,0,1],
                              "limits_deg": {"x": [-10, 10]}}]})",
               {"'r'", "limits_deg", "free root"});
  expect_error(R"({"root": "fixed", "bones": [{"name": "r", "parent": null, "head": [0,0,0],
                  "tail": [0,0,1], "limits_deg": {"x": [-10, 10]}}]})",
               {"'r'", "limits_deg", "fixed root"});
}

}  // namespace
}  // namespace physik
