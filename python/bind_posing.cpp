// PosingSession: physik::PosingSession (physik/posing/posing_session.h) from Python, as a tool
// embeds it: targets moved once a frame, a few steps of physics, or a solve to a residual rule.
// Like the C++ class, the calls allocate nothing in C++ after construction: set_target reads
// three numbers, set_pose copies into a pose sized once, advance and solve run the session's
// own buffers, and .pose is numpy views of the session's state (sized once by init_state, never
// reallocated; each view keeps the session alive). What the calls return (a dict of the step's
// stats, a namedtuple of the solve's result) are Python objects. Exceptions to the rule are the
// C++ class's own: a classic finish (its IK solver) and set_target under damping auto.
#include <optional>
#include <string>

#include <pybind11/stl.h>

#include "physik/io/json_fields.h"
#include "physik/io/scene_io.h"
#include "physik/io/summary_io.h"
#include "physik/model/bone_targets.h"
#include "physik/model/errors.h"
#include "physik/posing/posing_session.h"
#include "python/bind_common.h"

namespace physik::python {

namespace {

static_assert(sizeof(Vec3) == 3 * sizeof(double), "Vec3 arrays must be packed doubles");
static_assert(sizeof(Quat) == 4 * sizeof(double), "Quat arrays: packed doubles (x, y, z, w)");

Scene session_scene(const Scene& scene, bool solve_mode) {
  Scene s = scene;
  if (solve_mode) use_solve_mode(s.params);  // as `physik solve --solver physik`
  return s;
}

struct Session {
  Session(const Scene& scene, bool solve_mode)
      : session(session_scene(scene, solve_mode)), scratch(session.pose()) {
    check_start(session.scene());
  }

