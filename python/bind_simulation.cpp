// Simulation: a scene's run held open, stepped from Python. It composes the engine's public
// pieces exactly as run_scene does (physik/engine/engine.h: init_state, step, RunMonitor,
// fill_final_state), so Simulation(scene).run() gives run_scene's summary, bit for bit.
// The pose is read through numpy views of the SimState's arrays (no copy): the vectors are sized
// once by init_state and never reallocated, and each view keeps the Simulation alive.
// run(record_every=N) keeps `physik simulate --every N`'s trajectory.csv rows as arrays.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "physik/engine/engine.h"
#include "physik/engine/run_monitor.h"
#include "physik/io/summary_io.h"
#include "physik/model/errors.h"
#include "python/bind_common.h"

namespace physik::python {

namespace {

static_assert(sizeof(Vec3) == 3 * sizeof(double), "Vec3 arrays must be packed doubles");
static_assert(sizeof(Quat) == 4 * sizeof(double),
              "Quat arrays must be packed doubles (x, y, z, w)");

// The rows of Simulation.run(record_every=N): trajectory.csv's (physik/io/recorder.h), as
// arrays. A row for the state the run starts from, then step k when k % N == 0 or k is the
// scene's last step (RowRule::kEveryAndLast); a row with a non-finite value is left out, as the
// table leaves it out.
struct TrajectoryRows {
  int every = 0;  // N; 0 = not recording
  std::vector<int> steps, passes;
  std::vector<double> times, kinetic_energy, mismatch, separation;
  std::vector<double> residuals, heads, tails;  // per row: ncontrol, 3 nbone, 3 nbone values
  std::vector<double> res;                      // scratch: one row's residuals

  bool wants(const Scene& scene, int step) const {
    return every > 0 && (step % every == 0 || step == scene.steps);
  }

  void add(const Scene& scene, const SimState& s, const StepStats& st) {
    control_residuals(scene, s, res);
    const auto finite = [](const std::vector<Vec3>& v) {
      for (const Vec3& x : v) {
        if (!x.allFinite()) return false;
      }
      return true;
    };
    bool ok = std::isfinite(s.time) && std::isfinite(st.kinetic_energy) &&
              std::isfinite(st.mismatch) && std::isfinite(st.joint_separation) &&
              finite(s.frames.head_world) && finite(s.frames.tail_world);
    for (double r : res) ok = ok && std::isfinite(r);
    if (!ok) return;
    steps.push_back(s.step);
    passes.push_back(st.iterations());
    times.push_back(s.time);
    kinetic_energy.push_back(st.kinetic_energy);
    mismatch.push_back(st.mismatch);
    separation.push_back(st.joint_separation);
    residuals.insert(residuals.end(), res.begin(), res.end());
    for (int i = 0; i < scene.rig.nbone; ++i) {
      heads.insert(heads.end(), s.frames.head_world[i].data(), s.frames.head_world[i].data() + 3);
      tails.insert(tails.end(), s.frames.tail_world[i].data(), s.frames.tail_world[i].data() + 3);
    }
  }

  // the state a run starts from: no step taken (no passes, no mismatch)
  void add_start(const Scene& scene, const SimState& s) {
    StepStats st;
    st.kinetic_energy = physik::kinetic_energy(scene.rig, s);  // the member hides the function
    st.joint_separation = max_joint_separation(scene.rig, s.frames);
    add(scene, s, st);
  }
};

template <typename T>
py::array_t<T> array_of(const std::vector<T>& v, std::vector<py::ssize_t> shape) {
  py::array_t<T> a(shape);
  std::copy(v.begin(), v.end(), a.mutable_data());
  return a;
}

// The recorded rows as {name: array} (Python's Trajectory namedtuple takes them as keywords).
py::dict trajectory_dict(const Scene& scene, const TrajectoryRows& t) {
  const py::ssize_t rows = static_cast<py::ssize_t>(t.steps.size());
  const py::ssize_t nc = static_cast<py::ssize_t>(scene.control_points.size());
  const py::ssize_t nb = scene.rig.nbone;
  py::dict d;
  d["steps"] = array_of(t.steps, {rows});
  d["times"] = array_of(t.times, {rows});
  d["kinetic_energy"] = array_of(t.kinetic_energy, {rows});
  d["passes"] = array_of(t.passes, {rows});
  d["joint_mismatch"] = array_of(t.mismatch, {rows});
  d["joint_separation"] = array_of(t.separation, {rows});
  d["residuals"] = array_of(t.residuals, {rows, nc});
  d["heads"] = array_of(t.heads, {rows, nb, 3});
  d["tails"] = array_of(t.tails, {rows, nb, 3});
  return d;
}

struct Simulation {
  explicit Simulation(const Scene& s) : scene(s), monitor(scene) {  // the monitor keeps &scene
    check_start(scene);  // before the clock: a check, not the run
    const auto t0 = std::chrono::steady_clock::now();
    init_state(scene, state);
    wall_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    rtol = scene.residual_tol();
    vtol = scene.speed_tol();
    mass = scene.rig.total_mass();
  }

