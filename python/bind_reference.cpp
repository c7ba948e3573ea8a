// The MuJoCo reference: export_mjcf (`physik export-mjcf`) and compare_mujoco
// (`physik simulate --reference`'s comparison.json).
#include "physik/model/errors.h"
#include "python/bind_common.h"
#include "reference/compare.h"
#include "reference/mjcf_export.h"

namespace physik::python {

void bind_reference(py::module_& m) {
  m.def(
      "export_mjcf",
      [](const Rig& rig, const std::string& joints, double dt) {
        check_mjcf_timestep(dt, "dt");
        if (joints != "rig" && joints != "hinge" && joints != "ball") {
          throw_input_error("joints", "", "",
                            "unknown value '" + joints + "' (expected rig|hinge|ball)");
        }
        MjcfOptions o;
        o.joints = joints == "ball"    ? JointModel::kBallJoints
                   : joints == "hinge" ? JointModel::kHingeJoints
                                       : JointModel::kRigJoints;
        o.dt = dt;
        py::gil_scoped_release release;
        std::string xml = rig_to_mjcf(rig, o);
        compile_mjcf(xml);  // throws with MuJoCo's message if it does not load
        return xml;
      },
      py::arg("rig"), py::arg("joints") = "rig", py::arg("dt") = 0.05,
      R"doc(The rig as MuJoCo MJCF text, compiled by MuJoCo first (`physik export-mjcf`).

joints: "rig" (joint types and limits from the rig: the exact-constraints model), "hinge" (the
exact and implicit schemes' joints, a hinge or two where the rig locks axes, no limits: their
same-forces model) or "ball" (a ball at every bone, no limits: the gauss-seidel scheme's
same-forces model); dt: the model's time step, s.)doc");

  m.def(
      "compare_mujoco",
      [](const Scene& scene, const std::string& mode) {
        const bool short_name = mode == "same-forces" || mode == "exact-constraints";
        const std::string spec = short_name ? "mujoco:" + mode : mode;
        const ReferenceMode rm = parse_reference_spec(spec, "mode");
        nlohmann::json doc;
        {
          py::gil_scoped_release release;
          doc = comparison_to_json(scene, compare_with_mujoco(scene, rm));
        }
        return from_json(doc);
      },
      py::arg("scene"), py::arg("mode") = "same-forces",
      R"doc(PhysIK against MuJoCo on the scene, from the same initial pose: comparison.json of
`physik simulate SCENE --reference mujoco:MODE` as a dict.

mode: "same-forces" (MuJoCo under PhysIK's control, torsion and damping forces, the scheme's
joints: balls for gauss-seidel, hinges where the rig locks axes for exact and implicit) or
"exact-constraints" (the rig's joints and limits); "mujoco:..." is accepted too.)doc");
}

}  // namespace physik::python