  PosingSession session;
  Pose scratch;      // set_pose's input, sized once
  SolveResult last;  // the last solve's result, for summary()
  bool solved = false;
  std::vector<Vec3> angles, excess;  // scratch of the pose's joint angles
};

// n finite-or-not numbers from any sequence (list, tuple, numpy array) into `out`; no C++
// allocation. `what` names them in the TypeError ("(x, y, z)").
void numbers_arg(py::handle v, int n, const char* method, const char* field, const char* what,
                 double* out) {
  const auto bad = [&] {
    return py::type_error(std::string(method) + "(): " + field + " must be " + std::to_string(n) +
                          " numbers " + what + ", got " + std::string(py::repr(v)));
  };
  if (!PySequence_Check(v.ptr()) || py::isinstance<py::str>(v) || PySequence_Size(v.ptr()) != n) {
    PyErr_Clear();
    throw bad();
  }
  for (int k = 0; k < n; ++k) {
    const py::object item = py::reinterpret_steal<py::object>(PySequence_GetItem(v.ptr(), k));
    if (!item) throw py::error_already_set();
    out[k] = PyFloat_AsDouble(item.ptr());
    if (out[k] == -1.0 && PyErr_Occurred()) {
      PyErr_Clear();
      throw bad();
    }
  }
}

// Three finite-or-not numbers from any sequence; no C++ allocation.
Vec3 vec3_arg(py::handle v, const char* method, const char* field) {
  Vec3 out;
  numbers_arg(v, 3, method, field, "(x, y, z)", out.data());
  return out;
}

// set_pose's input into the session's scratch pose: (nbone, 4) quaternions (x, y, z, w) and the
// root head (3,); a wrong shape is bad input, as the C++ set_pose reports a wrong bone count.
void fill_pose(Session& s, py::handle local_rotations, py::handle root_head) {
  const Rig& rig = s.session.scene().rig;
  using Rows = py::array_t<double, py::array::c_style | py::array::forcecast>;
  const Rows q = Rows::ensure(local_rotations);  // no copy of a C-ordered float64 array
  if (!q) throw py::type_error("set_pose(): local_rotations must be (nbone, 4) numbers");
  if (q.ndim() != 2 || q.shape(1) != 4 || q.shape(0) != rig.nbone) {
    throw_input_error("set_pose", "", "local_rotations",
                      "shape " + std::string(py::str(q.attr("shape"))) + " for a rig of " +
                          std::to_string(rig.nbone) + " bones (expected (" +
                          std::to_string(rig.nbone) + ", 4), quaternions x, y, z, w)");
  }
  const double* d = q.data();
  for (int i = 0; i < rig.nbone; ++i) {
    s.scratch.bone_local_rotation[i] = Quat(d[4 * i + 3], d[4 * i], d[4 * i + 1], d[4 * i + 2]);
  }
  s.scratch.root_head_world = vec3_arg(root_head, "set_pose", "root_head");
  if (!s.scratch.root_head_world.allFinite()) {
    throw_input_error("set_pose", "", "root_head", "not finite");
  }
}

SolveFinish finish_from(const std::string& name) {
  if (name == "none") return SolveFinish::kNone;
  if (name == "ccd") return SolveFinish::kCcd;
  if (name == "dls") return SolveFinish::kDls;
  throw_input_error("solve", "", "finish", "unknown finish '" + name + "' (expected none|ccd|dls)");
}

// The classic finish's options ({"max_iterations", "lambda", "respect_limits", "jacobian"}, as
// physik solve's --max-iterations, --lambda, --no-limits and --jacobian set them).
void finish_options(py::handle options, IkOptions& opt) {
  if (options.is_none()) return;
  const nlohmann::json o = to_json(options, "finish_options");
  const JsonContext ctx{"solve", "finish_options"};
  ctx.require_object(o, "finish_options");
  ctx.only_keys(o, {"max_iterations", "lambda", "respect_limits", "jacobian"});
  opt.max_iterations = ctx.integer_or(o, "max_iterations", opt.max_iterations);
  if (opt.max_iterations < 0) ctx.fail("max_iterations", "must not be negative");
  opt.lambda = ctx.number_or(o, "lambda", opt.lambda);
  if (opt.lambda < 0.0) ctx.fail("lambda", "must not be negative");
  opt.respect_limits = ctx.boolean_or(o, "respect_limits", opt.respect_limits);
  const std::string j = ctx.choice_or(o, "jacobian", {"analytic", "fd"}, "analytic");
  opt.jacobian = j == "fd" ? JacobianKind::kFiniteDifference : JacobianKind::kAnalytic;
}

py::dict step_stats_dict(const StepStats& st) {
  py::dict d;
  d["passes"] = st.passes;
  d["substeps"] = st.substeps;
  d["mismatch"] = st.mismatch;
  d["kinetic_energy"] = st.kinetic_energy;
  d["max_residual"] = st.max_residual;
  d["joint_separation"] = st.joint_separation;
  return d;
}

const SolveRule kDefaultRule{};

const char* method_name(SolveMethod m) {
  return m == SolveMethod::kEquilibrium ? "equilibrium" : "steps";
}

SolveMethod method_from(const std::string& name) {
  if (name == "equilibrium") return SolveMethod::kEquilibrium;
  if (name == "steps") return SolveMethod::kSteps;
  throw_input_error("solve", "", "method",
                    "unknown method '" + name + "' (expected equilibrium|steps)");
}

}  // namespace

void bind_posing_calls(py::class_<Session>& cls);
void bind_posing_targets(py::class_<Session>& cls);
void bind_posing_pins(py::class_<Session>& cls);
void bind_posing_solve(py::class_<Session>& cls, py::object result_type);
void bind_posing_state(py::class_<Session>& cls);

// physik.solve_mode_rule() and physik.steps_mode_rule(): the two solve modes' rules as keywords
void bind_solve_rules(py::module_& m) {
  const auto rule_dict = [](const SolveRule& r) {
    py::dict d;
    d["method"] = method_name(r.method);
    d["tolerance"] = r.tolerance;
    d["tolerance_fraction"] = r.tolerance_fraction;
    d["tolerance_angle"] = r.tolerance_angle;
    d["max_steps"] = r.max_steps;
    d["stall_steps"] = r.stall_steps;
    d["stall_fraction"] = r.stall_fraction;
    d["initial_step"] = r.initial_step;
    d["armature"] = r.armature;
    d["dt_growth"] = r.dt_growth;
    d["max_dt"] = r.max_dt;
    return d;
  };
  m.def(
      "solve_mode_rule", [rule_dict] { return rule_dict(solve_mode_rule()); },
      R"doc(The solve mode's rule (physik::solve_mode_rule) as PosingSession.solve's keywords:
the equilibrium solve (SolveRule's defaults). session.solve(**physik.solve_mode_rule()) is
`physik solve --solver physik`'s solve (which also sets max_steps to --max-iterations).)doc");
  m.def(
      "steps_mode_rule", [rule_dict] { return rule_dict(steps_mode_rule()); },
      R"doc(The time-stepping solve mode's rule (physik::steps_mode_rule) as PosingSession.solve's
keywords: method "steps", the step growing by dt_growth per settling step up to max_dt. With a
session made with solve_mode=True, session.solve(**physik.steps_mode_rule()) is `physik solve
--solver physik-steps`'s solve (which also sets max_steps to the scene's step count).)doc");
}

void bind_posing(py::module_& m) {
  py::object result_type =
      py::module_::import("collections")
          .attr("namedtuple")(
              "PosingSolveResult",
              py::make_tuple("converged", "diverged", "stalled", "out_of_steps", "steps",
                             "finish_iterations", "residual", "final_dt", "tolerance", "method",
                             "stationary", "refused", "tolerance_angle"));
  result_type.attr("__module__") = "physik";
  result_type.attr("__doc__") = R"doc(PosingSession.solve's result (physik::SolveResult).

converged: every goal within its own tolerance at the end (control points within tolerance, rig
units; orientation targets and aims within tolerance_angle, rad); diverged: the physics diverged
(the time-stepping method only; the session is back where the solve started); stalled: no goal
short of its tolerance improved (the stall rule, per goal); out_of_steps: max_steps reached short
of it, still improving; steps: physics steps, or the equilibrium solve's iterations; finish_iterations:
the classic finish's iterations (0 = none ran); residual: the goal residual at the end
(PosingSession.residual), rig units; final_dt: the last step's length (the equilibrium's trust
region's h), s; tolerance: the one used, rig units; method: "equilibrium" or "steps";
stationary: the equilibrium solve ended at a rest pose short of a goal (out of reach, against a
limit); refused: the equilibrium's trials its trust region refused; tolerance_angle: the one
used, rad.)doc";
  m.attr("PosingSolveResult") = result_type;
  bind_solve_rules(m);
  py::class_<Session> cls(m, "PosingSession", R"doc(PhysIK embedded in a tool: a scene held open.

PosingSession(scene, solve_mode=False) copies the scene and puts its initial pose in. Move the
control points' targets with set_target (once a frame, as a user drags), then either advance(k)
steps of the scene's engine (live, with its secondary motion) or solve() the pose: by default the
equilibrium solve (the rest pose as a minimisation of the potential, a trust region of implicit
steps at rest; in the solve mode's engine settings whatever the session's), or with
method="steps" the physics run until every goal is within its tolerance or no goal improves;
then CCD or DLS if finish says so. solve_mode=True gives the scene the solve mode's engine
settings (scheme implicit, torsion_torque gradient), as `physik solve --solver physik`;
physik.steps_mode_rule() gives the time-stepping solve mode's rule (`--solver physik-steps`).

.pose gives read-only numpy views of the session's state (no copy), valid as long as they are
referenced. After construction set_target, set_pose, advance, solve and residual allocate
nothing in C++ (a classic finish, and set_target under damping auto, do, as in C++). Not
thread-safe; advance and solve release the GIL while the engine runs.)doc");
  bind_posing_calls(cls);
  bind_posing_targets(cls);
  bind_posing_pins(cls);
  bind_posing_solve(cls, result_type);
  bind_posing_state(cls);
}

// construction, targets, poses and steps
void bind_posing_calls(py::class_<Session>& cls) {
  cls.def(py::init<const Scene&, bool>(), py::arg("scene"), py::arg("solve_mode") = false)
      .def(
          "set_target",
          [](Session& s, int c, py::object target, bool interpolate) {
            s.session.set_target(c, vec3_arg(target, "set_target", "target"), interpolate);
          },
          py::arg("c"), py::arg("target"), py::arg("interpolate") = false,
          R"doc(Move control point c's target (world, rig units).

interpolate=False jumps (the spring pulls toward the new point at once); True moves it along the
scene's interpolation, as a schedule would. A bad index or a non-finite target raises
InputError.)doc")
      .def(
          "_set_pose",
          [](Session& s, py::object local_rotations, py::object root_head) {
            fill_pose(s, local_rotations, root_head);
            s.session.set_pose(s.scratch);
          },
          py::arg("local_rotations"), py::arg("root_head"),
          "PosingSession.set_pose's C++ half: (nbone, 4) quaternions (x, y, z, w), root head (3,).")
      .def(
          "advance",
          [](Session& s, int steps) {
            if (steps < 0) throw_input_error("advance", "", "steps", "must not be negative");
            StepStats st;
            {
              py::gil_scoped_release release;
              st = s.session.advance(steps);
            }
            return step_stats_dict(st);
          },
          py::arg("steps") = 1,
          R"doc(`steps` steps of the scene's engine (its integration, joint solve and dt); returns
the last step's stats as a dict (passes, mismatch, kinetic_energy, max_residual,
joint_separation). It does not watch for divergence: solve() does.)doc");
}

