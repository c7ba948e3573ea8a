// Outside rigs: the engine's default on rigs from outside the project, as a new user meets it.
// MuJoCo's sample models (Debian's libmujoco-samples) become rigs through the MJCF importer
// (reference/mjcf_import.h, as `physik rig from-mjcf`); each rig gets two scenes that name no
// settings (no "params" object, so the engine's default preset, whatever it is when this runs):
// one control point, and two. Each scene runs under four configurations:
//   default                  no overrides
//   original                 --set preset=original (the paper's explicit scheme, c = 3)
//   implicit-auto-axes       original + scheme implicit + damping auto + the paper's
//                            torsion torque (k x excess about each rest axis)
//   implicit-auto-gradient   the same with the torsion potential's exact gradient
// and ends converged (at rest, the run monitor's rule), not converged (still moving at the step
// cap), diverged, or refused (the scene or run rejected as input;
// a refusal counts as a failure). The targets follow one fixed rule, outside_rigs.h.
// Models that are the same rig up to names and a translation (MuJoCo ships one humanoid in six
// files) count once; the others are listed as skipped with the rig they repeat.
//
// The rig's own body, on every converted model, on arm26 with its root made free (as
// converted before anchored roots) and on a motion-capture skeleton written here
// (experiments/mocap_bvh.h, converted as `rig from-bvh --scale 0.01`):
//   weld turn    rad, max over every step of the default runs of its two scenes and of their
//                solves (the solve mode, as `solve --solver physik`) of the turn of a welded bone
//                in its weld's frame, angle(R_w q_rest, R_i) (experiments/weld_turn.h); rigid: at
//                most 1e-9
//   root drift   rig units, max over the same steps of |head_root - head_root^rest|
//   rest         J, max kinetic energy over 100 steps from rest, no control point, no gravity,
//                self_collision on, under gauss-seidel, exact and implicit (experiments/at_rest.h):
//                every force is then a sum of exact zeros, so 0
//   overlaps     capsule pairs overlapping at rest (physik/engine/bone_overlaps.h) not excluded
//   rigs/*.json, scenes/*.json   the converted rigs and the scenes (`physik simulate` runs them)
//   bvh/mocap.bvh                the skeleton's file
//   runs.csv                     one row per rig x scene x configuration (with its weld turn and
//                                root drift)
//   checks.csv                   one row per checked rig (the body's measures above)
//   summary.json                 counts per configuration, the skipped files, the report
#include "experiments/outside_rigs.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "experiments/at_rest.h"
#include "experiments/columns.h"
#include "experiments/common.h"
#include "experiments/mocap_bvh.h"
#include "experiments/weld_turn.h"
#include "physik/engine/bone_overlaps.h"
#include "physik/engine/engine.h"
#include "physik/io/bvh.h"
#include "physik/io/rig_io.h"
#include "physik/io/scene_io.h"
#include "physik/model/errors.h"
#include "physik/posing/scene_solve.h"
#include "reference/mjcf_import.h"

