// solve: `physik solve` (physik/posing/scene_solve.h), the classic IK solvers and the engine. The
// options come from the solve options' table (physik/posing/solve_options.h): physik.solve's
// keywords, defaults and doc are built from _solve_option_table() (python/physik/__init__.py).
#include <pybind11/stl.h>

#include "physik/io/summary_io.h"
#include "physik/model/errors.h"
#include "physik/posing/scene_solve.h"
#include "python/bind_common.h"

namespace physik::python {

namespace {

const char* kind_name(SolveOptionKind k) {
  switch (k) {
    case SolveOptionKind::kReal:
      return "real";
    case SolveOptionKind::kInteger:
      return "integer";
    case SolveOptionKind::kBoolean:
      return "boolean";
    case SolveOptionKind::kChoice:
      return "choice";
    case SolveOptionKind::kVec3:
      return "vec3";
  }
  return "?";
}

// the table for Python: name, kind, unit, choices, doc and the default as a Python value
py::list option_table() {
  py::list rows;
  const SceneSolveOptions defaults;
  for (const SolveOptionRow& r : solve_option_table()) {
    const SolveOptionValue v = r.get(defaults);
    py::object def;
    switch (r.kind) {
      case SolveOptionKind::kChoice:
        def = py::str(v.text);
        break;
      case SolveOptionKind::kBoolean:
        def = py::bool_(v.number != 0.0);
        break;
      case SolveOptionKind::kInteger:
        def = py::int_(static_cast<long>(v.number));
        break;
      case SolveOptionKind::kReal:
        def = py::float_(v.number);
        break;
      case SolveOptionKind::kVec3:
        def = py::none();
        break;  // none given
    }
    py::dict d;
    d["name"] = r.name;
    d["kind"] = kind_name(r.kind);
    d["unit"] = r.unit;
    d["choices"] = r.choices;
    d["doc"] = r.doc;
    d["default"] = def;
    rows.append(d);
  }
  return rows;
}

// one Python value as the row's kind; TypeError-free: a wrong type is InputError naming it
SolveOptionValue option_value(const SolveOptionRow& row, const py::handle& value) {
  SolveOptionValue v;
  const std::string name = option_label(row.name, OptionSpelling::kName);
  try {
    switch (row.kind) {
      case SolveOptionKind::kChoice:
        v.text = value.cast<std::string>();
        break;
      case SolveOptionKind::kBoolean:
        v.number = value.cast<bool>() ? 1.0 : 0.0;
        break;
      case SolveOptionKind::kInteger:
        v.number = static_cast<double>(value.cast<long>());
        break;
      case SolveOptionKind::kReal:
        v.number = value.cast<double>();
        break;
      case SolveOptionKind::kVec3:
        if (!value.is_none()) v.vec = value.cast<std::vector<double>>();
        break;
    }
  } catch (const py::cast_error&) {
    throw_input_error(name, "", "",
                      std::string("expected a ") + kind_name(row.kind) + ", got " +
                          std::string(py::str(value.get_type().attr("__name__"))));
  }
  return v;
}

}  // namespace

void bind_solve(py::module_& m) {
  m.attr("_SOLVE_DT_GROWTH") = kSolveDtGrowth;
  m.attr("_SOLVE_MAX_DT") = kSolveMaxDt;
  m.def("_solve_option_table", &option_table, "The solve options' table (solve_options.h).");
  m.def(
      "_solve",
      [](const Scene& scene, const py::dict& options, bool raise_on_divergence) {
        SceneSolveOptions o;
        for (const auto& [key, value] : options) {
          const std::string name = key.cast<std::string>();
          const SolveOptionRow* row = find_solve_option(name);
          if (!row) throw_input_error(name, "", "", "not a solve option");
          if (row->kind == SolveOptionKind::kVec3 && value.is_none()) continue;
          set_solve_option(o, *row, option_value(*row, value), OptionSpelling::kName);
        }
        // the engine runs the contacts from the initial pose; a classic solver refuses a ground
        if (o.solver == "physik" || o.solver == "physik-explicit") check_start(scene);
        SceneSolveResult r;
        {
          py::gil_scoped_release release;
          r = solve_scene(scene, o, OptionSpelling::kName);
        }
        const nlohmann::json summary = solve_summary_to_json(r);
        if (raise_on_divergence && r.diverged) {
          throw DivergedRun(summary.value("divergence_reason", std::string("diverged")));
        }
        return py::make_tuple(
            from_json(summary),
            pose_arrays(r.scene.rig, r.scene.params.locked_axes(), r.frames, r.pose));
      },
      py::arg("scene"), py::arg("options"), py::arg("raise_on_divergence"),
      "physik.solve's C++ half: (summary dict, pose arrays).");
}

}  // namespace physik::python