namespace {

// a bone target's bone by name (InputError naming the method for an unknown one)
int bone_arg(const Session& s, const std::string& bone, const char* method) {
  return target_bone_index(s.session.scene(), bone, {method, ""});
}

}  // namespace

// orientation targets and aims: set (add or replace, one per bone and kind)
void bind_posing_targets(py::class_<Session>& cls) {
  cls.def(
         "set_orientation_target",
         [](Session& s, const std::string& bone, py::object quaternion, std::optional<double> k,
            std::optional<std::string> spring, std::optional<double> cap) {
           const char* m = "set_orientation_target";
           double q[4];
           numbers_arg(quaternion, 4, m, "quaternion", "(w, x, y, z)", q);
           OrientationTarget t;
           t.bone = bone_arg(s, bone, m);
           std::vector<std::string> warnings;
           t.target_world = target_quaternion(q[0], q[1], q[2], q[3], {m, ""}, warnings);
           warn_input(warnings);
           set_turn_spring(spring, k, cap, {m, ""}, t);
           s.session.set_orientation_target(t);
         },
         py::arg("bone"), py::arg("quaternion"), py::kw_only(), py::arg("k") = py::none(),
         py::arg("spring") = py::none(), py::arg("cap") = py::none(),
         R"doc(Turn `bone` toward a target frame: quaternion [w, x, y, z], world<-bone (unit).

As the scene file's "orientation_targets": k (N m/rad), spring ("linear" or "capped") and cap
(rad) default to the params' control spring turned into rotation by the bone's length. Adds the
bone's orientation target or replaces it. A quaternion whose norm is within 1e-3 of 1 is
normalised with an InputWarning; a zero one, one farther from unit or an unknown bone (with a
"did you mean") raises InputError.)doc")
      .def(
          "set_aim_target",
          [](Session& s, const std::string& bone, py::object point, py::object axis,
             std::optional<double> k, std::optional<std::string> spring,
             std::optional<double> cap) {
            const char* m = "set_aim_target";
            AimTarget t;
            t.bone = bone_arg(s, bone, m);
            t.point_world = vec3_arg(point, m, "point");
            t.axis_bone = axis.is_none() ? default_aim_axis(s.session.scene().rig, t.bone)
                                         : vec3_arg(axis, m, "axis");
            set_turn_spring(spring, k, cap, {m, ""}, t);
            s.session.set_aim_target(t);
          },
          py::arg("bone"), py::arg("point"), py::kw_only(), py::arg("axis") = py::none(),
          py::arg("k") = py::none(), py::arg("spring") = py::none(), py::arg("cap") = py::none(),
          R"doc(Turn `bone`'s axis toward `point` (world, rig units) seen from its head.

axis: in the bone's frame (default: the bone's forward axis where the rig's human template gives
it one, the face or a palm; else [0, 1, 0], along the bone); k, spring and cap as
set_orientation_target. Adds the bone's aim or replaces it. A point on the bone's head in the
pose now, a zero axis or an unknown bone raises InputError.)doc");
}

