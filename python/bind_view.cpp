// The viewer: physik.view() writes `physik view`'s page (viewer/view_page.h) from run folders.
#include <pybind11/stl.h>

#include "python/bind_common.h"
#include "viewer/view_page.h"

namespace physik::python {

void bind_view(py::module_& m) {
  m.def(
      "_view",
      [](const std::vector<std::string>& folders, const std::string& out, const std::string& title,
         const std::vector<std::string>& labels, int max_frames) {
        viewer::ViewOptions o;
        o.title = title;
        o.labels = labels;
        o.max_frames = max_frames;
        py::gil_scoped_release release;
        return viewer::write_view_page(folders, o, out);
      },
      py::arg("folders"), py::arg("out"), py::arg("title"), py::arg("labels"),
      py::arg("max_frames"), "physik.view's page (use physik.view).");
}

}  // namespace physik::python
