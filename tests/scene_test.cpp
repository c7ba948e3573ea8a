// Scene files: presets, overrides, and every bad-scene case with its error.
#include "physik/model/scene.h"

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "physik/io/scene_io.h"
#include "physik/model/errors.h"
#include "tests/test_util.h"

namespace physik {
namespace {

std::string rig_dir() {
  return test::model_path("rigs");
}

Scene parse(const std::string& text) {
  return scene_from_json(parse_json_text(text, "bad_scene.json"), "bad_scene.json", rig_dir());
}

void expect_error(const std::string& text, std::initializer_list<const char*> fragments) {
  try {
    parse(text);
    FAIL() << "no error for " << text;
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.rfind("bad_scene.json: ", 0), 0u) << msg;
    for (const char* f : fragments)
      EXPECT_NE(msg.find(f), std::string::npos) << msg << " lacks " << f;
  }
}

std::string with_cp(const std::string& cp, const std::string& params = "{}") {
  return R"({"rig": "elbow.json", "params": )" + params + R"(, "control_points": [)" + cp + "]}";
}

TEST(Scene, PresetsAndOverrides) {
  const Scene a =
      parse(with_cp(R"({"bone": "forearm", "target": [0, 1, 3]})", R"({"preset": "paper"})"));
  EXPECT_EQ(a.params.damping, 20.0);
  EXPECT_EQ(a.params.dt, 0.05);
  EXPECT_EQ(a.params.joint_eps, 1e-3);
  EXPECT_FALSE(a.control_points[0].k.has_value());  // no k of its own:
  EXPECT_EQ(a.control_points[0].k_in(a.params),
            30.0);  // the paper's k is the control-point default
  const Scene b = parse(with_cp(R"({"bone": "forearm", "target": [0, 1, 3], "k": 5})",
                                R"({"damping": 2.5, "integration": "free-rods"})"));
  EXPECT_EQ(b.params.preset, std::string(kDefaultPreset));
  EXPECT_EQ(b.params.damping, 2.5);
  // the key scheme replaced, still read: free rods are a form of the gauss-seidel scheme
  EXPECT_EQ(b.params.scheme, Scheme::kGaussSeidel);
  EXPECT_TRUE(b.params.free_rods);
  EXPECT_EQ(b.control_points[0].k_in(b.params), 5.0);
  // round trip through JSON (written with the new keys)
  const Json written = scene_to_json(b);
  EXPECT_EQ(written["params"]["scheme"], "gauss-seidel");
  EXPECT_EQ(written["params"]["free_rods"], true);
  EXPECT_FALSE(written["params"].contains("integration"));
  const Scene c = scene_from_json(written, "rt.json", "/");
  EXPECT_EQ(c.params.damping, 2.5);
  EXPECT_TRUE(c.params.free_rods);
  EXPECT_EQ(c.control_points[0].target_world, b.control_points[0].target_world);
  const Scene d = parse(with_cp(R"({"bone": "forearm", "target": [0, 1, 3]})",
                                R"({"preset": "original", "joint_solve": "exact"})"));
  EXPECT_EQ(d.params.scheme, Scheme::kExact);
  EXPECT_EQ(scene_from_json(scene_to_json(d), "rt.json", "/").params.scheme, Scheme::kExact);
}

TEST(Scene, TheKeysSchemeReplacedMapOntoIt) {
  const auto scheme_of = [](const std::string& params) {
    return parse(with_cp(R"({"bone": "forearm", "target": [0, 1, 3]})", params)).params;
  };
  EXPECT_EQ(scheme_of(R"({"preset": "original", "integration": "implicit"})").scheme,
            Scheme::kImplicit);
  EXPECT_EQ(scheme_of(R"({"integration": "articulated"})").scheme, Scheme::kGaussSeidel);
  EXPECT_EQ(scheme_of(R"({"integration": "articulated", "joint_solve": "exact"})").scheme,
            Scheme::kExact);
  // joint_solve alone meant integration articulated, the default before scheme: exact is exact
  // under the default preset too (it ran scheme implicit once the default became robust)
  EXPECT_EQ(scheme_of(R"({"joint_solve": "exact"})").scheme, Scheme::kExact);
  EXPECT_EQ(scheme_of(R"({"preset": "robust", "joint_solve": "exact"})").scheme, Scheme::kExact);
  EXPECT_EQ(scheme_of(R"({"integration": "implicit", "joint_solve": "exact"})").scheme,
            Scheme::kImplicit);
  EXPECT_EQ(scheme_of(R"({"preset": "original", "joint_solve": "gauss-seidel"})").scheme,
            Scheme::kGaussSeidel);
  expect_error(with_cp("", R"({"integration": "implicit", "joint_solve": "gauss-seidel"})"),
               {"params", "field 'joint_solve'", "cannot run with integration implicit"});
  expect_error(with_cp("", R"({"integration": "free-rods", "joint_solve": "exact"})"),
               {"params", "field 'integration'", "free-rods needs joint_solve gauss-seidel"});
  expect_error(with_cp("", R"({"scheme": "exact", "integration": "implicit"})"),
               {"params", "field 'integration'", "give scheme only"});
  expect_error(with_cp("", R"({"integration": "sideways"})"),
               {"params", "field 'integration'", "unknown value 'sideways'"});
  // --set takes them too, and the scheme named there wins over the file's old keys
  const Scene e = scene_from_json(
      parse_json_text(
          with_cp(R"({"bone": "forearm", "target": [0, 1, 3]})", R"({"integration": "free-rods"})"),
          "o.json"),
      "o.json", rig_dir(), parse_param_overrides({"scheme=exact"}, "--set"));
  EXPECT_EQ(e.params.scheme, Scheme::kExact);
  EXPECT_FALSE(e.params.free_rods);
  const EngineParams f = params_from_json(
      Json(nullptr), "n.json", parse_param_overrides({"integration=free-rods"}, "--set"));
  EXPECT_EQ(f.scheme, Scheme::kGaussSeidel);
  EXPECT_TRUE(f.free_rods);
}

TEST(Scene, ParamOverridesReachControlPointsThatInheritThem) {
  const std::string path = test::model_path("scenes/fig6_elbow_linear.json");  // control_k 30
  const Scene a = load_scene(path, parse_param_overrides({"control_k=12", "control_spring=capped",
                                                          "control_cap=0.3", "damping=1.5"},
                                                         "--set"));
  EXPECT_EQ(a.params.damping, 1.5);
  for (const ControlPoint& cp : a.control_points) {
    EXPECT_EQ(cp.k_in(a.params), 12.0);
    EXPECT_EQ(cp.spring_in(a.params), SpringLaw::kCapped);
    EXPECT_EQ(cp.cap_in(a.params), 0.3);
  }
  // a preset override swaps the base; the scene's own params (control_k 30) stay on top
  const Scene b = load_scene(path, parse_param_overrides({"preset=paper"}, "--set"));
  EXPECT_EQ(b.params.damping, 20.0);
  EXPECT_EQ(b.control_points[0].k_in(b.params), 30.0);
  // an explicit per-point k is not overridden
  const auto dir = std::filesystem::temp_directory_path() / "physik_override_test";
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "s.json")
      << R"({"rig": ")" << test::model_path("rigs/elbow.json")
      << R"(", "control_points": [{"bone": "forearm", "target": [0,1,3], "k": 7},
                                                            {"bone": "forearm", "target": [0,1,3]}]})";
  const Scene c =
      load_scene((dir / "s.json").string(), parse_param_overrides({"control_k=5"}, "--set"));
  EXPECT_EQ(c.control_points[0].k_in(c.params), 7.0);
  EXPECT_EQ(c.control_points[1].k_in(c.params), 5.0);
  // bad overrides name --set and the key
  EXPECT_THROW(parse_param_overrides({"dampng=3"}, "--set"), InputError);
  EXPECT_THROW(parse_param_overrides({"=3"}, "--set"), InputError);
  try {
    load_scene(path, parse_param_overrides({"dt=-1"}, "--set"));
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "--set: params: field 'dt': must be positive");
  }
}

