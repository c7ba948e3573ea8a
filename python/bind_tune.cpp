// Ceres: tune (`physik tune --report`) and equilibrium (`physik equilibrium`), with the CLI's
// reports (tune/reports.h) and its option checks and messages.
#include <cstdio>

#include <pybind11/stl.h>

#include "physik/model/errors.h"
#include "python/bind_common.h"
#include "tune/reports.h"

namespace physik::python {

namespace {

// "damping,control_k", ["damping", "control_k"] or {"damping": (lo, hi) | None, ...}
tune::TuneOptions tune_options(py::object params, py::object bounds) {
  tune::TuneOptions to;
  std::string names;
  std::vector<std::string> bound_specs;
  const auto add = [&](const std::string& name) { names += (names.empty() ? "" : ",") + name; };
  const auto bound = [&](const std::string& name, py::handle lohi) {
    const auto pair = lohi.cast<std::pair<double, double>>();
    char buf[128];
    std::snprintf(buf, sizeof buf, "=%.17g:%.17g", pair.first, pair.second);
    bound_specs.push_back(name + buf);
  };
  if (py::isinstance<py::str>(params)) {
    names = params.cast<std::string>();
  } else if (py::isinstance<py::dict>(params)) {
    for (const auto& kv : params.cast<py::dict>()) {
      add(py::str(kv.first));
      if (!kv.second.is_none()) bound(py::str(kv.first), kv.second);
    }
  } else {
    for (const std::string& n : params.cast<std::vector<std::string>>()) add(n);
  }
  to.params = tune::parse_tune_params(names, "params");
  if (!bounds.is_none()) {
    for (const auto& kv : bounds.cast<py::dict>()) bound(py::str(kv.first), kv.second);
  }
  for (const std::string& b : bound_specs) tune::apply_bounds(to.params, b, "bounds");
  return to;
}

}  // namespace

void bind_tune(py::module_& m) {
  m.def(
      "_tune",
      [](const Scene& scene_in, py::object params, py::object bounds, const std::string& objective,
         const std::string& measure, int steps, int scan_points, int max_iterations, bool verbose) {
        Scene scene = scene_in;
        tune::TuneOptions to = tune_options(params, bounds);
        to.objective = tune::objective_from_string(objective, "objective");
        to.measure = tune::measure_from_string(measure, "measure");
        if (steps < 0) throw_input_error("steps", "", "", "must not be negative");
        if (steps > 0) scene.steps = steps;
        if (scan_points < 0 || scan_points == 1) {
          throw_input_error("scan_points", "", "", "must be 0 (no scan) or at least 2");
        }
        to.scan_points = scan_points;
        to.max_iterations = std::max(1, max_iterations);
        to.verbose = verbose;
        check_start(scene);
        tune::TuneResult r;
        {
          py::gil_scoped_release release;
          r = tune::tune_scene(scene, to);
        }
        py::dict report = from_json(tune::tune_report_to_json(scene, to, r));
        report["ceres_full"] = r.ceres_full;
        report["tuned_scene"] = py::cast(r.tuned_scene);
        return report;
      },
      py::arg("scene"), py::arg("params"), py::arg("bounds"), py::arg("objective"),
      py::arg("measure"), py::arg("steps"), py::arg("scan_points"), py::arg("max_iterations"),
      py::arg("verbose"), "physik.tune's C++ half.");

  m.def(
      "_equilibrium",
      [](const Scene& scene, const std::string& start, bool compare) {
        tune::check_equilibrium_start(start);
        tune::EquilibriumReport rep;
        {
          py::gil_scoped_release release;
          rep = tune::equilibrium_report(scene, start, compare);
        }
        py::dict doc = from_json(rep.doc);
        return py::make_tuple(doc, pose_arrays(scene.rig, scene.params.locked_axes(),
                                               rep.result.frames, rep.result.pose));
      },
      py::arg("scene"), py::arg("start"), py::arg("compare"), "physik.equilibrium's C++ half.");
}

}  // namespace physik::python