// pins (set: add or replace), every bone target's clear, and the targets read back
void bind_posing_pins(py::class_<Session>& cls) {
  cls.def(
         "set_pin",
         [](Session& s, const std::string& bone, py::object point, double alpha,
            std::optional<double> k) {
           const char* m = "set_pin";
           Pin pin;
           pin.bone = bone_arg(s, bone, m);
           pin.alpha = alpha;
           pin.k = k;
           check_pin(s.session.scene(), pin, {m, ""});  // alpha in range before it is used
           pin.point_world = point.is_none()
                                 ? point_on_bone(s.session.frames(), pin.bone, pin.alpha)
                                 : vec3_arg(point, m, "point");
           s.session.set_pin(pin);
         },
         py::arg("bone"), py::arg("point") = py::none(), py::kw_only(), py::arg("alpha") = 0.0,
         py::arg("k") = py::none(),
         R"doc(Hold the point `alpha` along `bone` (0 = head, 1 = tail) at `point` (world, rig units).

point=None: where that point is in the pose now. k (N/m) defaults to 100 times the params'
control_k. Adds the bone's pin or replaces it. A welded bone (pin the bone it is welded to), an
alpha outside [0, 1], k <= 0 or an unknown bone raises InputError.)doc")
      .def(
          "clear_orientation_target",
          [](Session& s, const std::string& bone) {
            return s.session.clear_orientation_target(
                bone_arg(s, bone, "clear_orientation_target"));
          },
          py::arg("bone"), "Remove `bone`'s orientation target; False when it had none.")
      .def(
          "clear_aim_target",
          [](Session& s, const std::string& bone) {
            return s.session.clear_aim_target(bone_arg(s, bone, "clear_aim_target"));
          },
          py::arg("bone"), "Remove `bone`'s aim target; False when it had none.")
      .def(
          "clear_pin",
          [](Session& s, const std::string& bone) {
            return s.session.clear_pin(bone_arg(s, bone, "clear_pin"));
          },
          py::arg("bone"), "Remove `bone`'s pin; False when it had none.")
      .def_property_readonly(
          "bone_targets",
          [](const Session& s) {
            const nlohmann::json j = scene_to_json(s.session.scene());
            py::dict out;
            for (const char* key : {"orientation_targets", "aim_targets", "pins"}) {
              out[key] = j.contains(key) ? from_json(j[key]) : py::list();
            }
            return out;
          },
          R"doc({"orientation_targets": [...], "aim_targets": [...], "pins": [...]}: the session's
bone targets now, in the scene file's format (a new dict; allocates).)doc");
}

// PosingSession.solve's docstring
constexpr const char* kSolveDoc =
    R"doc(Solve to the rule; the session continues from the result.

The keywords are physik::SolveRule's, with its defaults: method ("equilibrium": the rest pose by
a trust region of implicit steps at rest; "steps": the scene's engine stepping), tolerance (rig
units, the control points'; 0 = tolerance_fraction of the goals' reach), tolerance_angle (rad,
the orientation targets' and aims'; 0 = tolerance over the reach), max_steps (steps, or the
equilibrium's iterations), the stall rule (stopped when no goal short of its tolerance improved
by stall_fraction of itself over stall_steps steps or iterations; 0 = the method's: 50 steps, 6
iterations), initial_step (s, the equilibrium's first trial step), armature (the equilibrium's
joint armature, a fraction of the rig's inertia about its root), dt_growth and max_dt (steps:
the step lengthening by dt_growth each settling step up to max_dt, s; 1 = off; needs scheme
implicit), finish ("none", "ccd" or "dls": the classic solver that closes the rest after a
stall) and finish_options ({"max_iterations", "lambda", "respect_limits", "jacobian"} for the
finish, as physik solve's flags). physik.solve_mode_rule() and physik.steps_mode_rule() give
the two solve modes'. Returns a PosingSolveResult. A rule out of range, or a scene without a
goal, raises InputError.)doc";

