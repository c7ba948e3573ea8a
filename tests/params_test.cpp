// The parameter table: its defaults against the documented presets, the scene reader and writer
// and --set driven by it (round trips, every bound's message, every kind's text), and control
// points that inherit their spring from the params.
#include "physik/model/params.h"

#include <fstream>
#include <map>
#include <optional>
#include <regex>
#include <set>
#include <sstream>

#include <gtest/gtest.h>

#include "physik/engine/engine.h"
#include "physik/io/scene_io.h"
#include "physik/model/errors.h"
#include "tests/engine_test_util.h"
#include "tests/test_util.h"

namespace physik {
namespace {

std::vector<std::string> split(const std::string& s, const std::string& sep) {
  std::vector<std::string> out;
  std::size_t at = 0;
  for (std::size_t next; (next = s.find(sep, at)) != std::string::npos; at = next + sep.size()) {
    out.push_back(s.substr(at, next - at));
  }
  out.push_back(s.substr(at));
  return out;
}

std::string strip(std::string s) {
  s = std::regex_replace(s, std::regex("`"), "");
  const auto b = s.find_first_not_of(' '), e = s.find_last_not_of(' ');
  return b == std::string::npos ? "" : s.substr(b, e - b + 1);
}

// models/README.md documents every parameter with the `original` preset's value and unit:
// "| `control_k`, `control_spring`, `control_cap` | 10, `linear`, 1 | N/m, -, rig units | ... |"
std::map<std::string, std::pair<std::string, std::string>> documented_original() {
  const std::string doc = test::read_file(std::string(PHYSIK_SOURCE_DIR) + "/models/README.md");
  const auto from = doc.find("Engine parameters (`params`)");
  EXPECT_NE(from, std::string::npos);
  std::map<std::string, std::pair<std::string, std::string>> out;  // name -> (value, unit)
  std::istringstream lines(doc.substr(from));
  std::string line;
  while (std::getline(lines, line) && (out.empty() || line.rfind("|", 0) == 0)) {
    if (line.rfind("| `", 0) != 0) continue;
    const auto cells = split(line.substr(1), "|");  // key, default, unit, meaning
    const auto names = split(strip(cells[0]), ", "), values = split(strip(cells[1]), ", "),
               units = split(strip(cells[2]), ", ");
    for (std::size_t i = 0; i < names.size(); ++i) {
      const std::string unit = i < units.size() ? strip(units[i]) : "";
      out[strip(names[i])] = {strip(values[i]), unit == "-" ? "" : unit};
    }
  }
  return out;
}

// a documented value ("1e-3", "0.05", "linear", "true") equals the row's
bool same_value(const ParamRow& row, ParamValue v, const std::string& text) {
  if (row.kind == ParamKind::kReal || row.kind == ParamKind::kInteger) {
    return std::stod(text) == v;
  }
  return format_param(row, v) == text;
}

TEST(ParamTable, OriginalDefaultsAndUnitsAreTheDocumentedOnes) {
  const auto doc = documented_original();
  for (const ParamRow& row : param_table()) {
    SCOPED_TRACE(row.name);
    ASSERT_TRUE(doc.count(row.name)) << "models/README.md does not document " << row.name;
    EXPECT_TRUE(same_value(row, row.defaults[0], doc.at(row.name).first))
        << format_param(row, row.defaults[0]) << " vs documented " << doc.at(row.name).first;
    EXPECT_EQ(row.unit, doc.at(row.name).second);
  }
  EXPECT_EQ(doc.at("preset").first, kDefaultPreset);
}

TEST(ParamTable, PaperPresetIsTheOriginalWithThePapersDampingAndStiffness) {
  // README "Settings for a new rig": paper = damping 20 N s/m and control k 30 N/m, the rest as
  // the original
  const std::map<std::string, std::string> paper_changes = {{"damping", "20"}, {"control_k", "30"}};
  ASSERT_EQ(kPresetNames[1], std::string("paper"));
  for (const ParamRow& row : param_table()) {
    SCOPED_TRACE(row.name);
    const auto it = paper_changes.find(row.name);
    if (it == paper_changes.end())
      EXPECT_EQ(row.defaults[1], row.defaults[0]);
    else
      EXPECT_TRUE(same_value(row, row.defaults[1], it->second));
  }
  const EngineParams paper = preset_params("paper"), original = preset_params("original");
  EXPECT_EQ(paper.damping, 20.0);
  EXPECT_EQ(paper.control_k, 30.0);
  EXPECT_EQ(paper.preset, "paper");
}

TEST(ParamTable, RobustIsTheOriginalWithTheImplicitStepDampingAutoAndTheGradientTorque) {
  // models/README.md: robust = scheme implicit, damping auto, torsion torque gradient; the rest as
  // the original
  const std::map<std::string, std::string> robust_changes = {
      {"scheme", "implicit"}, {"damping_auto", "true"}, {"torsion_torque", "gradient"}};
  const int robust = preset_index("robust");
  ASSERT_GE(robust, 0);
  for (const ParamRow& row : param_table()) {
    SCOPED_TRACE(row.name);
    const auto it = robust_changes.find(row.name);
    if (it == robust_changes.end())
      EXPECT_EQ(row.defaults[robust], row.defaults[0]);
    else
      EXPECT_TRUE(same_value(row, row.defaults[robust], it->second));
  }
  // the default preset, of scene files that name none and of EngineParams()
  EXPECT_EQ(std::string(kDefaultPreset), "robust");
  EXPECT_EQ(params_to_json(EngineParams()), params_to_json(preset_params("robust")));
  EXPECT_EQ(params_from_json(Json(nullptr), "none.json").preset, "robust");
  const EngineParams p = preset_params("robust");
  EXPECT_TRUE(p.damping_auto);  // the damping row's setter runs first, damping_auto's after
  EXPECT_EQ(params_to_json(p)["damping"], "auto");
}

TEST(ParamTable, RowsOutOfTheSchemeAreWrittenOnlyWhereTheyCount) {
  EngineParams p = preset_params("paper");
  EXPECT_EQ(params_to_json(p)["scheme"], "gauss-seidel");
  EXPECT_FALSE(params_to_json(p).contains("free_rods"));  // written only away from its default
  p.scheme = Scheme::kExact;
  Json j = params_to_json(p);
  EXPECT_EQ(j["scheme"], "exact");
  // the exact solve does not read the gauss-seidel rows: the writer leaves those at the
  // preset's value, which the reader accepts
  EXPECT_EQ(params_from_json(j, "rt.json").scheme, Scheme::kExact);
  p.joint_eps = 1e-9;
  EXPECT_FALSE(params_to_json(p).contains("joint_eps"));  // not used, so not written
  p.scheme = Scheme::kGaussSeidel;
  EXPECT_EQ(params_to_json(p)["joint_eps"], 1e-9);
  // damping auto is written "damping": "auto", never as a damping_auto key
  EXPECT_FALSE(params_to_json(p).contains("damping_auto"));
  p.damping_auto = true;
  EXPECT_EQ(params_to_json(p)["damping"], "auto");
  EXPECT_FALSE(params_to_json(p).contains("damping_auto"));
  EXPECT_TRUE(params_from_json(params_to_json(p), "rt.json").damping_auto);
  const Json a = {{"damping", "auto"}};
  EXPECT_TRUE(params_from_json(a, "auto.json").damping_auto);
  // implicit_max_splits likewise (the implicit step's energy guard, added with it)
  EXPECT_FALSE(params_to_json(p).contains("implicit_max_splits"));
  p.scheme = Scheme::kImplicit;
  p.joint_eps = 1e-3;
  p.implicit_max_splits = 0;
  EXPECT_EQ(params_to_json(p)["implicit_max_splits"].get<int>(), 0);
  EXPECT_EQ(params_from_json(params_to_json(p), "rt.json").implicit_max_splits, 0);
  EXPECT_FALSE(params_to_json(p).contains("torsion_torque"));
  p.torsion_torque = TorsionTorque::kGradient;
  EXPECT_EQ(params_to_json(p)["torsion_torque"], "gradient");
  EXPECT_EQ(params_from_json(params_to_json(p), "rt.json").torsion_torque,
            TorsionTorque::kGradient);
  // implicit_linearisation: written when it is not gauss-newton
  EXPECT_FALSE(params_to_json(p).contains("implicit_linearisation"));
  p.implicit_linearisation = ImplicitLinearisation::kFull;
  EXPECT_EQ(params_to_json(p)["implicit_linearisation"], "full");
  EXPECT_EQ(params_from_json(params_to_json(p), "rt.json").implicit_linearisation,
            ImplicitLinearisation::kFull);
  // flush_subnormals: written only when off, so runs from before it was added read the same
  EXPECT_FALSE(params_to_json(p).contains("flush_subnormals"));
  p.flush_subnormals = false;
  EXPECT_EQ(params_to_json(p)["flush_subnormals"], false);
  EXPECT_FALSE(params_from_json(params_to_json(p), "rt.json").flush_subnormals);
  EXPECT_TRUE(params_from_json(Json::object(), "rt.json").flush_subnormals);
  for (const ParamRow& row : param_table()) {
    // the contact rows too: a scene without contacts never gives them
    const bool contact = row.name == "contact_k" || row.name == "contact_damping" ||
                         row.name == "friction" || row.name == "friction_speed" ||
                         row.name == "friction_stiffness";
    if (row.name != "free_rods" && row.name != "damping_auto" &&
        row.name != "implicit_max_splits" && row.name != "torsion_torque" &&
        row.name != "implicit_linearisation" && row.name != "flush_subnormals" && !contact) {
      EXPECT_TRUE(row.written_at_default) << row.name;
    }
  }
}

TEST(ParamTable, RowsAreWellFormed) {
  std::set<std::string> names;
  for (const ParamRow& row : param_table()) {
    SCOPED_TRACE(row.name);
    EXPECT_TRUE(names.insert(row.name).second) << "listed twice";
    EXPECT_FALSE(row.doc.empty());
    for (int i = 0; i < kPresetCount; ++i) EXPECT_EQ(range_violation(row, row.defaults[i]), "");
    EXPECT_EQ(row.kind == ParamKind::kChoice, !row.choices.empty());
    if (row.tune) {
      EXPECT_EQ(row.kind, ParamKind::kReal);
      EXPECT_GT(row.tune->first, 0.0);
      EXPECT_LT(row.tune->first, row.tune->second);
      EXPECT_EQ(range_violation(row, row.tune->first), "");  // the tuner stays in the valid range
      EXPECT_EQ(range_violation(row, row.tune->second), "");
    }
  }
}

// a valid value other than the default, for every kind
ParamValue other_value(const ParamRow& row) {
  const ParamValue d = row.defaults[0];
  switch (row.kind) {
    // halfway to the lower bound, or to the upper one when the default sits on the lower
    case ParamKind::kReal:
      // (the text form keeps 6 significant digits: a large default, contact_k's, gets 2 d)
      if (!row.valid.hi) return d < 1000.0 ? 2.0 * d + 0.125 : 2.0 * d;
      return 0.5 * (d + (d > *row.valid.lo ? *row.valid.lo : *row.valid.hi));
    case ParamKind::kInteger:
      return d + 3.0;
    case ParamKind::kBoolean:
      return d != 0.0 ? 0.0 : 1.0;
    case ParamKind::kChoice:
      return static_cast<ParamValue>((static_cast<int>(d) + 1) % row.choices.size());
  }
  return d;
}

// Where the row's value would not take part in the run (ParamRow::conflict), the settings that
// make it: a capped torsion spring for torsion_cap, the implicit step for its splits, a polar
// interpolation for its fallback; a row of the scheme itself keeps the scheme it sets.
void make_it_count(const ParamRow& row, EngineParams& p) {
  if (row.conflict_reason(p).empty()) return;
  if (row.name == "torsion_cap") p.torsion_spring = SpringLaw::kCapped;
  if (row.name == "implicit_max_splits" || row.name == "implicit_linearisation") {
    p.scheme = Scheme::kImplicit;
  }
  if (row.name == "interpolation_fallback") p.interpolation = Interpolation::kPolarCom;
  if (row.name == "free_rods") p.scheme = Scheme::kGaussSeidel;
  ASSERT_EQ(row.conflict_reason(p), "");
}

TEST(ParamTable, EveryRowRoundTripsThroughTheSceneFormatAndText) {
  for (const ParamRow& row : param_table()) {
    SCOPED_TRACE(row.name);
    EngineParams p = preset_params("paper");
    const ParamValue v = other_value(row);
    ASSERT_NE(v, row.get(p));
    row.set(p, v);
    EXPECT_EQ(row.get(p), v);
    make_it_count(row, p);
    // parse -> write -> parse
    const Json written = params_to_json(p);
    const EngineParams back = params_from_json(written, "rt.json");
    EXPECT_EQ(params_to_json(back), written);
    EXPECT_EQ(row.get(back), v);
    EXPECT_EQ(back.preset, "paper");
    // the text form --set reads
    EXPECT_EQ(parse_param_text(row, format_param(row, v), "--set"), v);
  }
}

std::string params_error(const std::string& params_json) {
  try {
    params_from_json(parse_json_text(params_json, "p.json"), "p.json");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

std::string set_error(const std::string& assignment) {
  try {
    parse_param_overrides({assignment}, "--set");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(ParamTable, EveryBoundGivesItsMessageInSceneFilesAndSet) {
  struct Case {
    const char* key;
    const char* value;
    const char* reason;
  };
  const Case cases[] = {
      {"dt", "0", "must be positive"},
      {"dt", "-0.01", "must be positive"},
      {"damping", "-1", "must not be negative"},
      {"angular_velocity_factor", "-0.1", "must not be negative"},
      {"angular_velocity_factor", "1.5", "must lie in [0, 1]"},
      {"joint_eps", "0", "must be positive"},
      {"max_passes", "-1", "must not be negative (0 = 5 n^2)"},
      {"control_k", "-3", "must not be negative"},
      {"control_cap", "0", "must be positive"},
      {"torsion_k", "-1", "must not be negative"},
      {"torsion_cap", "0", "must be positive"},
      {"torsion_tolerance", "-0.1", "must not be negative"},
      {"torsion_tolerance", "0.5", "must lie in [0, 0.5)"},
      {"interpolation_steps", "-1", "must not be negative"},
      {"interpolation_fallback", "0", "must be positive"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(std::string(c.key) + " = " + c.value);
    const std::string field = std::string("params: field '") + c.key + "': " + c.reason;
    EXPECT_EQ(params_error(std::string("{\"") + c.key + "\": " + c.value + "}"),
              "p.json: " + field);
    EXPECT_EQ(set_error(std::string(c.key) + "=" + c.value), "--set: " + field);
  }
  // every ranged row (a new one too) refuses a value past each bound, alike in both places
  for (const ParamRow& row : param_table()) {
    const ParamRange& g = row.valid;
    std::vector<double> bad;
    if (g.lo) bad.push_back(g.lo_allowed ? *g.lo - 1.0 : *g.lo);
    if (g.hi) bad.push_back(g.hi_allowed ? *g.hi + 1.0 : *g.hi);
    for (double v : bad) {
      const std::string text = format_param(row, v), why = range_violation(row, v);
      SCOPED_TRACE(row.name + " = " + text);
      EXPECT_FALSE(why.empty());
      EXPECT_EQ(params_error("{\"" + row.name + "\": " + text + "}"),
                "p.json: params: field '" + row.name + "': " + why);
      EXPECT_EQ(set_error(row.name + "=" + text),
                "--set: params: field '" + row.name + "': " + why);
    }
  }
  // the bounds that are allowed are accepted
  for (const char* ok : {"angular_velocity_factor=0", "angular_velocity_factor=1", "damping=0",
                         "torsion_tolerance=0", "max_passes=0", "interpolation_steps=0"}) {
    EXPECT_EQ(set_error(ok), "") << ok;
  }
}

TEST(ParamSet, EachKindParsesItsTextAndRejectsBadText) {
  const ParamOverrides o = parse_param_overrides(
      {"dt=0.025", "max_passes=40", "centripetal=true", "gyroscopic=false", "control_spring=capped",
       "integration=free-rods", "damping=1", "damping=2.5", "preset=paper"},
      "--set");
  EngineParams p;
  o.apply(p);
  EXPECT_EQ(p.dt, 0.025);
  EXPECT_EQ(p.max_passes, 40);
  EXPECT_TRUE(p.centripetal);
  EXPECT_FALSE(p.gyroscopic);
  EXPECT_EQ(p.control_spring, SpringLaw::kCapped);
  EXPECT_EQ(p.scheme, Scheme::kGaussSeidel);  // integration, the old key, still read
  EXPECT_TRUE(p.free_rods);
  EXPECT_EQ(p.damping, 2.5);  // the later one wins
  EXPECT_EQ(o.preset, "paper");

  EXPECT_EQ(set_error("dt=abc"), "--set: params: field 'dt': expected a number, got 'abc'");
  EXPECT_EQ(set_error("dt=0.05s"), "--set: params: field 'dt': expected a number, got '0.05s'");
  EXPECT_EQ(set_error("dt=inf"), "--set: params: field 'dt': not a finite number");
  EXPECT_EQ(set_error("dt="), "--set: params: field 'dt': expected a number, got ''");
  EXPECT_EQ(set_error("max_passes=2.5"),
            "--set: params: field 'max_passes': expected an integer, got '2.5'");
  EXPECT_EQ(set_error("max_passes=4294967297"),
            "--set: params: field 'max_passes': integer out of range");
  EXPECT_EQ(set_error("centripetal=yes"),
            "--set: params: field 'centripetal': expected true or false, got 'yes'");
  EXPECT_EQ(
      set_error("control_spring=bungee"),
      "--set: params: field 'control_spring': unknown value 'bungee' (expected linear|capped)");
  EXPECT_EQ(set_error("preset=fast"),
            "--set: params: field 'preset': unknown preset 'fast' (original|paper|robust)");
  EXPECT_EQ(set_error("=3"), "--set: field '=3': expected key=value");
  EXPECT_EQ(set_error("damping"), "--set: field 'damping': expected key=value");
  // a typo gets the closest key; a name near none lists them all
  EXPECT_EQ(set_error("dampng=3"), "--set: unknown parameter 'dampng' (did you mean 'damping'?)");
  EXPECT_EQ(set_error("torsion_tolerence=0.2"),
            "--set: unknown parameter 'torsion_tolerence' (did you mean 'torsion_tolerance'?)");
  const std::string unknown = set_error("wobbliness=3");
  EXPECT_EQ(unknown.rfind("--set: unknown parameter 'wobbliness' (known: preset, dt, damping,", 0),
            0u)
      << unknown;
  for (const ParamRow& row : param_table())
    EXPECT_NE(unknown.find(row.name), std::string::npos) << row.name;
  // in a scene file too, naming the file and the field
  EXPECT_EQ(params_error(R"({"dampng": 3})"),
            "p.json: params: field 'dampng': unknown parameter 'dampng' (did you mean 'damping'?)");
}

std::string scene_params_error(const std::string& params_json,
                               const std::vector<std::string>& set) {
  try {
    params_from_json(parse_json_text(params_json, "p.json"), "p.json",
                     parse_param_overrides(set, "--set"));
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(ParamSet, AnExplicitDampingTurnsDampingAutoOffAndIsTheValueUsed) {
  // robust's damping is auto: a number given for it, by the file or --set, is the one used
  const EngineParams file =
      params_from_json(parse_json_text(R"({"damping": 1})", "p.json"), "p.json");
  EXPECT_FALSE(file.damping_auto);
  EXPECT_EQ(file.damping, 1.0);
  const EngineParams set =
      params_from_json(parse_json_text(R"({"damping": "auto"})", "p.json"), "p.json",
                       parse_param_overrides({"damping=1"}, "--set"));
  EXPECT_FALSE(set.damping_auto);
  EXPECT_EQ(set.damping, 1.0);
  // and the other way round; overrides apply in order, the later wins
  const EngineParams back =
      params_from_json(parse_json_text(R"({"preset": "original", "damping": 2})", "p.json"),
                       "p.json", parse_param_overrides({"damping=1", "damping=auto"}, "--set"));
  EXPECT_TRUE(back.damping_auto);
  // a file that gives both is contradictory
  EXPECT_EQ(scene_params_error(R"({"preset": "original", "damping": 2, "damping_auto": true})", {}),
            "p.json: params: field 'damping': a damping value beside damping auto: give one or the "
            "other");
  EXPECT_EQ(
      scene_params_error(R"({"damping": "auto", "damping_auto": false})", {}),
      "p.json: params: field 'damping_auto': beside \"damping\": \"auto\": give one or the other");
}

TEST(ParamSet, AValueTheRunWouldNotUseIsRefusedNamingWhereItCameFrom) {
  // robust runs the exact solve: the gauss-seidel rows do not take part
  EXPECT_EQ(scene_params_error("{}", {"max_passes=10"}),
            "--set: field 'max_passes': applies to the gauss-seidel scheme only (this run: scheme "
            "implicit)");
  EXPECT_EQ(scene_params_error(R"({"joint_eps": 1e-6})", {}),
            "p.json: params: field 'joint_eps': applies to the gauss-seidel scheme only (this run: "
            "scheme implicit)");
  EXPECT_EQ(scene_params_error(R"({"scheme": "exact", "free_rods": true})", {}),
            "p.json: params: field 'free_rods': applies to the gauss-seidel scheme only (this run: "
            "scheme exact)");
  EXPECT_EQ(scene_params_error(R"({"preset": "original"})", {"implicit_max_splits=2"}),
            "--set: field 'implicit_max_splits': applies to the implicit scheme only (this run: "
            "scheme gauss-seidel)");
  EXPECT_EQ(scene_params_error(R"({"torsion_cap": 0.2})", {}),
            "p.json: params: field 'torsion_cap': applies to capped torsion springs only (this "
            "run: linear)");
  EXPECT_EQ(scene_params_error(R"({"interpolation": "none", "interpolation_steps": 5})", {}),
            "p.json: params: field 'interpolation_steps': applies only with an interpolation (this "
            "run: none)");
  EXPECT_EQ(scene_params_error(R"({"interpolation_fallback": 0.01})", {}),
            "p.json: params: field 'interpolation_fallback': applies to polar interpolation only "
            "(this run: linear)");
  // ... but not where they take part, nor at the preset's own value (a written scene lists it)
  EXPECT_EQ(scene_params_error(R"({"preset": "original", "max_passes": 10})", {}), "");
  EXPECT_EQ(scene_params_error(R"({"joint_eps": 0.001, "torsion_cap": 0.5})", {}), "");
  EXPECT_EQ(scene_params_error(R"({"torsion_spring": "capped", "torsion_cap": 0.2})", {}), "");
  EXPECT_EQ(scene_params_error(R"({"preset": "original"})", {"scheme=implicit"}), "");
}

// two points on one rod: the first gives no k, the second its own
Scene two_point_scene(double params_k, std::optional<double> first_k) {
  Scene s = test::scene_for(test::one_rod(), preset_params("original"), 40);
  s.params.control_k = params_k;
  ControlPoint a = test::control(0, 1.0, Vec3(0.6, 0.2, 0.7), 1.0);
  a.k = first_k;
  a.spring.reset();
  a.cap.reset();
  s.control_points = {a, test::control(0, 0.0, Vec3(0.1, -0.1, 0.1), 7.0)};
  s.initial_pose = rest_pose(s.rig);
  return s;
}

TEST(ControlPointInheritance, APointWithoutKFollowsTheParamsAtUse) {
  Scene s = two_point_scene(10.0, std::nullopt);
  s.params.control_k = 50.0;  // after the scene is built, as the tuner and --set do
  EXPECT_EQ(s.control_points[0].k_in(s.params), 50.0);
  EXPECT_EQ(s.control_points[1].k_in(s.params), 7.0);  // its own k stays
  // the same run as a scene that gives the first point k = 50 itself
  const RunSummary inherit = run_scene(s);
  const RunSummary own = run_scene(two_point_scene(10.0, 50.0));
  EXPECT_EQ(state_hash(inherit.final_frames), state_hash(own.final_frames));
  const RunSummary other = run_scene(two_point_scene(10.0, std::nullopt));
  EXPECT_NE(state_hash(inherit.final_frames), state_hash(other.final_frames));  // k matters here
}

TEST(ControlPointInheritance, TheWriterKeepsOnlyWhatAPointGives) {
  const std::string rig = test::model_path("rigs/elbow.json");
  const Json doc = parse_json_text(R"({"rig": ")" + rig + R"(", "params": {"control_k": 12},
      "control_points": [{"bone": "forearm", "target": [0, 1, 3]},
                         {"bone": "forearm", "target": [0, 1, 3], "k": 7, "spring": "capped", "cap": 0.2}]})",
                                   "s.json");
  const Scene s = scene_from_json(doc, "s.json", "/");
  const Json out = scene_to_json(s);
  const Json& cp0 = out["control_points"][0];
  EXPECT_FALSE(cp0.contains("k") || cp0.contains("spring") || cp0.contains("cap")) << cp0.dump();
  EXPECT_EQ(out["control_points"][1]["k"], 7.0);
  EXPECT_EQ(out["control_points"][1]["spring"], "capped");
  EXPECT_EQ(out["control_points"][1]["cap"], 0.2);
  // read back, a changed control_k still reaches the first point only
  Scene back = scene_from_json(out, "rt.json", "/");
  back.params.control_k = 40.0;
  EXPECT_EQ(back.control_points[0].k_in(back.params), 40.0);
  EXPECT_EQ(back.control_points[1].k_in(back.params), 7.0);
  EXPECT_EQ(back.control_points[1].cap_in(back.params), 0.2);
  EXPECT_EQ(back.control_points[1].spring_in(back.params), SpringLaw::kCapped);
}

}  // namespace
}  // namespace physik