  // One step, observed as run_scene observes it; false once the monitor says stop.
  void advance() {
    last = step(scene, state);
    stopped = monitor.observe(observe_step(scene, state, last));
    // the tuning study's "settled" (experiments/tuning_study.cpp): residuals within tolerance
    // and the rig at rest; a NaN fails both comparisons
    const bool settled =
        last.max_residual <= rtol && std::sqrt(2.0 * last.kinetic_energy / mass) < vtol;
    if (!settled) last_unsettled = state.step;
    if (trajectory.wants(scene, state.step)) trajectory.add(scene, state, last);
  }

  // up to n steps (fewer once the run stops); the GIL is released by the caller
  int advance_n(long n, bool to_scene_steps) {
    const auto t0 = std::chrono::steady_clock::now();
    int taken = 0;
    while (!stopped && (to_scene_steps ? state.step < scene.steps : taken < n)) {
      advance();
      ++taken;
    }
    wall_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return taken;
  }

  RunSummary summary() const {
    RunSummary out = monitor.summary();
    monitor.fill_final(scene, state, out);  // as run_scene: the last finite state on a blow-up
    out.wall_time_s = wall_s;
    return out;
  }

  void raise_if_diverged(bool raise) const {
    if (raise && monitor.diverged()) throw DivergedRun(monitor.summary().divergence_reason);
  }

