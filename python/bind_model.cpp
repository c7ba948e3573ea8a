// Rig and Scene: loading (the CLI's loaders, the same messages), building from dicts, reading
// back. Parameters pass through as dicts in the scene file's format (models/README.md), read and
// written by the parameter table (physik/model/params.h), so a new parameter needs no new binding.
#include <algorithm>
#include <cmath>
#include <optional>

#include <pybind11/stl.h>

#include "physik/io/json_fields.h"
#include "physik/io/rig_io.h"
#include "physik/io/scene_io.h"
#include "physik/io/scene_warnings.h"
#include "physik/model/errors.h"
#include "physik/model/rig_generators.h"
#include "physik/model/scaled_scene.h"
#include "python/bind_common.h"

namespace physik::python {

py::array vec3_array(const std::vector<Vec3>& v) {
  py::array_t<double> a({static_cast<py::ssize_t>(v.size()), py::ssize_t(3)});
  auto m = a.mutable_unchecked<2>();
  for (std::size_t i = 0; i < v.size(); ++i) {
    for (int k = 0; k < 3; ++k) m(i, k) = v[i][k];
  }
  return a;
}

namespace {

nlohmann::json vec_json(const Vec3& v) {
  return {v.x(), v.y(), v.z()};
}

// The scene's convergence settings as the scene file writes them.
nlohmann::json convergence_json(const ConvergenceParams& c) {
  return {{"residual_tol", c.residual_tol},
          {"speed_tol", c.speed_tol},
          {"settle_steps", c.settle_steps},
          {"stop_when_converged", c.stop_when_converged},
          {"stop_at_residual_tol", c.stop_at_residual_tol},
          {"divergence_energy", c.divergence_energy}};
}

// Scene.update(params=..., convergence=..., steps=...): the file's rules and messages, applied
// after loading (as the experiments set s.params.damping).
//
// params go through the parameter table: the scene's params as the scene writer gives them, with
// the changes on top, are read again as a scene's "params" object (params_from_json: the same
// keys, kinds, ranges and messages, and the same refusal of a value the run would not use, judged
// with the scene's own settings), so a new row needs nothing here. "preset" replaces every value
// by the preset's, then the other changes apply. damping and damping_auto are one setting: a
// change of either replaces both ("damping": 1 turns auto off, "damping": "auto" on).
void update_params(Scene& s, const nlohmann::json& changes, const std::string& source) {
  JsonContext{source, "params"}.require_object(changes, "params");
  nlohmann::json read =
      changes.contains("preset") ? nlohmann::json::object() : params_to_json(s.params);
  if (changes.contains("damping") || changes.contains("damping_auto")) {
    read.erase("damping");
    read.erase("damping_auto");
  }
  for (const auto& [key, value] : changes.items()) read[key] = value;
  s.params = params_from_json(read, source, {}, nullptr, param_scene(s));
  for (const auto& [key, value] : changes.items()) {
    if (key != "preset" &&
        std::find(s.params_given.begin(), s.params_given.end(), key) == s.params_given.end()) {
      s.params_given.push_back(key);
    }
  }
}

void update_scene(Scene& s, py::object params, py::object convergence, py::object steps,
                  const std::string& source) {
  if (!params.is_none()) update_params(s, to_json(params, "params"), source);
  if (!convergence.is_none()) {
    const nlohmann::json c = to_json(convergence, "convergence");
    const JsonContext ctx{source, "convergence"};
    ctx.require_object(c, "convergence");
    ctx.only_keys(c, {"residual_tol", "speed_tol", "settle_steps", "stop_when_converged",
                      "stop_at_residual_tol", "divergence_energy"});
    ConvergenceParams& p = s.convergence;
    const auto non_negative = [&](const char* key, double fallback) {
      const double v = ctx.number_or(c, key, fallback);
      if (v < 0.0) ctx.fail(key, "must not be negative");
      return v;
    };
    p.residual_tol = non_negative("residual_tol", p.residual_tol);
    p.speed_tol = non_negative("speed_tol", p.speed_tol);
    p.settle_steps = ctx.integer_or(c, "settle_steps", p.settle_steps);
    if (p.settle_steps < 1) ctx.fail("settle_steps", "must be at least 1");
    p.stop_when_converged = ctx.boolean_or(c, "stop_when_converged", p.stop_when_converged);
    p.stop_at_residual_tol = ctx.boolean_or(c, "stop_at_residual_tol", p.stop_at_residual_tol);
    p.divergence_energy = non_negative("divergence_energy", p.divergence_energy);
  }
  if (!steps.is_none()) {
    const nlohmann::json doc = {{"steps", to_json(steps, "steps")}};
    const int n = JsonContext{source, ""}.integer(doc, "steps");
    if (n < 1) throw_input_error(source, "", "steps", "must be at least 1");
    s.steps = n;
  }
}

void bind_rig(py::module_& m) {
  py::class_<Rig> cls(m, "Rig",
                      R"doc(A rig: bones in DFS order (parents first), rest pose, limits, masses.

Constant: a Simulation never changes it. Build one with Rig.load, Rig.chain or Rig.from_dict.
Arrays are copies, per bone in DFS order; positions in rig units, world frame (Z up).)doc");
  cls.def_static("load", &load_rig, py::arg("path"),
                 "Load a rig file (models/README.md). Bad input raises InputError with the CLI's "
                 "message (file, element, field).")
      .def_static("chain", &make_chain_rig, py::arg("n"), py::arg("bone_length") = 1.0,
                  py::arg("radius") = 0.5,
                  "A straight chain of n free bones along +Z from the origin (`physik rig chain`).")
      .def_static(
          "from_dict",
          [](py::object d, const std::string& source) {
            return rig_from_json(to_json(d, "rig"), source);
          },
          py::arg("d"), py::arg("source") = "<rig dict>",
          "A rig from a dict in the rig file format; `source` names it in error messages.")
      .def(
          "to_dict", [](const Rig& r) { return from_json(rig_to_json(r)); },
          "The rig as a dict in the rig file format (explicit rest frames, total masses).")
      .def_readonly("name", &Rig::name, "The rig's name.")
      .def_readonly("nbone", &Rig::nbone, "Number of bones.")
      .def_readonly("bone_names", &Rig::bone_name, "Bone names, DFS order.")
      .def_readonly("bone_parents", &Rig::bone_parent, "Parent index per bone (-1 for the root).")
      .def_readonly("bone_lengths", &Rig::bone_length, "Rest length per bone, rig units.")
      .def_readonly("bone_masses", &Rig::bone_mass, "Mass per bone, kg.")
      .def_property_readonly(
          "rest_heads", [](const Rig& r) { return vec3_array(r.bone_rest_head_world); },
          "(nbone, 3) rest heads, world, rig units (a copy).")
      .def_property_readonly(
          "rest_tails", [](const Rig& r) { return vec3_array(r.bone_rest_tail_world); },
          "(nbone, 3) rest tails, world, rig units (a copy).")
      .def_property_readonly("total_mass", &Rig::total_mass, "Total mass, kg.")
      .def_property_readonly("height", &Rig::height,
                             "Extent of the rest pose along world Z, rig units.")
      .def("find_bone", &Rig::find_bone, py::arg("name"), "Index of a bone by name, -1 if absent.")
      .def("__repr__", [](const Rig& r) {
        return "<physik.Rig '" + r.name + "' with " + std::to_string(r.nbone) + " bones>";
      });
  bind_rig_source(cls);
}

void bind_scene_reading(py::class_<Scene>& cls);
void bind_scene_views(py::class_<Scene>& cls);

void bind_scene(py::module_& m) {
  py::class_<Scene> cls(m, "Scene",
                        R"doc(A scene: a rig, engine parameters, control points, a schedule, steps.

Build one with Scene.load (a file, as the CLI reads it) or Scene.from_dict (the same format as a
dict). Parameters, control points and the convergence settings read back as dicts in the scene
file's format (models/README.md "Scenes"); Scene.update changes them with the file's checks.)doc");
  bind_scene_reading(cls);
  bind_scene_views(cls);
}

}  // namespace

ParamOverrides param_overrides(const py::object& values, const std::string& source) {
  std::vector<std::string> assignments;
  if (py::isinstance<py::dict>(values)) {
    for (const auto& kv : values.cast<py::dict>()) {
      const nlohmann::json v = to_json(kv.second, source);
      // the value as --set's text: a string as it is, a number or a boolean as JSON writes it
      // (shortest text that reads back to the same double)
      assignments.push_back(py::str(kv.first).cast<std::string>() + "=" +
                            (v.is_string() ? v.get<std::string>() : v.dump()));
    }
  } else if (!values.is_none()) {
    assignments = values.cast<std::vector<std::string>>();
  }
  return parse_param_overrides(assignments, source);
}

namespace {

// Scene.load: exactly `physik simulate PATH --set key=value... --steps N`: the same parsing,
// checks and messages, with the keyword, "overrides", as their source
Scene load_scene_from_python(const std::string& path, py::object overrides, int steps) {
  std::vector<std::string> warnings;
  Scene s = load_scene(path, param_overrides(overrides, "overrides"), warnings);
  warn_input(warnings);
  // as `simulate --steps N`: negative is bad input, 0 keeps the scene's
  if (steps < 0) throw_input_error("steps", "", "", "must not be negative");
  if (steps > 0) s.steps = steps;
  return s;
}

// load, from_dict, to_dict, update: the scene file's format both ways
void bind_scene_reading(py::class_<Scene>& cls) {
  cls.def_static("load", &load_scene_from_python, py::arg("path"),
                 py::arg("overrides") = py::none(), py::arg("steps") = 0,
                 R"doc(Load a scene file as `physik simulate PATH [--set k=v]... [--steps N]` does.

overrides: a dict {param: value} or a list of "key=value" strings: `--set`, merged into the file's
params before the scene is read (control points that take their k, spring or cap from the params
follow; "preset" swaps the base preset); an unknown key raises InputError naming overrides.
steps: replaces the scene's step count (0 keeps it, as --steps). Relative rig paths resolve against the scene's folder.
A quaternion within 1e-3 of unit is normalised with an InputWarning; farther, InputError.)doc")
      .def_static(
          "from_dict",
          [](py::object d, const std::string& base_dir, const std::string& source) {
            std::vector<std::string> warnings;
            Scene s = scene_from_json(to_json(d, "scene"), source, base_dir, {}, warnings);
            warn_input(warnings);
            return s;
          },
          py::arg("d"), py::arg("base_dir") = ".", py::arg("source") = "<scene dict>",
          R"doc(A scene from a dict in the scene file format.

"rig" is a rig file path (relative paths resolve against base_dir) or the rig dict itself (the rig
file format; Scene.rig_file is then ""). `source` names the dict in error messages, as a file name
would.)doc")
      .def(
          "to_dict", [](const Scene& s) { return from_json(scene_to_json(s)); },
          "The scene as a dict in the scene file format (rig as an absolute path, or inline when "
          "it came inline).")
      .def(
          "update",
          [](Scene& s, py::object params, py::object convergence, py::object steps) {
            update_scene(s, params, convergence, steps, s.file.empty() ? "<scene>" : s.file);
          },
          py::kw_only(), py::arg("params") = py::none(), py::arg("convergence") = py::none(),
          py::arg("steps") = py::none(),
          R"doc(Change the loaded scene in place, with the scene file's checks and messages.

params: {key: value} applied to the resolved params, with the parameter table's checks (as an
experiment sets s.params.damping; control points that give no k, spring or cap follow the params,
those that give their own keep it); "preset" first resets every parameter to that preset's values
(physik.param_table() lists the keys); convergence: {key: value} for the convergence settings;
steps: the step count.)doc")
      .def(
          "copy", [](const Scene& s) { return Scene(s); }, "An independent copy.")
      .def("__copy__", [](const Scene& s) { return Scene(s); })
      .def(
          "__deepcopy__", [](const Scene& s, py::dict) { return Scene(s); }, py::arg("memo"));
}

// what a scene holds, read back as the scene file's dicts
void bind_scene_views(py::class_<Scene>& cls) {
  cls.def_readonly("file", &Scene::file, "Where the scene came from (its path or source name).")
      .def_readonly("rig_file", &Scene::rig_file, "The resolved rig path (\"\" for an inline rig).")
      .def_property_readonly(
          "rig", [](const Scene& s) { return s.rig; }, "The scene's rig (a copy).")
      .def_readonly("steps", &Scene::steps, "Steps to run.")
      .def_property_readonly(
          "params", [](const Scene& s) { return from_json(params_to_json(s.params)); },
          "The engine parameters, resolved, as the scene file's params dict.")
      .def_property_readonly(
          "convergence", [](const Scene& s) { return from_json(convergence_json(s.convergence)); },
          "The convergence settings as a dict (0 = the default tolerance).")
      .def_property_readonly(
          "control_points",
          [](const Scene& s) {
            py::list out;
            for (const ControlPoint& c : s.control_points) {
              out.append(from_json({{"name", c.name},
                                    {"bone", s.rig.bone_name[c.bone]},
                                    {"alpha", c.alpha},
                                    {"target", vec_json(c.target_world)},
                                    {"spring", to_string(c.spring_in(s.params))},
                                    {"k", c.k_in(s.params)},
                                    {"cap", c.cap_in(s.params)}}));
            }
            return out;
          },
          "The control points as dicts, spring, k and cap resolved (a point that gives none takes "
          "the params' at use, so it follows Scene.update(params=...)).")
      .def_property_readonly(
          "schedule",
          [](const Scene& s) {
            py::list out;
            for (const TargetChange& t : s.schedule) {
              out.append(from_json({{"step", t.step},
                                    {"control_point", t.control_point},
                                    {"target", vec_json(t.target_world)}}));
            }
            return out;
          },
          "The target changes, sorted by step, as dicts (control_point is an index).")
      .def_property_readonly("residual_tol", &Scene::residual_tol,
                             "Residual tolerance in use, rig units.")
      .def_property_readonly("speed_tol", &Scene::speed_tol,
                             "Rest speed tolerance in use, rig units/s.")
      .def("__repr__", [](const Scene& s) {
        return "<physik.Scene '" + s.file + "': " + std::to_string(s.rig.nbone) + " bones, " +
               std::to_string(s.control_points.size()) + " control points, " +
               std::to_string(s.steps) + " steps>";
      });
}

}  // namespace