TEST(Scene, ShippedScenesLoad) {
  int n = 0;
  for (const auto& e : std::filesystem::directory_iterator(test::model_path("scenes"))) {
    if (e.path().extension() != ".json") continue;
    EXPECT_NO_THROW(load_scene(e.path().string())) << e.path();
    ++n;
  }
  EXPECT_GT(n, 0);
}

TEST(SceneInput, UnknownBone) {
  expect_error(with_cp(R"({"bone": "wing", "target": [0, 0, 1]})"),
               {"control_points[0]", "'bone'", "unknown bone 'wing'"});
}

TEST(SceneInput, AlphaOutsideUnitInterval) {
  expect_error(with_cp(R"({"bone": "forearm", "alpha": 1.5, "target": [0, 0, 1]})"),
               {"control_points[0]", "'alpha'", "[0, 1]"});
  expect_error(with_cp(R"({"bone": "forearm", "alpha": -0.1, "target": [0, 0, 1]})"), {"'alpha'"});
}

TEST(SceneInput, NegativeStiffnessOrTimeStep) {
  expect_error(with_cp(R"({"bone": "forearm", "k": -3, "target": [0, 0, 1]})"),
               {"control_points[0]", "'k'", "negative"});
  expect_error(with_cp(R"({"bone": "forearm", "target": [0, 0, 1]})", R"({"dt": -0.01})"),
               {"params", "'dt'", "positive"});
  expect_error(with_cp(R"({"bone": "forearm", "target": [0, 0, 1]})", R"({"dt": 0})"),
               {"params", "'dt'"});
  expect_error(with_cp(R"({"bone": "forearm", "target": [0, 0, 1]})", R"({"damping": -1})"),
               {"params", "'damping'"});
}