// solve, with SolveRule's fields as keywords
void bind_posing_solve(py::class_<Session>& cls, py::object result_type) {
  cls.def(
      "solve",
      [result_type](Session& s, const std::string& method, double tolerance,
                    double tolerance_fraction, double tolerance_angle, int max_steps,
                    int stall_steps, double stall_fraction, double initial_step, double armature,
                    double dt_growth, double max_dt, const std::string& finish,
                    py::object options) {
        SolveRule rule;
        rule.method = method_from(method);
        rule.tolerance = tolerance;
        rule.tolerance_fraction = tolerance_fraction;
        rule.tolerance_angle = tolerance_angle;
        rule.initial_step = initial_step;
        rule.armature = armature;
        rule.max_steps = max_steps;
        rule.stall_steps = stall_steps;
        rule.stall_fraction = stall_fraction;
        rule.dt_growth = dt_growth;
        rule.max_dt = max_dt;
        rule.finish = finish_from(finish);
        if (rule.finish == SolveFinish::kNone && !options.is_none()) {  // never unused
          throw_input_error("solve", "", "finish_options", "given without a finish (ccd or dls)");
        }
        finish_options(options, rule.finish_options);
        {
          py::gil_scoped_release release;
          s.last = s.session.solve(rule);
        }
        s.solved = true;
        const SolveResult& r = s.last;
        return result_type(r.converged, r.diverged, r.stalled, r.out_of_steps, r.steps,
                           r.finish_iterations, r.residual, r.final_dt, r.tolerance,
                           method_name(r.method), r.stationary, r.refused, r.tolerance_angle);
      },
      py::kw_only(), py::arg("method") = method_name(kDefaultRule.method),
      py::arg("tolerance") = kDefaultRule.tolerance,
      py::arg("tolerance_fraction") = kDefaultRule.tolerance_fraction,
      py::arg("tolerance_angle") = kDefaultRule.tolerance_angle,
      py::arg("max_steps") = kDefaultRule.max_steps,
      py::arg("stall_steps") = kDefaultRule.stall_steps,
      py::arg("stall_fraction") = kDefaultRule.stall_fraction,
      py::arg("initial_step") = kDefaultRule.initial_step,
      py::arg("armature") = kDefaultRule.armature, py::arg("dt_growth") = kDefaultRule.dt_growth,
      py::arg("max_dt") = kDefaultRule.max_dt, py::arg("finish") = "none",
      py::arg("finish_options") = py::none(), kSolveDoc);
}

