#include "physik/io/scene_io.h"

#include <algorithm>
#include <filesystem>

#include "physik/io/rig_io.h"
#include "physik/model/errors.h"

namespace physik {

namespace {

SpringLaw spring_law(const JsonContext& ctx, const Json& obj, const std::string& key,
                     SpringLaw fallback) {
  const std::string v = ctx.choice_or(obj, key, {"linear", "capped"}, to_string(fallback));
  return v == "linear" ? SpringLaw::kLinear : SpringLaw::kCapped;
}

double positive(const JsonContext& ctx, const Json& obj, const std::string& key, double fallback) {
  const double v = ctx.number_or(obj, key, fallback);
  if (!(v > 0.0)) ctx.fail(key, "must be positive");
  return v;
}

double non_negative(const JsonContext& ctx, const Json& obj, const std::string& key,
                    double fallback) {
  const double v = ctx.number_or(obj, key, fallback);
  if (v < 0.0) ctx.fail(key, "must not be negative");
  return v;
}

int control_point_ref(const JsonContext& ctx, const Json& v, const std::vector<ControlPoint>& cps) {
  if (v.is_number_integer()) {
    const int i = v.get<int>();
    if (i < 0 || i >= static_cast<int>(cps.size())) {
      ctx.fail("control_point", "index " + std::to_string(i) + " out of range (" +
                                    std::to_string(cps.size()) + " control points)");
    }
    return i;
  }
  if (v.is_string()) {
    for (std::size_t i = 0; i < cps.size(); ++i) {
      if (cps[i].name == v.get<std::string>()) return static_cast<int>(i);
    }
    ctx.fail("control_point", "no control point named '" + v.get<std::string>() + "'");
  }
  ctx.fail("control_point", "expected an index or a control point name");
}

}  // namespace

EngineParams params_from_json(const Json& params, const std::string& source) {
  JsonContext ctx{source, "params"};
  if (params.is_null()) return preset_params(kDefaultPreset, source);
  ctx.require_object(params, "params");
  ctx.only_keys(params, {"preset", "dt", "damping", "angular_velocity_factor", "joint_eps",
                         "joint_eps_relative",  // TODO(table)
                         "max_passes", "centripetal", "gyroscopic", "control_k",
                         "control_spring", "control_cap", "torsion_k", "torsion_spring",
                         "torsion_cap", "torsion_tolerance", "integration", "interpolation",
                         "interpolation_steps", "interpolation_fallback"});
  EngineParams p = preset_params(ctx.string_or(params, "preset", kDefaultPreset), source);
  p.dt = positive(ctx, params, "dt", p.dt);
  p.damping = non_negative(ctx, params, "damping", p.damping);
  p.angular_velocity_factor =
      non_negative(ctx, params, "angular_velocity_factor", p.angular_velocity_factor);
  if (p.angular_velocity_factor > 1.0) ctx.fail("angular_velocity_factor", "must lie in [0, 1]");
  p.joint_eps = positive(ctx, params, "joint_eps", p.joint_eps);
  // TODO(table): joint_eps_relative in [0, 1)
  p.joint_eps_relative = non_negative(ctx, params, "joint_eps_relative", p.joint_eps_relative);
  if (p.joint_eps_relative >= 1.0) ctx.fail("joint_eps_relative", "must lie in [0, 1)");
  p.max_passes = ctx.integer_or(params, "max_passes", p.max_passes);
  if (p.max_passes < 0) ctx.fail("max_passes", "must not be negative (0 = 5 n^2)");
  p.centripetal = ctx.boolean_or(params, "centripetal", p.centripetal);
  p.gyroscopic = ctx.boolean_or(params, "gyroscopic", p.gyroscopic);
  p.control_k = non_negative(ctx, params, "control_k", p.control_k);
  p.control_spring = spring_law(ctx, params, "control_spring", p.control_spring);
  p.control_cap = positive(ctx, params, "control_cap", p.control_cap);
  p.torsion_k = non_negative(ctx, params, "torsion_k", p.torsion_k);
  p.torsion_spring = spring_law(ctx, params, "torsion_spring", p.torsion_spring);
  p.torsion_cap = positive(ctx, params, "torsion_cap", p.torsion_cap);
  p.torsion_tolerance = non_negative(ctx, params, "torsion_tolerance", p.torsion_tolerance);
  if (p.torsion_tolerance >= 0.5) ctx.fail("torsion_tolerance", "must lie in [0, 0.5)");
  const std::string integ =
      ctx.choice_or(params, "integration", {"articulated", "free-rods"}, to_string(p.integration));
  p.integration = integ == "articulated" ? Integration::kArticulated : Integration::kFreeRods;
  const std::string interp = ctx.choice_or(
      params, "interpolation", {"none", "linear", "polar-head", "polar-com"},
      to_string(p.interpolation));
  p.interpolation = interp == "none"         ? Interpolation::kNone
                    : interp == "linear"     ? Interpolation::kLinear
                    : interp == "polar-head" ? Interpolation::kPolarHead
                                             : Interpolation::kPolarCom;
  p.interpolation_steps = ctx.integer_or(params, "interpolation_steps", p.interpolation_steps);
  if (p.interpolation_steps < 0) ctx.fail("interpolation_steps", "must not be negative");
  p.interpolation_fallback =
      positive(ctx, params, "interpolation_fallback", p.interpolation_fallback);
  return p;
}

Json params_to_json(const EngineParams& p) {
  return {{"preset", p.preset},
          {"dt", p.dt},
          {"damping", p.damping},
          {"angular_velocity_factor", p.angular_velocity_factor},
          {"joint_eps", p.joint_eps},
          {"joint_eps_relative", p.joint_eps_relative},  // TODO(table)
          {"max_passes", p.max_passes},
          {"centripetal", p.centripetal},
          {"gyroscopic", p.gyroscopic},
          {"control_k", p.control_k},
          {"control_spring", to_string(p.control_spring)},
          {"control_cap", p.control_cap},
          {"torsion_k", p.torsion_k},
          {"torsion_spring", to_string(p.torsion_spring)},
          {"torsion_cap", p.torsion_cap},
          {"torsion_tolerance", p.torsion_tolerance},
          {"integration", to_string(p.integration)},
          {"interpolation", to_string(p.interpolation)},
          {"interpolation_steps", p.interpolation_steps},
          {"interpolation_fallback", p.interpolation_fallback}};
}

Scene scene_from_json(const Json& doc, const std::string& source, const std::string& base_dir) {
  JsonContext top{source, ""};
  top.require_object(doc, "");
  top.only_keys(doc, {"name", "comment", "rig", "params", "control_points", "schedule", "steps",
                      "convergence", "initial_pose", "initial_velocity"});
  Scene s;
  s.file = source;

  // the rig, relative to the scene file unless absolute
  const std::string rig_ref = top.string(doc, "rig");
  std::filesystem::path rig_path(rig_ref);
  if (rig_path.is_relative()) rig_path = std::filesystem::path(base_dir) / rig_path;
  s.rig_file = rig_path.lexically_normal().string();
  if (!std::filesystem::exists(s.rig_file)) {
    top.fail("rig", "rig file '" + s.rig_file + "' does not exist");
  }
  s.rig = load_rig(s.rig_file);

  s.params = params_from_json(doc.contains("params") ? doc["params"] : Json(nullptr), source);

  s.steps = top.integer_or(doc, "steps", s.steps);
  if (s.steps < 1) top.fail("steps", "must be at least 1");

  // control points
  if (doc.contains("control_points")) {
    const Json& cps = doc["control_points"];
    if (!cps.is_array()) top.fail("control_points", "expected an array");
    for (std::size_t i = 0; i < cps.size(); ++i) {
      JsonContext ctx{source, "control_points[" + std::to_string(i) + "]"};
      const Json& c = cps[i];
      ctx.require_object(c, "");
      ctx.only_keys(c, {"name", "bone", "alpha", "target", "spring", "k", "cap", "comment"});
      ControlPoint cp;
      cp.name = ctx.string_or(c, "name", "");
      const std::string bone = ctx.string(c, "bone");
      cp.bone = s.rig.find_bone(bone);
      if (cp.bone < 0) ctx.fail("bone", "unknown bone '" + bone + "' in rig " + s.rig_file);
      cp.alpha = ctx.number_or(c, "alpha", 1.0);
      if (cp.alpha < 0.0 || cp.alpha > 1.0) ctx.fail("alpha", "must lie in [0, 1] (0 = head, 1 = tail)");
      cp.target_world = ctx.vec3(c, "target");
      cp.spring = spring_law(ctx, c, "spring", s.params.control_spring);
      cp.k = non_negative(ctx, c, "k", s.params.control_k);
      cp.cap = positive(ctx, c, "cap", s.params.control_cap);
      s.control_points.push_back(cp);
    }
  }

  // schedule of target changes
  if (doc.contains("schedule")) {
    const Json& sch = doc["schedule"];
    if (!sch.is_array()) top.fail("schedule", "expected an array");
    for (std::size_t i = 0; i < sch.size(); ++i) {
      JsonContext ctx{source, "schedule[" + std::to_string(i) + "]"};
      ctx.require_object(sch[i], "");
      ctx.only_keys(sch[i], {"step", "control_point", "target", "comment"});
      TargetChange t;
      t.step = ctx.integer(sch[i], "step");
      if (t.step < 0 || t.step >= s.steps) {
        ctx.fail("step", "must lie in [0, steps) = [0, " + std::to_string(s.steps) + ")");
      }
      t.control_point = control_point_ref(ctx, ctx.require(sch[i], "control_point"),
                                          s.control_points);
      t.target_world = ctx.vec3(sch[i], "target");
      s.schedule.push_back(t);
    }
    std::stable_sort(s.schedule.begin(), s.schedule.end(),
                     [](const TargetChange& a, const TargetChange& b) { return a.step < b.step; });
  }

  // convergence settings
  if (doc.contains("convergence")) {
    const Json& c = doc["convergence"];
    JsonContext ctx{source, "convergence"};
    ctx.require_object(c, "convergence");
    ctx.only_keys(c, {"residual_tol", "speed_tol", "settle_steps", "stop_when_converged",
                      "stop_at_residual_tol", "divergence_energy"});
    s.convergence.residual_tol = non_negative(ctx, c, "residual_tol", 0.0);
    s.convergence.speed_tol = non_negative(ctx, c, "speed_tol", 0.0);
    s.convergence.settle_steps = ctx.integer_or(c, "settle_steps", s.convergence.settle_steps);
    if (s.convergence.settle_steps < 1) ctx.fail("settle_steps", "must be at least 1");
    s.convergence.stop_when_converged = ctx.boolean_or(c, "stop_when_converged", false);
    s.convergence.stop_at_residual_tol = ctx.boolean_or(c, "stop_at_residual_tol", false);
    s.convergence.divergence_energy = non_negative(ctx, c, "divergence_energy", 0.0);
  }

  // initial pose: rest, optionally with a root position and per-bone rotation vectors (deg)
  s.initial_pose = rest_pose(s.rig);
  if (doc.contains("initial_pose")) {
    const Json& ip = doc["initial_pose"];
    JsonContext ctx{source, "initial_pose"};
    ctx.require_object(ip, "initial_pose");
    ctx.only_keys(ip, {"root_head", "rotation_deg"});
    if (ip.contains("root_head")) s.initial_pose.root_head_world = ctx.vec3(ip, "root_head");
    if (ip.contains("rotation_deg")) {
      const Json& rot = ip["rotation_deg"];
      ctx.require_object(rot, "rotation_deg");
      for (auto it = rot.begin(); it != rot.end(); ++it) {
        const int b = s.rig.find_bone(it.key());
        if (b < 0) ctx.fail("rotation_deg." + it.key(), "unknown bone");
        const Vec3 v = ctx.vec3_value(*it, "rotation_deg." + it.key()) * (kPi / 180.0);
        const double angle = v.norm();
        s.initial_pose.bone_local_rotation[b] =
            angle > 0.0 ? Quat(Eigen::AngleAxisd(angle, v / angle)) : Quat::Identity();
      }
    }
  }
  if (doc.contains("initial_velocity")) s.initial_velocity_world = top.vec3(doc, "initial_velocity");
  return s;
}

Scene load_scene(const std::string& path) { return load_scene(path, Json::object()); }

Scene load_scene(const std::string& path, const Json& param_overrides) {
  Json doc = read_json_file(path);
  if (!param_overrides.empty()) {
    if (doc.is_object() && (!doc.contains("params") || doc["params"].is_null())) {
      doc["params"] = Json::object();
    }
    if (doc.is_object() && doc["params"].is_object()) {
      for (auto it = param_overrides.begin(); it != param_overrides.end(); ++it) {
        doc["params"][it.key()] = it.value();
      }
    }
  }
  const std::string base = std::filesystem::path(path).parent_path().string();
  return scene_from_json(doc, path, base.empty() ? "." : base);
}

Json parse_param_overrides(const std::vector<std::string>& assignments, const std::string& source) {
  const Json known = params_to_json(EngineParams{});
  Json out = Json::object();
  for (const std::string& kv : assignments) {
    const auto eq = kv.find('=');
    if (eq == std::string::npos || eq == 0) {
      throw_input_error(source, "", kv, "expected key=value");
    }
    const std::string key = kv.substr(0, eq), value = kv.substr(eq + 1);
    if (!known.contains(key)) {
      std::string all;
      for (auto it = known.begin(); it != known.end(); ++it) all += (all.empty() ? "" : ", ") + it.key();
      throw_input_error(source, "params", key, "unknown parameter (known: " + all + ")");
    }
    try {
      out[key] = Json::parse(value);
    } catch (const Json::exception&) {
      out[key] = value;  // a bare word such as capped or free-rods
    }
  }
  return out;
}

Json scene_to_json(const Scene& s) {
  Json cps = Json::array();
  for (const ControlPoint& c : s.control_points) {
    Json j = {{"bone", s.rig.bone_name[c.bone]},
              {"alpha", c.alpha},
              {"target", {c.target_world.x(), c.target_world.y(), c.target_world.z()}},
              {"spring", to_string(c.spring)},
              {"k", c.k},
              {"cap", c.cap}};
    if (!c.name.empty()) j["name"] = c.name;
    cps.push_back(j);
  }
  Json sch = Json::array();
  for (const TargetChange& t : s.schedule) {
    sch.push_back({{"step", t.step},
                   {"control_point", t.control_point},
                   {"target", {t.target_world.x(), t.target_world.y(), t.target_world.z()}}});
  }
  Json rot = Json::object();
  for (int i = 0; i < s.rig.nbone; ++i) {
    const Vec3 v = rotation_vector(s.initial_pose.bone_local_rotation[i]) * (180.0 / kPi);
    if (v.norm() > 0.0) rot[s.rig.bone_name[i]] = {v.x(), v.y(), v.z()};
  }
  const Vec3& r = s.initial_pose.root_head_world;
  return {{"rig", std::filesystem::absolute(s.rig_file).lexically_normal().string()},
          {"params", params_to_json(s.params)},
          {"control_points", cps},
          {"schedule", sch},
          {"steps", s.steps},
          {"convergence",
           {{"residual_tol", s.convergence.residual_tol},
            {"speed_tol", s.convergence.speed_tol},
            {"settle_steps", s.convergence.settle_steps},
            {"stop_when_converged", s.convergence.stop_when_converged},
            {"stop_at_residual_tol", s.convergence.stop_at_residual_tol},
            {"divergence_energy", s.convergence.divergence_energy}}},
          {"initial_pose", {{"root_head", {r.x(), r.y(), r.z()}}, {"rotation_deg", rot}}},
          {"initial_velocity",
           {s.initial_velocity_world.x(), s.initial_velocity_world.y(), s.initial_velocity_world.z()}}};
}

}  // namespace physik