TEST(SceneInput, NonFiniteTarget) {
  expect_error(with_cp(R"({"bone": "forearm", "target": [0, 1e999, 1]})"), {"overflow"});
  expect_error(with_cp(R"({"bone": "forearm", "target": [0, "x", 1]})"),
               {"control_points[0]", "target[1]", "number"});
  expect_error(with_cp(R"({"bone": "forearm", "target": [0, 1]})"),
               {"control_points[0]", "'target'", "3 numbers"});
}

TEST(SceneInput, MissingOrBadRig) {
  expect_error(R"({"params": {}})", {"'rig'", "missing"});
  expect_error(R"({"rig": "no_such_rig.json"})", {"'rig'", "does not exist"});
}

TEST(SceneInput, UnknownParamsAndValues) {
  expect_error(with_cp("", R"({"dampng": 3})"), {"params", "'dampng'", "did you mean 'damping'"});
  expect_error(with_cp("", R"({"preset": "fast"})"), {"params", "'preset'", "unknown preset"});
  expect_error(with_cp("", R"({"integration": "rk4"})"),
               {"params", "'integration'", "articulated|free-rods"});
  expect_error(with_cp("", R"({"interpolation": "cubic"})"), {"'interpolation'"});
  expect_error(with_cp("", R"({"joint_solve": "lu"})"),
               {"params", "'joint_solve'", "gauss-seidel|exact"});
  expect_error(with_cp("", R"({"torsion_spring": "stiff"})"), {"'torsion_spring'"});
  expect_error(with_cp(R"({"bone": "forearm", "target": [0,0,1], "spring": "bungee"})"),
               {"control_points[0]", "'spring'"});
}

TEST(SceneInput, IntegersDoNotWrap) {
  expect_error(R"({"rig": "elbow.json", "steps": 4294967297})", {"'steps'", "out of range"});
  expect_error(R"({"rig": "elbow.json", "steps": -9223372036854775807})",
               {"'steps'", "out of range"});
  expect_error(R"({"rig": "elbow.json", "steps": 2.5})", {"'steps'", "integer"});
}

TEST(SceneInput, Schedule) {
  const std::string base = R"({"rig": "elbow.json", "steps": 50,
      "control_points": [{"name": "tip", "bone": "forearm", "target": [0, 0, 4]}], "schedule": )";
  EXPECT_EQ(parse(base + R"([{"step": 10, "control_point": "tip", "target": [1, 0, 3]}]})")
                .schedule[0]
                .control_point,
            0);
  expect_error(base + R"([{"step": 60, "control_point": 0, "target": [1, 0, 3]}]})",
               {"schedule[0]", "'step'"});
  expect_error(base + R"([{"step": 5, "control_point": 3, "target": [1, 0, 3]}]})",
               {"schedule[0]", "'control_point'", "out of range"});
  expect_error(base + R"([{"step": 5, "control_point": "toe", "target": [1, 0, 3]}]})",
               {"schedule[0]", "no control point named 'toe'"});
}

TEST(SceneInput, InitialPoseUnknownBone) {
  expect_error(R"({"rig": "elbow.json", "initial_pose": {"rotation_deg": {"knee": [0, 0, 10]}}})",
               {"initial_pose", "rotation_deg.knee", "unknown bone"});
  expect_error(R"({"rig": "elbow.json", "initial_pose": {"rotation_deg": {"forarm": [0, 0, 1]}}})",
               {"rotation_deg.forarm", "unknown bone 'forarm' (did you mean 'forearm'?)"});
  // a rotation vector whose length overflows (1e200 degrees): refused, not a NaN pose
  expect_error(
      R"({"rig": "elbow.json", "initial_pose": {"rotation_deg": {"forearm": [1e200, 0, 0]}}})",
      {"initial_pose", "rotation_deg.forearm", "beyond +-1e6 degrees"});
  expect_error(
      R"({"rig": "elbow.json", "control_points": [{"bone": "uper_arm", "target": [0, 0, 0]}]})",
      {"control_points[0]", "unknown bone 'uper_arm' (did you mean 'upper_arm'?)"});
}

