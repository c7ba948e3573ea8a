#include "python/bind_common.h"

#include <algorithm>
#include <cstdint>

#include "physik/engine/start_contacts.h"
#include "physik/model/errors.h"
#include "physik/model/joint_angles.h"

namespace physik::python {

nlohmann::json to_json(py::handle v, const std::string& what) {
  using nlohmann::json;
  if (v.is_none()) return nullptr;
  if (PyBool_Check(v.ptr())) return v.cast<bool>();  // before int: bool is an int in Python
  if (PyLong_Check(v.ptr())) {
    int overflow = 0;
    const long long x = PyLong_AsLongLongAndOverflow(v.ptr(), &overflow);
    if (overflow == 0) return x;
    if (overflow > 0) {
      const unsigned long long u = PyLong_AsUnsignedLongLong(v.ptr());
      if (!PyErr_Occurred()) return u;
      PyErr_Clear();
    }
    throw py::value_error(what + ": integer out of range");
  }
  if (PyFloat_Check(v.ptr())) return v.cast<double>();
  if (py::isinstance<py::str>(v)) return v.cast<std::string>();
  if (py::isinstance<py::dict>(v)) {
    json out = json::object();
    for (const auto& kv : v.cast<py::dict>()) {
      if (!py::isinstance<py::str>(kv.first)) {
        throw py::type_error(what + ": dictionary keys must be strings, got " +
                             std::string(py::str(py::type::of(kv.first).attr("__name__"))));
      }
      const std::string key = kv.first.cast<std::string>();
      out[key] = to_json(kv.second, what + "." + key);
    }
    return out;
  }
  if (py::isinstance<py::list>(v) || py::isinstance<py::tuple>(v)) {
    json out = json::array();
    std::size_t i = 0;
    for (py::handle item : v) out.push_back(to_json(item, what + "[" + std::to_string(i++) + "]"));
    return out;
  }
  if (py::hasattr(v, "tolist")) return to_json(v.attr("tolist")(), what);  // numpy arrays, scalars
  if (py::hasattr(v, "__index__")) return to_json(v.attr("__index__")(), what);
  if (py::hasattr(v, "__float__")) return to_json(v.attr("__float__")(), what);
  throw py::type_error(what + ": cannot be written as JSON (a " +
                       std::string(py::str(py::type::of(v).attr("__name__"))) + ")");
}

py::object from_json(const nlohmann::json& v) {
  switch (v.type()) {
    case nlohmann::json::value_t::null:
      return py::none();
    case nlohmann::json::value_t::boolean:
      return py::bool_(v.get<bool>());
    case nlohmann::json::value_t::number_integer:
      return py::int_(v.get<long long>());
    case nlohmann::json::value_t::number_unsigned:
      return py::int_(v.get<unsigned long long>());
    case nlohmann::json::value_t::number_float:
      return py::float_(v.get<double>());
    case nlohmann::json::value_t::string:
      return py::str(v.get<std::string>());
    case nlohmann::json::value_t::array: {
      py::list out;
      for (const auto& item : v) out.append(from_json(item));
      return out;
    }
    case nlohmann::json::value_t::object: {
      py::dict out;
      for (auto it = v.begin(); it != v.end(); ++it) out[py::str(it.key())] = from_json(it.value());
      return out;
    }
    default:
      return py::none();  // binary and discarded values do not occur here
  }
}

namespace {

// NumPy's own constructor with the dimensions on the stack: py::array's takes them in vectors,
// which would be C++ allocations on every read of a view (the posing session reads its pose
// each frame). Not writeable from the start; the owner is the array's base, kept alive by it.
py::array view_of(const double* data, int ndim, const Py_intptr_t* dims, const Py_intptr_t* strides,
                  py::handle owner) {
  auto& api = py::detail::npy_api::get();
  py::object a = py::reinterpret_steal<py::object>(
      api.PyArray_NewFromDescr_(api.PyArray_Type_, py::dtype::of<double>().release().ptr(), ndim,
                                const_cast<Py_intptr_t*>(dims), const_cast<Py_intptr_t*>(strides),
                                const_cast<double*>(data), 0, nullptr));
  if (!a) throw py::error_already_set();
  if (api.PyArray_SetBaseObject_(a.ptr(), owner.inc_ref().ptr()) != 0) {
    throw py::error_already_set();
  }
  return py::reinterpret_steal<py::array>(a.release());
}

}  // namespace

py::array readonly_view(const double* data, py::ssize_t rows, py::ssize_t cols,
                        py::ssize_t row_stride, py::handle owner) {
  const Py_intptr_t dims[2] = {rows, cols};
  const Py_intptr_t strides[2] = {row_stride, static_cast<Py_intptr_t>(sizeof(double))};
  return view_of(data, 2, dims, strides, owner);
}

py::array readonly_view(const double* data, py::ssize_t n, py::handle owner) {
  const Py_intptr_t dims[1] = {n};
  const Py_intptr_t strides[1] = {static_cast<Py_intptr_t>(sizeof(double))};
  return view_of(data, 1, dims, strides, owner);
}

namespace {

template <typename T, int N>
py::array_t<double> rows_copy(const std::vector<T>& v, const double* (*at)(const T&)) {
  py::array_t<double> a({static_cast<py::ssize_t>(v.size()), py::ssize_t(N)});
  auto m = a.mutable_unchecked<2>();
  for (std::size_t i = 0; i < v.size(); ++i) {
    for (int k = 0; k < N; ++k) m(i, k) = at(v[i])[k];
  }
  return a;
}

const double* vec_data(const Vec3& v) {
  return v.data();
}
const double* quat_data(const Quat& q) {
  return q.coeffs().data();
}

}  // namespace

py::tuple joint_angle_arrays(const Rig& rig, LockedAxes locked, const Pose& pose,
                             std::vector<Vec3>& angles, std::vector<Vec3>& excess) {
  joint_angles_and_excess(rig, locked, pose, angles, excess);
  return py::make_tuple(rows_copy<Vec3, 3>(angles, vec_data), rows_copy<Vec3, 3>(excess, vec_data));
}

py::dict pose_arrays(const Rig& rig, LockedAxes locked, const BoneFrames& frames,
                     const Pose& pose) {
  py::dict d;
  d["heads"] = rows_copy<Vec3, 3>(frames.head_world, vec_data);
  d["tails"] = rows_copy<Vec3, 3>(frames.tail_world, vec_data);
  d["orientations"] = rows_copy<Quat, 4>(frames.orient_world, quat_data);
  d["local_rotations"] = rows_copy<Quat, 4>(pose.bone_local_rotation, quat_data);
  d["root_head"] = py::array_t<double>(3, pose.root_head_world.data());
  std::vector<Vec3> angles, excess;
  const py::tuple a = joint_angle_arrays(rig, locked, pose, angles, excess);
  d["joint_angles"] = a[0];
  d["limit_excess"] = a[1];
  return d;
}

namespace {

// The CLI names an option by its flag ("--max-dt: must be ..."); Python by its keyword
// ("max_dt: must be ..."). The messages the shared C++ writes for the CLI's flags (physik solve's
// options, tune's) get the keyword in place of a leading flag.
std::string python_wording(const char* what) {
  const std::string m = what;
  if (m.rfind("--", 0) != 0) return m;
  const std::size_t end = std::min(m.find_first_of(": ", 2), m.size());
  std::string name = m.substr(2, end - 2);
  std::replace(name.begin(), name.end(), '-', '_');
  if (name == "lambda") name = "lambda_";  // physik.solve's keyword (lambda is Python's)
  return name + m.substr(end);
}

}  // namespace

void check_start(const Scene& scene) {
  const std::string warning = check_start_contacts(scene);  // InputError past the surface
  if (warning.empty()) return;
  static PyObject* warning_class =
      py::object(py::module_::import("physik.errors").attr("StartContactWarning")).release().ptr();
  const std::string text = scene.file.empty() ? warning : scene.file + ": " + warning;
  if (PyErr_WarnEx(warning_class, text.c_str(), 1) < 0) throw py::error_already_set();
}

void warn_input(const std::vector<std::string>& warnings) {
  if (warnings.empty()) return;
  static PyObject* warning_class =
      py::object(py::module_::import("physik.errors").attr("InputWarning")).release().ptr();
  for (const std::string& w : warnings) {
    if (PyErr_WarnEx(warning_class, w.c_str(), 1) < 0) throw py::error_already_set();
  }
}

void register_errors(py::module_& m) {
  // the classes live in pure Python (physik/errors.py); leaked on purpose: they must outlive
  // every translation, including those during interpreter shutdown
  py::module_ errors = py::module_::import("physik.errors");
  static PyObject* input_error = py::object(errors.attr("InputError")).release().ptr();
  static PyObject* diverged_error = py::object(errors.attr("DivergedError")).release().ptr();
  m.attr("InputError") = py::handle(input_error);
  m.attr("DivergedError") = py::handle(diverged_error);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InputError& e) {
      PyErr_SetString(input_error, python_wording(e.what()).c_str());
    } catch (const DivergedRun& e) {
      PyErr_SetString(diverged_error, e.what());
    }
  });
}

}  // namespace physik::python
