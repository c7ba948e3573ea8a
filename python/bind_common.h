// Shared pieces of the Python bindings: JSON <-> Python conversion, read-only numpy
// views, and the registration functions of each area (one binding file per area).
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include "physik/model/kinematics.h"
#include "physik/model/scene.h"

namespace physik::python {

namespace py = pybind11;

// A Python value (dict, list, tuple, str, int, float, bool, None, numpy scalars and arrays) as
// JSON; `what` names the value in a TypeError for anything else.
nlohmann::json to_json(py::handle value, const std::string& what);
// JSON as plain Python values (dict, list, str, int, float, bool, None).
py::object from_json(const nlohmann::json& value);

// (n, 3) doubles, a new array (a copy of the points)
py::array vec3_array(const std::vector<Vec3>& v);

// A read-only numpy view of `rows` x `cols` doubles at `data`, `row_stride` bytes apart, kept
// alive by `owner` (no copy).
py::array readonly_view(const double* data, py::ssize_t rows, py::ssize_t cols,
                        py::ssize_t row_stride, py::handle owner);
// The same for a 1-d view of n doubles.
py::array readonly_view(const double* data, py::ssize_t n, py::handle owner);

// A pose as numpy copies: {"heads": (n,3), "tails": (n,3), "orientations": (n,4) world<-bone,
// "local_rotations": (n,4) rest-relative in the bone frame, both (x, y, z, w), "root_head": (3,),
// "joint_angles": (n,3), "limit_excess": (n,3) (physik/model/joint_angles.h)}.
// The angles are those of the joint model `locked` (the scene's scheme's,
// EngineParams::locked_axes()).
py::dict pose_arrays(const Rig& rig, LockedAxes locked, const BoneFrames& frames, const Pose& pose);

// (joint_angles, limit_excess) of `pose` as new (nbone, 3) arrays, rad (joint_angles.h),
// computed in the caller's scratch vectors (no C++ allocation once they are sized).
py::tuple joint_angle_arrays(const Rig& rig, LockedAxes locked, const Pose& pose,
                             std::vector<Vec3>& angles, std::vector<Vec3>& excess);

// C++ errors as the package's Python exceptions (physik.errors): InputError, DivergedError.
void register_errors(py::module_& m);

// The start-contact check of `physik simulate` (physik/engine/start_contacts.h) before a run of
// the engine: a rig started through the ground or a box is an InputError; one started into it
// issues physik.errors.StartContactWarning with the CLI's warning text (an error when the
// warnings filter makes it one).
void check_start(const Scene& scene);
// Each of `warnings` (what a reader changed of a value the user gave: physik/io/scene_warnings.h,
// bone_targets.h target_quaternion) issued as physik.errors.InputWarning.
void warn_input(const std::vector<std::string>& warnings);

void bind_model(py::module_& m);       // Rig, Scene
void bind_simulation(py::module_& m);  // Simulation
void bind_solve(py::module_& m);       // solve
void bind_reference(py::module_& m);   // export_mjcf, compare_mujoco
void bind_tune(py::module_& m);        // tune, equilibrium
void bind_posing(py::module_& m);      // PosingSession
void bind_view(py::module_& m);        // view (the page of `physik view`)
void bind_clip(py::module_& m);        // Clip, the write-back, follow scenes
// Rig.from_bvh, rig.source_skeleton, source_notes, root (bind_clip.cpp), called by bind_rig
void bind_rig_source(py::class_<Rig>& cls);
// a {param: value} dict (or a list of "key=value") as `--set` overrides, `source` naming them in
// messages (bind_model.cpp): Scene.load's overrides, follow's params
ParamOverrides param_overrides(const py::object& values, const std::string& source);

}  // namespace physik::python