  Scene scene;
  SimState state;
  RunMonitor monitor;
  StepStats last;
  bool stopped = false;
  double wall_s = 0.0;
  int last_unsettled = 0;
  double rtol = 0.0, vtol = 0.0, mass = 1.0;
  TrajectoryRows trajectory;         // run(record_every=N)'s rows while it runs
  std::vector<Vec3> angles, excess;  // scratch of the pose's joint angles
};

py::dict stats_dict(const StepStats& st) {
  py::dict d;
  d["passes"] = st.passes;
  d["substeps"] = st.substeps;
  d["mismatch"] = st.mismatch;
  d["kinetic_energy"] = st.kinetic_energy;
  d["max_residual"] = st.max_residual;
  d["joint_separation"] = st.joint_separation;
  d["joint_solve_s"] = st.joint_solve_s;
  return d;
}

}  // namespace

void bind_simulation_running(py::class_<Simulation>& cls);
void bind_simulation_views(py::class_<Simulation>& cls);
void bind_simulation_state(py::class_<Simulation>& cls);

void bind_simulation(py::module_& m) {
  m.def(
      "run_scene",
      [](const Scene& scene) {
        check_start(scene);
        RunSummary r;
        {
          py::gil_scoped_release release;
          r = physik::run_scene(scene);
        }
        return from_json(summary_to_json(scene, r));
      },
      py::arg("scene"),
      "physik::run_scene in one C++ call (no Python in the loop): the C++ side of "
      "bench/bench_python.py and a cross-check of Simulation.run(). Returns the summary dict.");
  py::class_<Simulation> cls(m, "Simulation",
                             R"doc(A run of the PhysIK engine on a scene, stepped from Python.

Simulation(scene) copies the scene and puts the rig in its initial pose (step 0). step(n) and
run() advance it; .summary is `physik simulate`'s summary.json as a dict; .pose gives numpy views
of the state (no copy, read-only, valid as long as the Simulation, which they keep alive).
The run stops for good when it diverges, or when it converges and the scene says to stop there
(convergence.stop_when_converged / stop_at_residual_tol); later step() calls take no step.
A Simulation is not thread-safe; step() and run() release the GIL while the engine runs.)doc");
  bind_simulation_running(cls);
  bind_simulation_views(cls);
  bind_simulation_state(cls);
}

// construction, step, run and the summary
void bind_simulation_running(py::class_<Simulation>& cls) {
  cls.def(py::init<const Scene&>(), py::arg("scene"))
      .def(
          "step",
          [](Simulation& s, long n, bool raise_on_divergence) {
            if (n < 0) throw_input_error("step", "", "n", "must not be negative");
            int taken = 0;
            {
              py::gil_scoped_release release;
              taken = s.advance_n(n, false);
            }
            s.raise_if_diverged(raise_on_divergence);
            return taken;
          },
          py::arg("n") = 1, py::arg("raise_on_divergence") = false,
          R"doc(Advance up to n steps; return the number taken (fewer once the run has stopped).

Steps past the scene's step count are allowed (a live simulation). With raise_on_divergence, a
diverged run raises DivergedError (the summary still says why).)doc")
      .def(
          "_run",
          [](Simulation& s, bool raise_on_divergence, long record_every) -> py::object {
            if (record_every < 0) {
              throw_input_error("run", "", "record_every", "must not be negative");
            }
            s.trajectory = TrajectoryRows{};
            s.trajectory.every =
                static_cast<int>(std::min<long>(record_every, std::numeric_limits<int>::max()));
            if (record_every > 0) s.trajectory.add_start(s.scene, s.state);
            {
              py::gil_scoped_release release;
              s.advance_n(0, true);
            }
            const TrajectoryRows rows = std::move(s.trajectory);
            s.trajectory = TrajectoryRows{};  // later step() calls record nothing
            s.raise_if_diverged(raise_on_divergence);
            py::object summary = from_json(summary_to_json(s.scene, s.summary()));
            if (record_every == 0) return summary;
            return py::make_tuple(summary, trajectory_dict(s.scene, rows));
          },
          py::arg("raise_on_divergence"), py::arg("record_every"),
          "Simulation.run's C++ half: the summary, or (summary, trajectory arrays).")
      .def_property_readonly(
          "summary",
          [](const Simulation& s) { return from_json(summary_to_json(s.scene, s.summary())); },
          "The run so far as `physik simulate`'s summary.json (a dict); wall_time_s counts the "
          "time "
          "spent in the constructor, step() and run().");
}

// the pose: numpy views of the state, and its joint angles
void bind_simulation_views(py::class_<Simulation>& cls) {
  cls.def(
         "_views",
         [](py::object self) {
           Simulation& s = self.cast<Simulation&>();
           const py::ssize_t n = s.scene.rig.nbone;
           const BoneFrames& f = s.state.frames;
           return py::make_tuple(
               readonly_view(f.head_world[0].data(), n, 3, sizeof(Vec3), self),
               readonly_view(f.tail_world[0].data(), n, 3, sizeof(Vec3), self),
               readonly_view(f.orient_world[0].coeffs().data(), n, 4, sizeof(Quat), self),
               readonly_view(s.state.pose.bone_local_rotation[0].coeffs().data(), n, 4,
                             sizeof(Quat), self),
               readonly_view(s.state.pose.root_head_world.data(), 3, self));
         },
         "(heads, tails, orientations, local_rotations, root_head) as read-only numpy views.")
      .def(
          "_joint_angles",
          [](Simulation& s) {
            return joint_angle_arrays(s.scene.rig, s.scene.params.locked_axes(), s.state.pose,
                                      s.angles, s.excess);
          },
          "(joint_angles, limit_excess) of the state's pose now, as new (nbone, 3) arrays.");
}

// what the run has reached: its scene, step count, time and the monitor's verdicts
void bind_simulation_state(py::class_<Simulation>& cls) {
  cls.def_property_readonly(
         "scene", [](const Simulation& s) { return s.scene; }, "The scene (a copy).")
      .def_property_readonly(
          "step_count", [](const Simulation& s) { return s.state.step; }, "Steps taken so far.")
      .def_property_readonly(
          "time", [](const Simulation& s) { return s.state.time; }, "Simulated time so far, s.")
      .def_property_readonly(
          "stopped", [](const Simulation& s) { return s.stopped; },
          "True once the run has stopped (diverged, or converged with a stop rule).")
      .def_property_readonly(
          "converged", [](const Simulation& s) { return s.monitor.converged(); },
          "The run monitor's converged flag (physik/engine/run_monitor.h).")
      .def_property_readonly(
          "diverged", [](const Simulation& s) { return s.monitor.diverged(); },
          "True once the run has diverged.")
      .def_property_readonly(
          "steps_to_settle",
          [](const Simulation& s) {
            const int run = s.state.step;
            return s.monitor.diverged() || s.last_unsettled >= run ? -1 : s.last_unsettled + 1;
          },
          R"doc(The tuning study's measure: the first step from which every later step so far had
every control point within residual_tol of its goal and the rig at rest (rms speed below
speed_tol); -1 if the last step was not settled or the run diverged.)doc")
      .def_property_readonly(
          "last_step", [](const Simulation& s) { return stats_dict(s.last); },
          "The last step's StepStats as a dict (passes, kinetic_energy, ...).")
      .def_property_readonly(
          "residuals",
          [](const Simulation& s) {
            std::vector<double> r;
            control_residuals(s.scene, s.state, r);
            return py::array_t<double>(static_cast<py::ssize_t>(r.size()), r.data());
          },
          "Each control point's distance to its goal target now, rig units (a copy).")
      .def_property_readonly(
          "kinetic_energy",
          [](const Simulation& s) { return kinetic_energy(s.scene.rig, s.state); },
          "Kinetic energy now, J.");
}

}  // namespace physik::python