// what the session holds: its pose as views, the residual, the last solve's summary
void bind_posing_state(py::class_<Session>& cls) {
  cls.def(
         "residual", [](const Session& s) { return s.session.residual(); },
         "Largest distance of any control point from its target now, or arc of an orientation "
         "target or aim (its turn times its bone's length), rig units (solve() judges each goal "
         "by its own measure: rig units or rad).")
      .def_property_readonly(
          "num_control_points", [](const Session& s) { return s.session.num_control_points(); },
          "Number of control points.")
      .def_property_readonly(
          "scene", [](const Session& s) { return s.session.scene(); },
          "The session's scene (a copy; with solve_mode, its engine settings).")
      .def_property_readonly(
          "step_count", [](const Session& s) { return s.session.state().step; },
          "Steps taken so far.")
      .def_property_readonly(
          "time", [](const Session& s) { return s.session.state().time; },
          "Simulated time so far, s.")
      .def_property_readonly(
          "targets",
          [](py::object self) {
            const Session& s = self.cast<const Session&>();
            const auto& t = s.session.state().target_goal_world;
            static const double kNone[3] = {0.0, 0.0, 0.0};  // a 0-row view needs some address
            return readonly_view(t.empty() ? kNone : t[0].data(),
                                 static_cast<py::ssize_t>(t.size()), 3, sizeof(Vec3), self);
          },
          "(ncontrol, 3) the control points' goal targets, world, rig units (a read-only view).")
      .def(
          "summary",
          [](const Session& s) {
            if (!s.solved) throw_input_error("summary", "", "", "no solve yet");
            return from_json(summary_to_json(s.session.scene(), s.session.summary(s.last)));
          },
          R"doc(The last solve's summary as `physik simulate`'s summary.json (a dict; allocates):
its steps, energy ledger, limit violation and final_state_hash of the session's state.)doc")
      .def(
          "_views",
          [](py::object self) {
            const Session& s = self.cast<const Session&>();
            const py::ssize_t n = s.session.scene().rig.nbone;
            const BoneFrames& f = s.session.frames();
            const Pose& p = s.session.pose();
            return py::make_tuple(
                readonly_view(f.head_world[0].data(), n, 3, sizeof(Vec3), self),
                readonly_view(f.tail_world[0].data(), n, 3, sizeof(Vec3), self),
                readonly_view(f.orient_world[0].coeffs().data(), n, 4, sizeof(Quat), self),
                readonly_view(p.bone_local_rotation[0].coeffs().data(), n, 4, sizeof(Quat), self),
                readonly_view(p.root_head_world.data(), 3, self));
          },
          "(heads, tails, orientations, local_rotations, root_head) as read-only numpy views.")
      .def(
          "_joint_angles",
          [](Session& s) {
            return joint_angle_arrays(s.session.scene().rig, s.session.scene().params.locked_axes(),
                                      s.session.pose(), s.angles, s.excess);
          },
          "(joint_angles, limit_excess) of the session's pose now, as new (nbone, 3) arrays.");
}

}  // namespace physik::python