void bind_model(py::module_& m) {
  bind_rig(m);
  bind_scene(m);
  m.def(
      "param_table", [] { return from_json(param_table_json()); },
      R"doc(The engine parameter table, as `physik params --json` prints it.

{"presets": [...], "default_preset": name, "params": [row, ...]}, a row per scene "params" key:
name, kind (real|integer|boolean|choice), unit, defaults {preset: value}, valid (text), doc, and
when they apply choices, range {lo, lo_allowed, hi, hi_allowed}, zero_means, tune [lo, hi].
Scene.load(overrides=...), Scene.update(params=...), tune(params=...) and sweep grids take these
names.)doc");
  m.def(
      "scaled_scene",
      [](const Scene& scene, double scale, std::optional<double> density, bool scale_torsion) {
        if (!(scale > 0.0) || !std::isfinite(scale)) {
          throw_input_error("scale", "", "", "must be a positive finite number");
        }
        if (density && (!(*density > 0.0) || !std::isfinite(*density))) {
          throw_input_error("density", "", "",
                            "must be a positive finite number (kg per rig unit)");
        }
        return scaled_scene(scene, scale, density, scale_torsion);
      },
      py::arg("scene"), py::arg("scale"), py::arg("density") = py::none(),
      py::arg("scale_torsion") = false,
      R"doc(The scene on its rig scaled by `scale` about the origin (physik/model/scaled_scene.h):
positions, radii, targets, the control points' caps and the root's start times scale; every
bone's mass density x length (kg per rig unit; None keeps the masses) and its inertia the
cylinder's; torsion k times density x scale^3 with scale_torsion. The tuning study's 0.1x / 10x
rigs.)doc");
}

}  // namespace physik::python
