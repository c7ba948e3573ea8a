// solve: `physik solve` (physik/io/scene_solve.h), the classic IK solvers and the engine.
#include <pybind11/stl.h>

#include "physik/io/scene_solve.h"
#include "physik/model/errors.h"
#include "python/bind_common.h"

namespace physik::python {

void bind_solve(py::module_& m) {
  m.attr("_SOLVE_DT_GROWTH") = kSolveDtGrowth;
  m.attr("_SOLVE_MAX_DT") = kSolveMaxDt;
  m.def(
      "_solve",
      [](const Scene& scene, const std::string& solver, double tol, int max_iterations,
         double lambda, const std::string& jacobian, std::vector<double> gravity,
         double rotation_damping, const std::string& socket, const std::string& cone,
         bool no_limits, double dt_growth, double max_dt, const std::string& finish,
         bool raise_on_divergence) {
        SceneSolveOptions o;
        o.solver = solver;
        o.tol = tol;
        o.max_iterations = max_iterations;
        o.lambda = lambda;
        o.jacobian = jacobian;
        o.gravity = std::move(gravity);
        o.rotation_damping = rotation_damping;
        o.socket = socket;
        o.cone = cone;
        o.no_limits = no_limits;
        o.dt_growth = dt_growth;
        o.max_dt = max_dt;
        o.finish = finish;
        SceneSolveResult r;
        {
          py::gil_scoped_release release;
          r = solve_scene(scene, o);
        }
        if (raise_on_divergence && r.diverged) {
          throw DivergedRun(r.summary.value("divergence_reason", std::string("diverged")));
        }
        return py::make_tuple(from_json(r.summary), pose_arrays(scene.rig, r.frames, r.pose));
      },
      py::arg("scene"), py::arg("solver"), py::arg("tol"), py::arg("max_iterations"),
      py::arg("lambda_"), py::arg("jacobian"), py::arg("gravity"), py::arg("rotation_damping"),
      py::arg("socket"), py::arg("cone"), py::arg("no_limits"), py::arg("dt_growth"),
      py::arg("max_dt"), py::arg("finish"), py::arg("raise_on_divergence"),
      "physik.solve's C++ half: (summary dict, pose arrays).");
}

}  // namespace physik::python
