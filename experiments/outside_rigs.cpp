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
//   rigs/*.json, scenes/*.json   the converted rigs and the scenes (`physik simulate` runs them)
//   runs.csv                     one row per rig x scene x configuration
//   summary.json                 counts per configuration, the skipped files, the report
// Models that are the same rig up to names and a translation (MuJoCo ships one humanoid in six
// files) count once; the others are listed as skipped with the rig they repeat.
#include "experiments/outside_rigs.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "experiments/columns.h"
#include "experiments/common.h"
#include "physik/engine/engine.h"
#include "physik/io/rig_io.h"
#include "physik/io/scene_io.h"
#include "physik/model/errors.h"
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

RunResult run_configuration(const std::string& scene_path, const Configuration& config) {
  RunResult r;
  const auto start = std::chrono::steady_clock::now();
  try {
    const Scene scene = load_scene(scene_path, parse_param_overrides(config.sets, "--set"));
    r.preset = scene.params.preset;
    const RunSummary s = run_scene(scene);
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
           number("wall_s", "s", "the run's wall time")});
  for (const SceneRuns& s : scenes) {
    for (std::size_t c = 0; c < s.runs.size(); ++c) {
      const RunResult& r = s.runs[c];
      const bool ran = r.outcome != Outcome::kRefused;
      t.add({s.rig->name, s.rig->rig.nbone, s.points, configurations()[c].name, r.preset,
             to_string(r.outcome), r.steps_to_converge, r.steps_run,
             ran ? Cell(r.max_residual / s.size) : Cell(), ran ? Cell(r.damping) : Cell(),
             r.wall_s});
    }
  }
  return t;
}

// writes the rig and its two scenes under ctx.out_dir, and runs every configuration
std::vector<SceneRuns> run_rig(const Context& ctx, const OutsideRig& r, int steps) {
  const std::string rig_file = "rigs/" + r.name + ".json";
  write_json(rig_to_json(r.rig), ctx.out_dir + "/" + rig_file);
  std::vector<SceneRuns> out;
  for (int points : {1, 2}) {
    SceneRuns s{&r, points, rig_size(r.rig), "", {}};
    s.path = ctx.out_dir + "/scenes/" + r.name + "-" + std::to_string(points) + "pt.json";
    write_json(scene_json("../" + rig_file, r.rig, pick_targets(r.rig, points), steps), s.path);
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
  Report report("Outside rigs: MuJoCo's sample models with scenes that name no settings");
  add_claims(report, tallies[config_index("default")], static_cast<int>(found.rigs.size()), t);
  add_tables(report, scenes, tallies, found.skipped);
  add_notes(report, scenes, steps);
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
                 {"runs", runs.rows_json()}},
                report, {&runs});
}

const Registration registered{
    280,
    {"outside_rigs", "study: the default on outside rigs",
     "MuJoCo's sample models as rigs, scenes with no settings: default, original and "
     "implicit + damping auto (both torsion torques)",
     run}};

}  // namespace

}  // namespace physik::experiments