// every name a scene carries, and every name it refers to, is refused with a control character
// in it (the MJCF writer and MuJoCo's parser cannot take one), naming the field and the byte but
// never the name itself (it would carry the byte into the message)
TEST(SceneInput, ControlCharactersInEveryName) {
  const std::string cp = R"({"bone": "forearm", "target": [0, 0, 4]})";
  const std::string contacts = R"("ground": {}, "self_collision": true)";
  const std::string nul = "control character 0x00 at offset 1";
  expect_error(R"({"rig": "elbow.json", "name": "s\u0000"})", {"field 'name'", nul.c_str()});
  expect_error(with_cp(R"({"name": "p\u0000", "bone": "forearm", "target": [0, 0, 4]})"),
               {"control_points[0]", "field 'name'", nul.c_str()});
  expect_error(with_cp(R"({"bone": "f\u0000", "target": [0, 0, 4]})"),
               {"control_points[0]", "field 'bone'", nul.c_str()});
  expect_error(
      R"({"rig": "elbow.json", "steps": 5, "control_points": [)" + cp +
          R"(], "schedule": [{"step": 1, "control_point": "t\u001f", "target": [0, 0, 3]}]})",
      {"schedule[0]", "field 'control_point'", "control character 0x1f at offset 1"});
  expect_error(
      R"({"rig": "elbow.json", "initial_pose": {"rotation_deg": {"f\u007f": [0, 0, 1]}}})",
      {"initial_pose: field 'rotation_deg': a bone name: control character 0x7f at offset 1"});
  expect_error(R"({"rig": "elbow.json", "obstacles": [{"name": "o\u0000", "box": )"
               R"({"center": [0, 0, -1], "half_extents": [1, 1, 0.1]}}]})",
               {"obstacles[0]", "field 'name'", nul.c_str()});
  expect_error(R"({"rig": "elbow.json", )" + contacts +
                   R"(, "collision_exclude": [["upper_arm", "f\u0000"]]})",
               {"collision_exclude[0]", nul.c_str()});
  expect_error(R"({"rig": {"name": "r\u0000", "bones": [{"name": "a", "parent": null, )"
               R"("head": [0, 0, 0], "tail": [0, 0, 1]}]}})",
               {"rig", "field 'name'", nul.c_str()});
  // the messages never hold the byte itself
  for (const std::string& text : {std::string(R"({"rig": "elbow.json", "name": "s\u0000"})"),
                                  with_cp(R"({"bone": "f\u0000", "target": [0, 0, 4]})")}) {
    try {
      parse(text);
      ADD_FAILURE() << "no error for " << text;
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).find('\0'), std::string::npos) << e.what();
    }
  }
}

// a written scene refers to its rig as the scene it came from did: a relative path stays relative
// (from where it is written), an absolute one absolute
TEST(Scene, WrittenScenesKeepTheRigPathRelativeAsGiven) {
  namespace fs = std::filesystem;
  const std::string source = test::model_path("scenes/pinhead_two_hands.json");
  const Scene s = load_scene(source);
  ASSERT_EQ(s.rig_ref, "../rigs/pinhead.json");
  const fs::path beside = fs::path(source).parent_path() / "tuned.json";
  EXPECT_EQ(scene_to_json(s, false, beside.string())["rig"], "../rigs/pinhead.json");
  const fs::path elsewhere = fs::temp_directory_path() / "physik_scene_test" / "deep" / "t.json";
  fs::create_directories(elsewhere.parent_path());
  const std::string rel = scene_to_json(s, false, elsewhere.string())["rig"];
  EXPECT_TRUE(fs::path(rel).is_relative()) << rel;
  EXPECT_TRUE(fs::equivalent(elsewhere.parent_path() / rel, s.rig_file)) << rel;
  // no folder to be relative to (stdout, a dictionary): absolute, as before
  EXPECT_TRUE(fs::path(scene_to_json(s)["rig"].get<std::string>()).is_absolute());
  EXPECT_TRUE(fs::path(scene_to_json(s, false, "-")["rig"].get<std::string>()).is_absolute());
  // an absolute path stays absolute wherever the scene goes
  Scene a = s;
  a.rig_ref = fs::absolute(s.rig_file).string();
  EXPECT_EQ(scene_to_json(a, false, beside.string())["rig"],
            fs::absolute(s.rig_file).lexically_normal().string());
}

TEST(SceneInput, BadRigInsideSceneNamesTheRigFile) {
  const auto dir = std::filesystem::temp_directory_path() / "physik_scene_test";
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "bad_rig.json")
      << R"({"bones": [{"name": "a", "parent": null, "head": [0,0,0], "tail": [0,0,0]}]})";
  std::ofstream(dir / "s.json") << R"({"rig": "bad_rig.json"})";
  try {
    load_scene((dir / "s.json").string());
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bad_rig.json: bones[0] 'a': field 'tail'"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace physik