namespace physik::experiments::outside_rigs {

double rig_size(const Rig& rig) {
  Vec3 lo = rig.bone_rest_head_world[0], hi = lo;
  for (int b = 0; b < rig.nbone; ++b) {
    for (const Vec3& p : {rig.bone_rest_head_world[b], rig.bone_rest_tail_world[b]}) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
  }
  return (hi - lo).maxCoeff();
}

namespace {

// the leaf whose rest tail is farthest from `from`, other than `except`; -1 if there is none
int farthest_leaf(const Rig& rig, const Vec3& from, int except) {
  int best = -1;
  double best_d = -1.0;
  for (int b = 0; b < rig.nbone; ++b) {
    if (!rig.bone_children[b].empty() || b == except) continue;
    const double d = (rig.bone_rest_tail_world[b] - from).norm();
    if (d > best_d) {  // strict: ties go to the first in depth-first order
      best = b;
      best_d = d;
    }
  }
  return best;
}

}  // namespace

std::vector<Pick> pick_targets(const Rig& rig, int points) {
  if (points < 1 || points > 2) throw std::logic_error("pick_targets: 1 or 2 points");
  const double move = kTargetFraction * rig_size(rig);
  const int first = farthest_leaf(rig, rig.bone_rest_head_world[0], -1);
  std::vector<Pick> picks = {
      {first, 1.0, rig.bone_rest_tail_world[first] + move * kFirstDirection}};
  if (points == 1) return picks;
  const int second = farthest_leaf(rig, rig.bone_rest_tail_world[first], first);
  if (second < 0) {
    picks.push_back({0, 0.0, rig.bone_rest_head_world[0]});  // one leaf: pin the root's head
  } else {
    picks.push_back({second, 1.0, rig.bone_rest_tail_world[second] + move * kSecondDirection});
  }
  return picks;
}

nlohmann::json scene_json(const std::string& rig_path, const Rig& rig,
                          const std::vector<Pick>& picks, int steps) {
  nlohmann::json points = nlohmann::json::array();
  for (const Pick& p : picks) {
    const Vec3& t = p.target_world;
    points.push_back({{"name", rig.bone_name[p.bone] + (p.alpha == 0.0 ? " head" : " tail")},
                      {"bone", rig.bone_name[p.bone]},
                      {"alpha", p.alpha},
                      {"target", {t.x(), t.y(), t.z()}}});
  }
  return {{"name", rig.name + ", " + std::to_string(picks.size()) + " control point(s)"},
          {"comment", "outside_rigs: no params, so the engine's default preset"},
          {"rig", rig_path},
          {"control_points", points},
          {"steps", steps},
          {"convergence", {{"stop_when_converged", true}}}};
}

const std::vector<Configuration>& configurations() {
  static const std::vector<Configuration> list = {
      {"default", {}},
      {"original", {"preset=original"}},
      {"implicit-auto-axes",
       {"preset=original", "scheme=implicit", "damping=auto", "torsion_torque=axes"}},
      {"implicit-auto-gradient",
       {"preset=original", "scheme=implicit", "damping=auto", "torsion_torque=gradient"}}};
  return list;
}

const char* to_string(Outcome o) {
  switch (o) {
    case Outcome::kConverged:
      return "converged";
    case Outcome::kNotConverged:
      return "not_converged";
    case Outcome::kDiverged:
      return "diverged";
    case Outcome::kRefused:
      return "refused";
  }
  return "?";
}

void BodyMeasure::observe(const Rig& rig, const BoneFrames& frames) {
  const double weld = max_weld_turn(rig, frames);
  const double root = max_weld_turn(rig, frames, rig.bone_body[rig.root()]);
  const double drift =
      (frames.head_world[rig.root()] - rig.bone_rest_head_world[rig.root()]).norm();
  if (!std::isfinite(weld) || !std::isfinite(root) || !std::isfinite(drift)) return;
  weld_turn = std::max(weld_turn, weld);
  root_turn = std::max(root_turn, root);
  root_drift = std::max(root_drift, drift);
}

void BodyMeasure::add(const BodyMeasure& other) {
  weld_turn = std::max(weld_turn, other.weld_turn);
  root_turn = std::max(root_turn, other.root_turn);
  root_drift = std::max(root_drift, other.root_drift);
}

RunResult run_configuration(const std::string& scene_path, const Configuration& config) {
  RunResult r;
  const auto start = std::chrono::steady_clock::now();
  try {
    const Scene scene = load_scene(scene_path, parse_param_overrides(config.sets, "--set"));
    r.preset = scene.params.preset;
    const RunSummary s = run_scene(
        scene, [&](const SimState& st, const StepStats&) { r.body.observe(scene.rig, st.frames); });
    r.outcome = s.diverged    ? Outcome::kDiverged
                : s.converged ? Outcome::kConverged
                              : Outcome::kNotConverged;
    r.steps_to_converge = s.converged ? s.steps_to_converge : -1;
    r.steps_run = s.steps_run;
    for (double x : s.final_residuals) r.max_residual = std::max(r.max_residual, x);
    r.damping = scene.params.damping_auto ? s.damping_auto_value : scene.params.damping;
  } catch (const InputError& e) {
    r = RunResult{};
    r.refusal = e.what();
  }
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

RunResult solve_configuration(const std::string& scene_path) {
  RunResult r;
  const auto start = std::chrono::steady_clock::now();
  try {
    const Scene scene = load_scene(scene_path);
    r.preset = scene.params.preset;
    SceneSolveOptions options;
    options.solver = "physik";
    const SceneSolveResult s = solve_scene(
        scene, options, OptionSpelling::kFlag,
        [&](const SimState& st, const StepStats&) { r.body.observe(scene.rig, st.frames); });
    r.outcome = s.diverged          ? Outcome::kDiverged
                : s.solve.converged ? Outcome::kConverged
                                    : Outcome::kNotConverged;
    r.steps_to_converge = s.solve.converged ? s.solve.steps : -1;
    r.steps_run = s.solve.steps;
    r.max_residual = s.solve.residual;
    r.damping = s.scene.params.damping_auto ? s.run.damping_auto_value : s.scene.params.damping;
  } catch (const InputError& e) {
    r = RunResult{};
    r.refusal = e.what();
  }
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

namespace {

bool close(double a, double b) {
  return std::abs(a - b) <= 1e-9 * (1.0 + std::abs(a) + std::abs(b));
}
template <class V>
bool close_all(const V& a, const V& b) {
  for (int k = 0; k < a.size(); ++k) {
    if (!close(a[k], b[k])) return false;
  }
  return true;
}

bool same_bone(const Rig& a, const Rig& b, int i) {
  const Quat &qa = a.bone_rest_orient_world[i], &qb = b.bone_rest_orient_world[i];
  bool same = a.bone_parent[i] == b.bone_parent[i] &&
              close_all(a.bone_head_in_parent[i], b.bone_head_in_parent[i]) &&
              qa.angularDistance(qb) <= 1e-9 &&  // q and -q: the same rotation
              close(a.bone_length[i], b.bone_length[i]) && close(a.bone_mass[i], b.bone_mass[i]) &&
              close(a.bone_radius[i], b.bone_radius[i]) &&
              close_all(a.bone_inertia_local[i], b.bone_inertia_local[i]);
  for (int k = 0; k < 3 && same; ++k) {
    const AxisLimit &la = a.bone_limit[i][k], &lb = b.bone_limit[i][k];
    same = la.limited == lb.limited && close(la.min, lb.min) && close(la.max, lb.max);
  }
  return same;
}

// "<folder>-<stem>" of a model file
std::string rig_name(const std::string& file) {
  const std::filesystem::path p(file);
  return p.parent_path().filename().string() + "-" + p.stem().string();
}

}  // namespace

bool same_rig(const Rig& a, const Rig& b) {
  if (a.nbone != b.nbone) return false;
  for (int i = 0; i < a.nbone; ++i) {
    if (!same_bone(a, b, i)) return false;
  }
  return true;
}

std::vector<std::string> sample_files(const std::string& dir) {
  namespace fs = std::filesystem;
  if (!fs::is_directory(dir)) {
    throw std::runtime_error("outside_rigs: " + dir +
                             ": no such folder (Debian's "
                             "libmujoco-samples puts MuJoCo's sample models there)");
  }
  std::vector<std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    if (e.is_regular_file() && e.path().extension() == ".xml") files.push_back(e.path().string());
  }
  std::sort(files.begin(), files.end());
  return files;
}

Collection collect_rigs(const std::vector<std::string>& files) {
  Collection out;
  for (const std::string& f : files) {
    Rig rig;
    try {
      rig = load_mjcf(f).rig();
    } catch (const InputError& e) {
      out.skipped.push_back({f, e.what()});
      continue;
    }
    const auto dup = std::find_if(out.rigs.begin(), out.rigs.end(),
                                  [&](const OutsideRig& r) { return same_rig(r.rig, rig); });
    if (dup != out.rigs.end()) {
      out.skipped.push_back(
          {f, "the same rig as " + dup->name + " (up to bone names and a translation)"});
    } else {
      out.rigs.push_back({rig_name(f), f, rig});
    }
  }
  return out;
}

Rig with_free_root(const Rig& rig) {
  nlohmann::json doc = rig_to_json(rig);
  doc.erase("root");
  for (nlohmann::json& b : doc["bones"]) {
    if (b["parent"].is_null()) b.erase("limits_deg");
  }
  return rig_from_json(doc, rig.name + " (root made free)");
}

RigChecks check_rig(const std::string& name, const std::string& source, const Rig& rig) {
  RigChecks c;
  c.name = name;
  c.source = source;
  c.rig = &rig;
  for (int i = 0; i < rig.nbone; ++i) {
    c.bodies += rig.body_nbone[i] > 0;
    c.welded += rig.welded(i);
  }
  c.rest_ke_gauss_seidel = rest_kinetic_energy(rig, RestScheme::kGaussSeidel, true, kRestSteps);
  c.rest_ke_exact = rest_kinetic_energy(rig, RestScheme::kExact, true, kRestSteps);
  c.rest_ke_implicit = rest_kinetic_energy(rig, RestScheme::kImplicit, true, kRestSteps);
  for (const BoneOverlap& o : rest_overlaps(rig)) {
    ++c.rest_overlaps;
    c.open_overlaps += !o.excluded;
  }
  const auto [rmin, rmax] = std::minmax_element(rig.bone_radius.begin(), rig.bone_radius.end());
  c.radius_min = *rmin;
  c.radius_max = *rmax;
  const auto [cmin, cmax] =
      std::minmax_element(rig.bone_collision_radius.begin(), rig.bone_collision_radius.end());
  c.collision_radius_min = *cmin;
  c.collision_radius_max = *cmax;
  return c;
}

MocapRig convert_mocap(const std::string& path) {
  std::filesystem::create_directories(std::filesystem::path(path).parent_path());
  std::ofstream(path) << mocap_bvh();
  BvhImportOptions options;  // Y up, as the file is
  options.scale = 0.01;      // centimetres
  const BvhAnimation anim = load_bvh(path, options);
  MocapRig m{anim.rig(), {}, true};
  const int root_node = anim.pivots.bone_node[m.rig.root()];
  for (int b = 0; b < m.rig.nbone; ++b) {
    if (anim.pivots.bone_node[b] != root_node) continue;
    m.pelvis.push_back(b);
    m.pelvis_one_body = m.pelvis_one_body && m.rig.bone_body[b] == m.rig.bone_body[m.pelvis[0]];
  }
  return m;
}

}  // namespace physik::experiments::outside_rigs

namespace physik::experiments {

namespace {

using namespace outside_rigs;

// one scene (a rig and its 1 or 2 control points) and its runs, one per configuration in
// configurations() order
struct SceneRuns {
  const OutsideRig* rig = nullptr;
  int points = 0;
  double size = 0.0;  // rig units, rig_size
  std::string path;   // the scene file
  std::vector<RunResult> runs;
};

// runs.csv: one row per rig x scene x configuration; numbers as JSON writes them, an empty
// cell where a refused run has none
Table runs_table(const std::vector<SceneRuns>& scenes) {
  const auto number = [](std::string name, std::string unit, std::string doc) {
    return real(std::move(name), std::move(unit), std::move(doc)).as_json_number();
  };
  Table t("runs", "runs.csv",
          {text("rig", "the rig (its MuJoCo sample model's name)"), integer("bones", "", "bones"),
           integer("points", "", "control points of the scene: 1 or 2"),
           text("configuration", "the settings the scene ran under"),
           text("preset", "the preset the run used"),
           text("outcome", "converged, not_converged, diverged or refused"),
           columns::kStepsToConverge, columns::kStepsRun,
           number("residual_over_size", "", "the largest final residual over the rig's size"),
           number("damping", "N s/m", "the damping the run used (damping auto's value)"),
           number("wall_s", "s", "the run's wall time"),
           number("weld_turn", "rad",
                  "the largest turn of a welded bone against its rest frame in its weld's frame, "
                  "over every step"),
           number("root_drift", "rig units",
                  "the largest distance of the root's head from its rest position, over every "
                  "step")});
  for (const SceneRuns& s : scenes) {
    for (std::size_t c = 0; c < s.runs.size(); ++c) {
      const RunResult& r = s.runs[c];
      const bool ran = r.outcome != Outcome::kRefused;
      t.add({s.rig->name, s.rig->rig.nbone, s.points, configurations()[c].name, r.preset,
             to_string(r.outcome), r.steps_to_converge, r.steps_run,
             ran ? Cell(r.max_residual / s.size) : Cell(), ran ? Cell(r.damping) : Cell(), r.wall_s,
             ran ? Cell(r.body.weld_turn) : Cell(), ran ? Cell(r.body.root_drift) : Cell()});
    }
  }
  return t;
}

// checks.csv's columns
std::vector<Column> checks_columns() {
  const auto number = [](std::string name, std::string unit, std::string doc) {
    return real(std::move(name), std::move(unit), std::move(doc)).as_json_number();
  };
  const std::string steps = std::to_string(kRestSteps);
  return {text("rig", "the rig"),
          text("source",
               "mjcf (a sample model), mjcf-free-root (arm26 with its root made "
               "free, as converted before anchored roots) or bvh (the experiment's "
               "own motion-capture skeleton, rig from-bvh --scale 0.01)"),
          integer("bones", "", "bones"),
          integer("bodies", "", "rigid bodies"),
          integer("welded", "", "welded bones"),
          text("root", "the root's joint to the world"),
          number("run_weld_turn", "rad",
                 "the largest turn inside a welded group over every step of the default "
                 "configuration's runs (simulate)"),
          number("solve_weld_turn", "rad",
                 "the same over every step of the solves (solve --solver physik)"),
          number("run_root_turn", "rad", "the run's turn inside the root's body"),
          number("solve_root_turn", "rad", "the solve's turn inside the root's body"),
          number("run_root_drift", "rig units",
                 "the largest distance of the root's head from rest in the runs"),
          number("solve_root_drift", "rig units", "the same in the solves"),
          integer("runs", "", "runs measured (not refused)"),
          integer("runs_converged", "", "runs that converged"),
          integer("solves", "", "solves measured (not refused)"),
          integer("solves_converged", "", "solves that converged"),
          number("rest_ke_gauss_seidel", "J",
                 "the largest kinetic energy over " + steps +
                     " steps at rest, no targets, no gravity, self_collision on: preset "
                     "original"),
          number("rest_ke_exact", "J", "the same, preset original with scheme exact"),
          number("rest_ke_implicit", "J", "the same, preset robust (implicit)"),
          integer("rest_overlaps", "", "bone pairs whose capsules overlap at rest"),
          integer("open_overlaps", "", "those not excluded (collision_exclude)"),
          number("radius_min", "rig units", "the smallest bone radius (inertia)"),
          number("radius_max", "rig units", "the largest bone radius"),
          number("collision_radius_min", "rig units", "the smallest collision radius"),
          number("collision_radius_max", "rig units", "the largest collision radius")};
}

// checks.csv: one row per checked rig (every converted sample model, arm26 with its root made
// free, the experiment's own BVH skeleton)
Table checks_table(const std::vector<RigChecks>& checks) {
  Table t("checks", "checks.csv", checks_columns());
  for (const RigChecks& c : checks) {
    t.add({c.name,
           c.source,
           c.rig->nbone,
           c.bodies,
           c.welded,
           to_string(c.rig->root_joint),
           c.run.weld_turn,
           c.solve.weld_turn,
           c.run.root_turn,
           c.solve.root_turn,
           c.run.root_drift,
           c.solve.root_drift,
           c.runs,
           c.runs_converged,
           c.solves,
           c.solves_converged,
           c.rest_ke_gauss_seidel,
           c.rest_ke_exact,
           c.rest_ke_implicit,
           c.rest_overlaps,
           c.open_overlaps,
           c.radius_min,
           c.radius_max,
           c.collision_radius_min,
           c.collision_radius_max});
  }
  return t;
}

// writes the rig and its two scenes (1 and 2 control points) under ctx.out_dir; their paths
std::vector<std::string> write_rig(const Context& ctx, const OutsideRig& r, int steps) {
  const std::string rig_file = "rigs/" + r.name + ".json";
  write_json(rig_to_json(r.rig), ctx.out_dir + "/" + rig_file);
  std::vector<std::string> paths;
  for (int points : {1, 2}) {
    paths.push_back(ctx.out_dir + "/scenes/" + r.name + "-" + std::to_string(points) + "pt.json");
    write_json(scene_json("../" + rig_file, r.rig, pick_targets(r.rig, points), steps),
               paths.back());
  }
  return paths;
}

// writes the rig and its two scenes under ctx.out_dir, and runs every configuration
std::vector<SceneRuns> run_rig(const Context& ctx, const OutsideRig& r, int steps) {
  std::vector<SceneRuns> out;
  const std::vector<std::string> paths = write_rig(ctx, r, steps);
  for (int points : {1, 2}) {
    SceneRuns s{&r, points, rig_size(r.rig), paths[points - 1], {}};
    for (const Configuration& c : configurations()) s.runs.push_back(run_configuration(s.path, c));
    out.push_back(std::move(s));
  }
  if (ctx.log) {
    *ctx.log << "  " << r.name << " (" << r.rig.nbone << " bones):";
    for (std::size_t c = 0; c < configurations().size(); ++c) {
      *ctx.log << " " << configurations()[c].name << " " << to_string(out[0].runs[c].outcome) << "/"
               << to_string(out[1].runs[c].outcome);
    }
    *ctx.log << "\n" << std::flush;
  }
  return out;
}

double median(std::vector<double> v) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  const std::size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

// a median as text: "-" when there is none
std::string median_text(const std::vector<double>& v, int digits = 4) {
  return v.empty() ? "-" : num(median(v), digits);
}

// a configuration's outcomes over every scene
struct Tally {
  std::string preset;  // the preset its scenes took (the first run that loaded)
  int converged = 0, not_converged = 0, diverged = 0, refused = 0;
  std::vector<double> steps, residuals;  // of the converged runs (residual over the rig size)
  double wall_s = 0.0;
  int runs() const { return converged + not_converged + diverged + refused; }
  double share() const { return runs() ? static_cast<double>(converged) / runs() : 0.0; }
};

Tally tally(const std::vector<SceneRuns>& scenes, std::size_t config) {
  Tally t;
  for (const SceneRuns& s : scenes) {
    const RunResult& r = s.runs[config];
    if (t.preset.empty()) t.preset = r.preset;
    t.wall_s += r.wall_s;
    switch (r.outcome) {
      case Outcome::kConverged:
        ++t.converged;
        t.steps.push_back(r.steps_to_converge);
        t.residuals.push_back(r.max_residual / s.size);
        break;
      case Outcome::kNotConverged:
        ++t.not_converged;
        break;
      case Outcome::kDiverged:
        ++t.diverged;
        break;
      case Outcome::kRefused:
        ++t.refused;
        break;
    }
  }
  return t;
}

nlohmann::json tally_json(const Tally& t) {
  return {{"preset", t.preset},
          {"runs", t.runs()},
          {"converged", t.converged},
          {"not_converged", t.not_converged},
          {"diverged", t.diverged},
          {"refused", t.refused},
          {"converged_share", t.share()},
          {"median_steps_converged",
           t.steps.empty() ? nlohmann::json(nullptr) : nlohmann::json(median(t.steps))},
          {"wall_s", t.wall_s}};
}

std::size_t config_index(const std::string& name) {
  for (std::size_t c = 0; c < configurations().size(); ++c) {
    if (configurations()[c].name == name) return c;
  }
  throw std::logic_error("outside_rigs: no configuration " + name);
}

// the two torsion torques under implicit + damping auto, scene by scene
struct TorsionComparison {
  int runs = 0, axes = 0, gradient = 0;            // runs, and converged runs of each
  std::vector<double> axes_steps, gradient_steps;  // where both converged, paired
  int identical = 0;  // same outcome, steps and final residual (no limit spring told them apart)
};

TorsionComparison compare_torsion(const std::vector<SceneRuns>& scenes) {
  const std::size_t ia = config_index("implicit-auto-axes");
  const std::size_t ig = config_index("implicit-auto-gradient");
  TorsionComparison t;
  for (const SceneRuns& s : scenes) {
    const RunResult &a = s.runs[ia], &g = s.runs[ig];
    ++t.runs;
    t.axes += a.outcome == Outcome::kConverged;
    t.gradient += g.outcome == Outcome::kConverged;
    if (a.outcome == Outcome::kConverged && g.outcome == Outcome::kConverged) {
      t.axes_steps.push_back(a.steps_to_converge);
      t.gradient_steps.push_back(g.steps_to_converge);
    }
    t.identical +=
        a.outcome == g.outcome && a.steps_run == g.steps_run && a.max_residual == g.max_residual;
  }
  return t;
}

void add_claims(Report& report, const Tally& d, int nrigs, const TorsionComparison& t) {
  report
      .claim("Scenes that name no settings converge on at least 90% of the outside rigs",
             "default (preset " + d.preset + "): " + std::to_string(d.converged) + " of " +
                 std::to_string(d.runs()) + " runs over " + std::to_string(nrigs) +
                 " rigs converged (" + num(100 * d.share(), 3) + "%); " +
                 std::to_string(d.diverged) + " diverged, " + std::to_string(d.not_converged) +
                 " still moving, " + std::to_string(d.refused) + " refused",
             d.share() >= 0.9 ? "yes" : "no")
      .named("default-converges");
  const bool more = t.gradient >= t.axes;
  const bool faster = t.axes_steps.empty() || median(t.gradient_steps) <= median(t.axes_steps);
  report.claim(
      "Under implicit + damping auto, the gradient torsion torque converges on at least as many "
      "outside-rig runs as the paper's axes torque, in no more median steps",
      "converged: gradient " + std::to_string(t.gradient) + ", axes " + std::to_string(t.axes) +
          " of " + std::to_string(t.runs) + "; median steps where both converged (" +
          std::to_string(t.axes_steps.size()) + "): gradient " + median_text(t.gradient_steps) +
          ", axes " + median_text(t.axes_steps) + "; identical runs " + std::to_string(t.identical),
      more && faster   ? "yes"
      : more || faster ? "partly"
                       : "no");
}

// --- the rig's own body ---------------------------------------------------------------------

constexpr double kWeldTolerance = 1e-9;  // rad, a welded group's largest turn that is rigid
// of the rig's size: the largest root drift that is an anchored root staying put (round-off)
constexpr double kDriftTolerance = 1e-12;

void add_run(RigChecks& c, const RunResult& r) {
  if (r.outcome == Outcome::kRefused) return;
  ++c.runs;
  c.runs_converged += r.outcome == Outcome::kConverged;
  c.run.add(r.body);
}

void add_solve(RigChecks& c, const RunResult& r) {
  if (r.outcome == Outcome::kRefused) return;
  ++c.solves;
  c.solves_converged += r.outcome == Outcome::kConverged;
  c.solve.add(r.body);
}

// a sample model's checks: its scenes' default runs (already run) and their solves
RigChecks check_sample(const SceneRuns& one, const SceneRuns& two) {
  RigChecks c = check_rig(one.rig->name, "mjcf", one.rig->rig);
  const std::size_t d = config_index("default");
  for (const SceneRuns* s : {&one, &two}) {
    add_run(c, s->runs[d]);
    add_solve(c, solve_configuration(s->path));
  }
  return c;
}

// a rig of the experiment's own (written with its scenes, each run under the default
// configuration and solved)
RigChecks check_own(const Context& ctx, const OutsideRig& r, const std::string& source, int steps) {
  RigChecks c = check_rig(r.name, source, r.rig);
  for (const std::string& path : write_rig(ctx, r, steps)) {
    add_run(c, run_configuration(path, configurations()[config_index("default")]));
    add_solve(c, solve_configuration(path));
  }
  return c;
}

double rest_ke(const RigChecks& c) {
  return std::max({c.rest_ke_gauss_seidel, c.rest_ke_exact, c.rest_ke_implicit});
}

double root_drift(const RigChecks& c) {
  return std::max(c.run.root_drift, c.solve.root_drift);
}

// `paper`: rad, the largest weld turn over the sample models' runs under the paper's scheme
// (configuration original; most of them diverge, and their last finite steps count), shown beside
// the claim's measures
void add_weld_claim(Report& report, const std::vector<const RigChecks*>& samples, double paper) {
  const RigChecks *run = nullptr, *solve = nullptr;
  int rigs = 0, welded = 0, runs = 0, solves = 0;
  for (const RigChecks* c : samples) {
    if (c->welded == 0) continue;
    ++rigs;
    welded += c->welded;
    runs += c->runs;
    solves += c->solves;
    if (!run || c->run.weld_turn > run->run.weld_turn) run = c;
    if (!solve || c->solve.weld_turn > solve->solve.weld_turn) solve = c;
  }
  const std::string claim =
      "Welded groups stay rigid to " + num(kWeldTolerance) +
      " rad through a run (simulate, the default) and a solve (solve --solver physik) on every "
      "converted sample model";
  if (rigs == 0) {
    report.claim(claim, "no converted sample model has a welded bone", "n/a").named("welds-rigid");
    return;
  }
  const bool holds = run->run.weld_turn <= kWeldTolerance &&
                     solve->solve.weld_turn <= kWeldTolerance && runs > 0 && solves > 0;
  // the rig that turned most, when one turned at all
  const auto where = [](double turn, const RigChecks* c) {
    return turn > 0.0 ? " (" + c->name + ")" : std::string();
  };
  report
      .claim(claim,
             std::to_string(rigs) + " rigs, " + std::to_string(welded) + " welded bones, " +
                 std::to_string(runs) + " runs, " + std::to_string(solves) +
                 " solves; largest turn: runs " + num(run->run.weld_turn, 3) + " rad" +
                 where(run->run.weld_turn, run) + ", solves " + num(solve->solve.weld_turn, 3) +
                 " rad" + where(solve->solve.weld_turn, solve) +
                 "; runs under the paper's scheme (original) " + num(paper, 3) + " rad",
             holds ? "yes" : "no")
      .named("welds-rigid");
}

void add_rest_claims(Report& report, const std::vector<const RigChecks*>& samples) {
  double gs = 0.0, exact = 0.0, implicit = 0.0;
  int overlaps = 0, open = 0;
  std::string open_rigs;
  for (const RigChecks* c : samples) {
    gs = std::max(gs, c->rest_ke_gauss_seidel);
    exact = std::max(exact, c->rest_ke_exact);
    implicit = std::max(implicit, c->rest_ke_implicit);
    overlaps += c->rest_overlaps;
    open += c->open_overlaps;
    if (c->open_overlaps > 0) open_rigs += (open_rigs.empty() ? " (" : ", ") + c->name;
  }
  if (!open_rigs.empty()) open_rigs += ")";
  const std::string n = std::to_string(samples.size());
  report
      .claim(
          "Rest stays rest: a converted sample model with no targets and no gravity, "
          "self_collision on, has no kinetic energy over " +
              std::to_string(kRestSteps) + " steps in every scheme",
          "largest over " + n + " rigs: gauss-seidel " + num(gs, 3) + " J, exact " + num(exact, 3) +
              " J, implicit " + num(implicit, 3) + " J",
          gs == 0.0 && exact == 0.0 && implicit == 0.0 ? "yes" : "no")
      .named("rest-stays-rest");
  report
      .claim(
          "No rest-pose overlap is left: every capsule pair of a converted sample model that "
          "overlaps at rest is excluded",
          std::to_string(overlaps) + " pairs overlap at rest over " + n + " rigs, " +
              std::to_string(open) + " not excluded" + open_rigs,
          open == 0 ? "yes" : "no")
      .named("no-rest-overlap");
}

void add_root_claim(Report& report, const RigChecks* arm, const RigChecks* free) {
  const std::string claim =
      "arm26's root, hinged to the world in MuJoCo, stays where it is under a control point "
      "pulling the hand (a pinned root; its head's drift 0 to " +
      num(kDriftTolerance) + " of the rig's size)";
  if (!arm) {
    report.claim(claim, "tendon_arm/arm26.xml gave no rig here", "n/a").named("arm26-root-fixed");
    return;
  }
  const double size = rig_size(*arm->rig);
  const bool anchored = arm->rig->root_anchored();
  std::string measured = "root " + std::string(to_string(arm->rig->root_joint)) +
                         ", largest drift over " + std::to_string(arm->runs) + " runs and " +
                         std::to_string(arm->solves) + " solves " + num(root_drift(*arm), 3) +
                         " (size " + num(size, 3) + ")";
  if (free) measured += "; with its root made free: " + num(root_drift(*free), 3);
  report
      .claim(
          claim, measured,
          anchored && arm->runs > 0 && arm->solves > 0 && root_drift(*arm) <= kDriftTolerance * size
              ? "yes"
              : "no")
      .named("arm26-root-fixed");
}

void add_mocap_claim(Report& report, const RigChecks& c, const MocapRig& m) {
  const double turn = std::max(c.run.weld_turn, c.solve.weld_turn);
  const double pelvis = std::max(c.run.root_turn, c.solve.root_turn);
  const bool holds = c.welded > 0 && c.runs > 0 && c.solves > 0 && turn <= kWeldTolerance &&
                     rest_ke(c) == 0.0 && c.open_overlaps == 0 && m.pelvis_one_body &&
                     pelvis <= kWeldTolerance;
  report
      .claim(
          "A motion-capture skeleton of this experiment's own (a BVH in centimetres, Y up, "
          "its root with three children), converted as rig from-bvh --scale 0.01, passes the "
          "same checks, and its pelvis (the root's segments) stays one body",
          std::to_string(c.welded) + " welded bones, turn " + num(turn, 3) +
              " rad; pelvis: " + std::to_string(m.pelvis.size()) + " bones, " +
              (m.pelvis_one_body ? "one body" : "several bodies") + ", turn " + num(pelvis, 3) +
              " rad; rest KE " + num(rest_ke(c), 3) + " J; " + std::to_string(c.open_overlaps) +
              " of " + std::to_string(c.rest_overlaps) + " rest overlaps open",
          holds ? "yes" : "no")
      .named("mocap-skeleton");
}

// "<steps>" when converged, else the outcome in a word
std::string outcome_cell(const RunResult& r) {
  switch (r.outcome) {
    case Outcome::kConverged:
      return std::to_string(r.steps_to_converge);
    case Outcome::kNotConverged:
      return "moving";
    case Outcome::kDiverged:
      return "diverged";
    case Outcome::kRefused:
      return "refused";
  }
  return "?";
}

void add_tables(Report& report, const std::vector<SceneRuns>& scenes,
                const std::vector<Tally>& tallies, const std::vector<Skipped>& skipped) {
  nlohmann::json per_config = nlohmann::json::array();
  for (std::size_t c = 0; c < tallies.size(); ++c) {
    const Tally& t = tallies[c];
    per_config.push_back({configurations()[c].name, t.preset, t.converged, t.not_converged,
                          t.diverged, t.refused, num(100 * t.share(), 3) + "%",
                          median_text(t.steps), median_text(t.residuals, 3), num(t.wall_s)});
  }
  report.table("Outcomes per configuration (steps and residuals: medians over converged runs)",
               {"configuration", "preset", "converged", "still moving", "diverged", "refused",
                "converged share", "steps", "residual / size", "wall time (s)"},
               per_config);
  std::vector<std::string> columns = {"rig", "bones"};
  for (const Configuration& c : configurations()) columns.push_back(c.name);
  nlohmann::json per_rig = nlohmann::json::array();
  for (std::size_t k = 0; k + 1 < scenes.size(); k += 2) {  // a rig's 1- and 2-point scenes
    nlohmann::json row = {scenes[k].rig->name, scenes[k].rig->rig.nbone};
    for (std::size_t c = 0; c < configurations().size(); ++c) {
      row.push_back(outcome_cell(scenes[k].runs[c]) + " / " + outcome_cell(scenes[k + 1].runs[c]));
    }
    per_rig.push_back(row);
  }
  report.table("Per rig: steps to converge with one / two control points", columns, per_rig);
  nlohmann::json skip_rows = nlohmann::json::array();
  for (const Skipped& s : skipped) skip_rows.push_back({s.file, s.reason});
  if (!skip_rows.empty())
    report.table("Sample files not run as a rig of their own", {"file", "reason"}, skip_rows);
}

void add_notes(Report& report, const std::vector<SceneRuns>& scenes, int steps) {
  report.note(
      "Targets, one rule for every rig: point 1 on the tail of the leaf bone farthest from "
      "the root bone's head, its target moved " +
      num(kTargetFraction) +
      " x the rig's size "
      "(the largest extent of its rest pose) along (1, 0, 1)/sqrt 2; point 2 on the leaf "
      "farthest from point 1, moved as much along (-1, 0, 1)/sqrt 2 (a rig with one leaf "
      "pins its root bone's head instead). The scenes name no params; a run stops once "
      "converged (at rest for 10 steps), else after " +
      std::to_string(steps) + " steps.");
  report.note(
      "Configurations: default = no overrides; original = --set preset=original; "
      "implicit-auto-axes|gradient = --set preset=original --set scheme=implicit "
      "--set damping=auto --set torsion_torque=axes|gradient. A refusal counts as a "
      "failure. Rerun one from this folder: physik simulate scenes/<rig>-<n>pt.json "
      "[--set ...].");
  for (const SceneRuns& s : scenes) {
    for (std::size_t c = 0; c < s.runs.size(); ++c) {
      if (s.runs[c].outcome != Outcome::kRefused) continue;
      report.note("First refusal (" + s.rig->name + ", " + configurations()[c].name +
                  "): " + s.runs[c].refusal);
      return;
    }
  }
}

void add_check_table(Report& report, const Table& checks) {
  checks.add_to_report(report,
                       "The rig's own body, per rig (checks.csv): the largest turn inside a "
                       "welded group, rest kinetic energy, overlaps at rest, the root's drift",
                       {{"rig", "rig"},
                        {"bones", "bones"},
                        {"bodies", "bodies"},
                        {"root", "root"},
                        {"turn, runs (rad)", "run_weld_turn"},
                        {"turn, solves (rad)", "solve_weld_turn"},
                        {"rest KE gauss-seidel (J)", "rest_ke_gauss_seidel"},
                        {"exact (J)", "rest_ke_exact"},
                        {"implicit (J)", "rest_ke_implicit"},
                        {"overlaps at rest", "rest_overlaps"},
                        {"open", "open_overlaps"},
                        {"root drift, runs", "run_root_drift"},
                        {"root drift, solves", "solve_root_drift"},
                        {"radius min", "radius_min"},
                        {"radius max", "radius_max"}});
}

void add_check_notes(Report& report) {
  report.note(
      "The rig's own body (checks.csv), on every converted sample model, on arm26 with its root "
      "made free (its limits against the world dropped: the root as the converter left it "
      "before anchored roots) and on a motion-capture skeleton the experiment writes "
      "(bvh/mocap.bvh: 183 cm, Y up, its Hips with three children, its Chest with three; "
      "converted as rig from-bvh --scale 0.01). The turn inside a welded group is the largest "
      "angle between a welded bone's frame and its rest frame in the frame of the bone it is "
      "welded to, over every step of the default configuration's runs of the rig's two scenes "
      "and of their solves (the solve mode, as solve --solver physik); the root's drift is its "
      "head's distance from rest over the same steps. Rest: the rig from rest, no control "
      "point, no gravity, self_collision on, " +
      std::to_string(kRestSteps) +
      " steps; the largest kinetic energy under preset original (gauss-seidel), original with "
      "scheme exact, and robust (implicit). Overlaps: capsule pairs closer than their radii' "
      "sum at rest (physik/engine/bone_overlaps.h), and those the rig does not exclude. runs.csv "
      "gives the turn and the drift of every run under every configuration (weld_turn, "
      "root_drift).");
}

nlohmann::json rigs_json(const std::vector<SceneRuns>& scenes) {
  nlohmann::json out = nlohmann::json::array();
  for (std::size_t k = 0; k + 1 < scenes.size(); k += 2) {
    const OutsideRig& r = *scenes[k].rig;
    nlohmann::json points = nlohmann::json::array();
    for (const Pick& p : pick_targets(r.rig, 2)) {
      points.push_back({{"bone", r.rig.bone_name[p.bone]},
                        {"alpha", p.alpha},
                        {"target", {p.target_world.x(), p.target_world.y(), p.target_world.z()}}});
    }
    out.push_back({{"name", r.name},
                   {"file", r.file},
                   {"model", r.rig.name},
                   {"bones", r.rig.nbone},
                   {"size", scenes[k].size},
                   {"points", points}});
  }
  return out;
}

// the quick context's models: kQuickFiles, each required
std::vector<std::string> quick_files(const std::vector<std::string>& files) {
  std::vector<std::string> out;
  for (const char* name : kQuickFiles) {
    const std::string path = std::string(kSamplesDir) + "/" + name;
    if (std::find(files.begin(), files.end(), path) == files.end()) {
      throw std::runtime_error("outside_rigs: " + path + ": missing (the quick run needs it)");
    }
    out.push_back(path);
  }
  return out;
}

// The rig's own body, checked: every sample model (the first `nsamples` checks), arm26 with its
// root made free, the BVH skeleton. The checks point to the sample rigs and to `own`.
struct BodyChecks {
  std::vector<RigChecks> checks;
  std::size_t nsamples = 0;
  std::deque<OutsideRig> own;
  MocapRig mocap;
};

void check_bodies(const Context& ctx, const std::vector<SceneRuns>& scenes, const Collection& found,
                  int steps, BodyChecks& out) {
  for (std::size_t k = 0; k + 1 < scenes.size(); k += 2) {
    out.checks.push_back(check_sample(scenes[k], scenes[k + 1]));
  }
  out.nsamples = out.checks.size();
  const auto arm = std::find_if(found.rigs.begin(), found.rigs.end(),
                                [](const OutsideRig& r) { return r.name == kArm26; });
  if (arm != found.rigs.end()) {
    out.own.push_back({arm->name + "-free-root", arm->file, with_free_root(arm->rig)});
    out.checks.push_back(check_own(ctx, out.own.back(), "mjcf-free-root", steps));
  }
  out.mocap = convert_mocap(ctx.out_dir + "/bvh/mocap.bvh");
  out.own.push_back({"mocap-bvh", ctx.out_dir + "/bvh/mocap.bvh", out.mocap.rig});
  out.checks.push_back(check_own(ctx, out.own.back(), "bvh", steps));
}

void add_body_claims(Report& report, const BodyChecks& body, const std::vector<SceneRuns>& scenes) {
  std::vector<const RigChecks*> samples;
  for (std::size_t k = 0; k < body.nsamples; ++k) samples.push_back(&body.checks[k]);
  double paper_turn = 0.0;
  for (const SceneRuns& s : scenes) {
    paper_turn = std::max(paper_turn, s.runs[config_index("original")].body.weld_turn);
  }
  add_weld_claim(report, samples, paper_turn);
  add_rest_claims(report, samples);
  const auto find_check = [&](const std::string& name) -> const RigChecks* {
    for (const RigChecks& c : body.checks) {
      if (c.name == name) return &c;
    }
    return nullptr;
  };
  add_root_claim(report, find_check(kArm26), find_check(std::string(kArm26) + "-free-root"));
  add_mocap_claim(report, body.checks.back(), body.mocap);
}

void run(const Context& ctx) {
  std::vector<std::string> files = sample_files(kSamplesDir);
  if (ctx.quick) files = quick_files(files);
  const Collection found = collect_rigs(files);
  if (found.rigs.empty()) throw std::runtime_error("outside_rigs: no sample model gave a rig");
  std::filesystem::create_directories(ctx.out_dir + "/rigs");
  std::filesystem::create_directories(ctx.out_dir + "/scenes");
  const int steps = ctx.quick ? kQuickStepCap : kStepCap;
  std::vector<SceneRuns> scenes;
  for (const OutsideRig& r : found.rigs) {
    for (SceneRuns& s : run_rig(ctx, r, steps)) scenes.push_back(std::move(s));
  }
  const Table runs = runs_table(scenes);
  runs.write_csv(ctx.out_dir);
  std::vector<Tally> tallies;
  nlohmann::json configs = nlohmann::json::array();
  for (std::size_t c = 0; c < configurations().size(); ++c) {
    tallies.push_back(tally(scenes, c));
    configs.push_back({{"name", configurations()[c].name},
                       {"sets", configurations()[c].sets},
                       {"counts", tally_json(tallies.back())}});
  }
  const TorsionComparison t = compare_torsion(scenes);
  BodyChecks body;  // the rig's own body
  check_bodies(ctx, scenes, found, steps, body);
  const Table checked = checks_table(body.checks);
  checked.write_csv(ctx.out_dir);
  Report report("Outside rigs: MuJoCo's sample models with scenes that name no settings");
  add_claims(report, tallies[config_index("default")], static_cast<int>(found.rigs.size()), t);
  add_body_claims(report, body, scenes);
  add_tables(report, scenes, tallies, found.skipped);
  add_check_table(report, checked);
  add_notes(report, scenes, steps);
  add_check_notes(report);
  report
      .settings(
          settings_json(load_scene(scenes.front().path), {{"target_fraction", kTargetFraction}}))
      .figures({"outside_rigs.png"});
  nlohmann::json skipped = nlohmann::json::array();
  for (const Skipped& s : found.skipped) {
    skipped.push_back({{"file", s.file}, {"reason", s.reason}});
  }
  write_summary(ctx,
                {{"experiment", "outside_rigs"},
                 {"samples_dir", kSamplesDir},
                 {"quick", ctx.quick},
                 {"step_cap", steps},
                 {"rigs", rigs_json(scenes)},
                 {"skipped", skipped},
                 {"configurations", configs},
                 {"torsion_comparison",
                  {{"runs", t.runs},
                   {"axes_converged", t.axes},
                   {"gradient_converged", t.gradient},
                   {"paired", t.axes_steps.size()},
                   {"identical", t.identical}}},
                 {"runs", runs.rows_json()},
                 {"checks", checked.rows_json()}},
                report, {&runs, &checked});
}

const Registration registered{
    280,
    {"outside_rigs", "study: the default on outside rigs",
     "MuJoCo's sample models as rigs, scenes with no settings: default, original and "
     "implicit + damping auto (both torsion torques)",
     run}};

}  // namespace

}  // namespace physik::experiments
