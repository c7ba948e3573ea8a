// physik._core: the compiled half of `import physik`. Thin bindings of the public
// headers, one file per area; the pure-Python half (python/physik/) adds the exceptions, the
// Pose wrapper, the keyword-friendly functions and the Dask sweeps.
#include "kdl/kdl_solve.h"
#include "physik/model/version.h"
#include "python/bind_common.h"

PYBIND11_MODULE(_core, m) {
  namespace py = pybind11;
  m.doc() = "The PhysIK testbed's C++ core (use the `physik` package, not this module).";
  m.attr("__version__") = physik::kVersion;  // the one definition, as `physik --version`
  physik::python::register_errors(m);
  physik::kdl::register_solvers();  // physik.solve(scene, "kdl" | "kdl-nr")
  physik::python::bind_model(m);
  physik::python::bind_simulation(m);
  physik::python::bind_solve(m);
  physik::python::bind_reference(m);
  physik::python::bind_tune(m);
  physik::python::bind_posing(m);
  physik::python::bind_view(m);
  physik::python::bind_clip(m);
}
