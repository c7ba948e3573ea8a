// Reading run folders for the viewer (run_reader.h).
#include "viewer/run_reader.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <unordered_map>

#include "physik/io/contacts_table.h"
#include "physik/io/json_fields.h"
#include "physik/io/pose_io.h"
#include "physik/io/recorder.h"
#include "physik/io/run_folder.h"
#include "physik/io/scene_io.h"
#include "physik/io/targets_limits.h"
#include "physik/model/errors.h"

namespace physik::viewer {

namespace fs = std::filesystem;

namespace {

// the viewer's bounds (run_reader.h): coordinates within the rig's, the rest within a float's
constexpr double kFloatMax = std::numeric_limits<float>::max();

// The first kept frame holding a value past the bounds: it and the later frames are left out.
struct Cut {
  int frame = std::numeric_limits<int>::max();  // the first frame left out
  int step = 0;                                 // its step
  std::string file, line, column, field, reason;

  bool before(int f) const { return f < frame; }
};

// The fields of one CSV line (RFC 4180: a quoted field may hold commas and doubled quotes;
// names hold no line breaks, the rig loader refuses control characters). False on an
// unbalanced quote.
bool split_csv_line(const std::string& line, std::vector<std::string>& fields) {
  fields.clear();
  std::string field;
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c != '"') {
        field += c;
      } else if (i + 1 < line.size() && line[i + 1] == '"') {
        field += '"';
        ++i;
      } else {
        quoted = false;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      fields.push_back(std::move(field));
      field.clear();
    } else if (c != '\r') {
      field += c;
    }
  }
  fields.push_back(std::move(field));
  return !quoted;
}

// The unquoted column names a table of `quoted` names has.
std::vector<std::string> unquoted(const std::vector<std::string>& first,
                                  const std::vector<std::string>& quoted) {
  std::string line;
  for (const std::string& f : first) line += (line.empty() ? "" : ",") + f;
  for (const std::string& q : quoted) line += "," + q;
  std::vector<std::string> out;
  split_csv_line(line, out);
  return out;
}

// A table file read row by row, with its line number for messages.
class CsvFile {
 public:
  explicit CsvFile(const std::string& path) : path_(path), in_(path) {
    if (!in_) throw_input_error(path, "", "", "cannot read the file");
  }
  const std::string& path() const { return path_; }
  int line_number() const { return line_; }

  // The next non-empty line's fields; false at the end.
  bool next(std::vector<std::string>& fields) {
    std::string line;
    while (std::getline(in_, line)) {
      ++line_;
      if (line.empty() || line == "\r") continue;
      if (!split_csv_line(line, fields)) fail("", "an unbalanced quote");
      return true;
    }
    return false;
  }

  // The header must be `expected`: the scene's columns. With `older` (the columns an earlier
  // version wrote, a prefix of `expected`), a header of those is taken too; returns whether the
  // header was the whole of `expected`.
  bool check_header(const std::vector<std::string>& expected,
                    const std::vector<std::string>& older = {}) {
    std::vector<std::string> header;
    if (!next(header)) throw_input_error(path_, "", "", "empty file (no header)");
    if (!older.empty() && header == older) return false;
    for (std::size_t k = 0; k < std::max(header.size(), expected.size()); ++k) {
      const std::string got = k < header.size() ? header[k] : "(none)";
      const std::string want = k < expected.size() ? expected[k] : "(none)";
      if (got != want) {
        fail("header", "column " + std::to_string(k + 1) + " is '" + got + "' where the run's " +
                           "scene.json gives '" + want + "'");
      }
    }
    return true;
  }

  [[noreturn]] void fail(const std::string& field, const std::string& reason) const {
    throw_input_error(path_, "line " + std::to_string(line_), field, reason);
  }

  double number(const std::vector<std::string>& fields, std::size_t k,
                const std::vector<std::string>& names) const {
    const std::string& text = fields[k];
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0' || !std::isfinite(v)) {
      fail(names[k], "'" + text + "' is not a finite number");
    }
    return v;
  }

  // field k as a float the page can hold: within `bound` (a coordinate: the rig's bound; else a
  // float's range). Past it, frame `frame` is where `cut` starts unless it starts earlier already;
  // false then.
  bool bounded(const std::vector<std::string>& fields, std::size_t k,
               const std::vector<std::string>& names, bool coordinate, int frame, int step,
               Cut& cut, float& out) const {
    const double v = number(fields, k, names);
    const double bound = coordinate ? kMaxCoordinate : kFloatMax;
    if (std::abs(v) <= bound) {
      out = static_cast<float>(v);
      return true;
    }
    if (cut.before(frame)) {
      static_assert(kMaxCoordinate == 1e9, "the message quotes it");
      cut.frame = frame;
      cut.step = step;
      cut.file = path_;
      cut.line = std::to_string(line_);
      cut.column = std::to_string(k + 1);
      cut.field = names[k];
      cut.reason =
          "'" + fields[k] + "' is beyond " +
          (coordinate ? std::string("the rig's coordinate bound +-1e9 (rig.h kMaxCoordinate)")
                      : std::string("the viewer's float range (+-3.4e38)"));
    }
    return false;
  }

 private:
  std::string path_;
  std::ifstream in_;
  int line_ = 0;
};

// Data rows of a table (non-empty lines after the header).
int count_rows(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  int rows = -1;  // the header
  while (std::getline(in, line)) {
    if (!line.empty() && line != "\r") ++rows;
  }
  return std::max(rows, 0);
}

std::vector<std::string> trajectory_columns(const Scene& scene) {
  std::vector<std::string> quoted = residual_column_names(scene);
  const std::vector<std::string> bones = bone_column_names(scene.rig);
  quoted.insert(quoted.end(), bones.begin(), bones.end());
  return unquoted(
      {"step", "time", "kinetic_energy", "passes", "joint_mismatch", "joint_separation"}, quoted);
}

// One kept trajectory row into the run's arrays; false (nothing kept, `cut` set) where a value
// lies past the viewer's bounds.
bool keep_row(const CsvFile& csv, const std::vector<std::string>& f,
              const std::vector<std::string>& names, Cut& cut, ViewRun& run) {
  const int ncontrol = static_cast<int>(run.scene.control_points.size());
  const int frame = static_cast<int>(run.steps.size());
  const double step = csv.number(f, 0, names);
  if (step != std::floor(step) || step < 0 || step > 2e9) csv.fail("step", "not a step number");
  const int n = static_cast<int>(step);
  const double time = csv.number(f, 1, names);
  float ke = 0.0f, largest = 0.0f, r = 0.0f;
  if (!csv.bounded(f, 2, names, false, frame, n, cut, ke)) return false;
  int which = -1;
  for (int c = 0; c < ncontrol; ++c) {
    if (!csv.bounded(f, 6 + c, names, false, frame, n, cut, r)) return false;
    if (which < 0 || r > largest) {
      largest = r;
      which = c;
    }
  }
  const std::size_t first = run.positions.size();
  for (std::size_t k = 6 + ncontrol; k < f.size(); ++k) {
    float x = 0.0f;
    if (!csv.bounded(f, k, names, true, frame, n, cut, x)) {
      run.positions.resize(first);
      return false;
    }
    run.positions.push_back(x);
  }
  run.steps.push_back(n);
  run.times.push_back(time);
  run.kinetic_energy.push_back(ke);
  run.max_residual.push_back(largest);
  run.max_residual_point.push_back(which);
  return true;
}

void read_trajectory(const std::string& path, int max_frames, Cut& cut, ViewRun& run) {
  run.rows_recorded = count_rows(path);
  if (run.rows_recorded == 0) {
    throw_input_error(path, "", "",
                      "an empty trajectory: the header and no row (no state of the "
                      "run was recorded)");
  }
  const long rows = run.rows_recorded, kept = std::min<long>(rows, max_frames);
  // the k-th kept row, rounded from k (rows - 1) / (kept - 1) in integers
  const auto kept_row = [&](long k) {
    return kept < 2 ? 0 : (2 * k * (rows - 1) + kept - 1) / (2 * (kept - 1));
  };
  long next = 0;  // the next kept row's k
  CsvFile csv(path);
  const std::vector<std::string> names = trajectory_columns(run.scene);
  csv.check_header(names);
  std::vector<std::string> f;
  for (long r = 0; csv.next(f); ++r) {
    if (f.size() != names.size()) {
      csv.fail("", std::to_string(f.size()) + " fields where the header has " +
                       std::to_string(names.size()));
    }
    if (next < kept && r == kept_row(next)) {
      if (!keep_row(csv, f, names, cut, run)) return;  // this frame and the later ones left out
      ++next;
    }
  }
}

// The frame of every kept step (a step recorded twice keeps its first frame).
std::unordered_map<int, int> frame_of_step(const ViewRun& run) {
  std::unordered_map<int, int> frame;
  for (std::size_t k = 0; k < run.steps.size(); ++k) frame.emplace(run.steps[k], int(k));
  return frame;
}

// One targets_and_limits.csv row of kept frame fr: its targets, limit excess and (where the file
// has them) bone orientations; stops at the first value past the bounds (`cut`)
void read_targets_row(const CsvFile& csv, const std::vector<std::string>& f,
                      const std::vector<std::string>& names, int fr, std::size_t orient_col,
                      Cut& cut, ViewRun& run) {
  const int nbone = run.scene.rig.nbone;
  const int ncontrol = static_cast<int>(run.scene.control_points.size());
  float* t = run.targets.data() + std::size_t(fr) * ncontrol * 3;
  bool ok = true;
  const int step = run.steps[fr];
  for (int k = 0; k < 3 * ncontrol && ok; ++k) {
    ok = csv.bounded(f, 1 + k, names, true, fr, step, cut, t[k]);
  }
  for (int b = 0; b < nbone && ok; ++b) {
    float e = 0.0f, x = 0.0f;
    for (int a = 0; a < 3 && ok; ++a) {
      ok = csv.bounded(f, 1 + 3 * ncontrol + 3 * b + a, names, false, fr, step, cut, x);
      e = std::max(e, std::abs(x));
    }
    run.limit_excess[std::size_t(fr) * nbone + b] = e;
  }
  if (!ok || run.orientations.empty()) return;
  // w x y z in the file, x y z w (three.js's order) in the page; unit quaternions, within any
  // bound
  float* q = run.orientations.data() + std::size_t(fr) * nbone * 4;
  for (int b = 0; b < nbone && ok; ++b) {
    const std::size_t c = orient_col + 4 * std::size_t(b);
    ok = csv.bounded(f, c, names, false, fr, step, cut, q[4 * b + 3]);
    for (int k = 0; k < 3 && ok; ++k) {
      ok = csv.bounded(f, c + 1 + k, names, false, fr, step, cut, q[4 * b + k]);
    }
  }
}

// Targets and limit excess of the kept frames (before `cut`, which a value past the bounds moves
// earlier); every kept frame must have its row.
void read_targets_limits(const std::string& path, Cut& cut, ViewRun& run) {
  const int nframe = static_cast<int>(run.steps.size()), nbone = run.scene.rig.nbone;
  const int ncontrol = static_cast<int>(run.scene.control_points.size());
  run.targets.assign(std::size_t(nframe) * ncontrol * 3, 0.0f);
  run.limit_excess.assign(std::size_t(nframe) * nbone, 0.0f);
  std::vector<char> has_row(nframe, 0);
  CsvFile csv(path);
  std::vector<std::string> names = unquoted({"step"}, targets_limits_column_names(run.scene));
  // folders recorded before the orientation columns: targets and excess only
  const std::vector<std::string> older(names.begin(), names.end() - 4 * std::size_t(nbone));
  if (csv.check_header(names, older)) {
    run.orientations.assign(std::size_t(nframe) * nbone * 4, 0.0f);
  } else {
    names = older;
    run.notes.push_back(std::string(kTargetsLimitsFile) +
                        " has no bone orientations (recorded by an earlier version): bone axes "
                        "and limit ranges are not shown");
  }
  const std::size_t orient_col = 1 + 3 * std::size_t(ncontrol) + 3 * std::size_t(nbone);
  const std::unordered_map<int, int> frame = frame_of_step(run);
  std::vector<std::string> f;
  while (csv.next(f)) {
    if (f.size() != names.size()) {
      csv.fail("", std::to_string(f.size()) + " fields where the header has " +
                       std::to_string(names.size()));
    }
    const auto it = frame.find(static_cast<int>(csv.number(f, 0, names)));
    if (it == frame.end() || !cut.before(it->second)) continue;  // a frame left out
    const int fr = it->second;
    if (has_row[fr]) continue;  // a step recorded twice keeps its first row, as its frame
    has_row[fr] = 1;
    read_targets_row(csv, f, names, fr, orient_col, cut, run);
  }
  for (int fr = 0; fr < nframe && cut.before(fr); ++fr) {
    if (!has_row[fr]) {
      throw_input_error(path, "", "step",
                        "no row for step " + std::to_string(run.steps[fr]) + " of " +
                            kTrajectoryFile + " (a run folder's tables hold the same steps)");
    }
  }
}

// one contacts.csv row's bone index: a bone of the rig, or -1 (the ground) where `ground_ok`
int contact_bone(const CsvFile& csv, const std::vector<std::string>& f, std::size_t k,
                 const std::vector<std::string>& names, int nbone, bool ground_ok) {
  const double b = csv.number(f, k, names);
  if (b != std::floor(b) || b < (ground_ok ? -1 : 0) || b >= nbone) {
    csv.fail(names[k], "'" + f[k] + "' is not a bone of the rig (0 to " +
                           std::to_string(nbone - 1) +
                           (ground_ok ? ", or -1 for the ground)" : ")"));
  }
  return static_cast<int>(b);
}

// The contacts of the kept frames, grouped by frame (contact_start); rows of frames decimation
// left out are skipped.
void read_contacts(const std::string& path, Cut& cut, ViewRun& run) {
  const int nframe = static_cast<int>(run.steps.size()), nbone = run.scene.rig.nbone;
  std::vector<std::vector<int>> bones(nframe);
  std::vector<std::vector<float>> values(nframe);
  CsvFile csv(path);
  const std::vector<std::string> names(std::begin(kContactsColumns), std::end(kContactsColumns));
  csv.check_header(names);
  const std::unordered_map<int, int> frame = frame_of_step(run);
  std::vector<std::string> f;
  while (csv.next(f)) {
    if (f.size() != names.size()) {
      csv.fail("", std::to_string(f.size()) + " fields where the header has " +
                       std::to_string(names.size()));
    }
    const int a = contact_bone(csv, f, 2, names, nbone, false);
    const int b = contact_bone(csv, f, 3, names, nbone, true);
    const auto it = frame.find(static_cast<int>(csv.number(f, 0, names)));
    // a row decimation left out, no trajectory row, or a frame left out
    if (it == frame.end() || !cut.before(it->second)) continue;
    std::vector<float> v(names.size() - 4);
    bool ok = true;
    // point x y z (a coordinate), normal x y z, depth (a coordinate), force
    for (std::size_t k = 4; k < names.size() && ok; ++k) {
      const bool coordinate = k < 7 || k == 10;
      ok = csv.bounded(f, k, names, coordinate, it->second, run.steps[it->second], cut, v[k - 4]);
    }
    if (!ok) continue;
    bones[it->second].insert(bones[it->second].end(), {a, b});
    values[it->second].insert(values[it->second].end(), v.begin(), v.end());
  }
  run.has_contacts = true;
  run.contact_start.assign(1, 0);
  for (int k = 0; k < nframe; ++k) {
    run.contact_bones.insert(run.contact_bones.end(), bones[k].begin(), bones[k].end());
    run.contact_values.insert(run.contact_values.end(), values[k].begin(), values[k].end());
    run.contact_start.push_back(static_cast<int>(run.contact_bones.size() / 2));
  }
}

// Without the table: each frame's goal targets from the scene and its schedule.
void goal_targets(ViewRun& run) {
  const Scene& sc = run.scene;
  const std::size_t ncontrol = sc.control_points.size();
  run.targets.clear();
  for (int step : run.steps) {
    std::vector<Vec3> goal;
    for (const ControlPoint& c : sc.control_points) goal.push_back(c.target_world);
    for (const TargetChange& t : sc.schedule) {
      if (t.step <= step) goal[t.control_point] = t.target_world;
    }
    for (std::size_t c = 0; c < ncontrol; ++c) {
      for (int a = 0; a < 3; ++a) run.targets.push_back(static_cast<float>(goal[c][a]));
    }
  }
}

// The frames before the cut kept, the rest left out, and the page told where; a cut at the first
// frame leaves nothing to show: refused, naming the file, line, column and value.
void apply_cut(const Cut& cut, ViewRun& run) {
  if (cut.frame == std::numeric_limits<int>::max()) return;  // every value within the bounds
  if (cut.frame == 0) {
    throw_input_error(cut.file, "line " + cut.line + ", column " + cut.column, cut.field,
                      cut.reason + ", in the first frame: no frame to show");
  }
  // a cut in the trajectory ended its frames there already
  const std::size_t keep = std::min(static_cast<std::size_t>(cut.frame), run.steps.size());
  const int nbone = run.scene.rig.nbone;
  const std::size_t ncontrol = run.scene.control_points.size();
  run.steps.resize(keep);
  run.times.resize(keep);
  run.kinetic_energy.resize(keep);
  run.max_residual.resize(keep);
  run.max_residual_point.resize(keep);
  run.positions.resize(keep * nbone * 6);
  run.targets.resize(keep * ncontrol * 3);
  if (!run.limit_excess.empty()) run.limit_excess.resize(keep * nbone);
  if (!run.orientations.empty()) run.orientations.resize(keep * nbone * 4);
  if (run.has_contacts) {
    run.contact_start.resize(keep + 1);
    run.contact_bones.resize(std::size_t(run.contact_start.back()) * 2);
    run.contact_values.resize(std::size_t(run.contact_start.back()) * 8);
  }
  run.notes.push_back("frames from step " + std::to_string(cut.step) + " on left out: " + cut.file +
                      " line " + cut.line + ", column " + cut.column + " ('" + cut.field +
                      "'): " + cut.reason);
}

}  // namespace

ViewRun read_run_folder(const std::string& folder, int max_frames) {
  if (max_frames < 2) throw_input_error("--max-frames", "", "", "must be at least 2");
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) {
    throw_input_error(folder, "", "", "not a run folder: no such folder");
  }
  for (const char* name : {kSceneFile, kTrajectoryFile}) {
    if (!fs::is_regular_file(fs::path(folder) / name, ec)) {
      throw_input_error(folder, "", "",
                        std::string("not a run folder: no ") + name +
                            " (physik simulate --out DIR writes a run folder)");
    }
  }
  ViewRun run;
  run.folder = folder;
  run.scene = load_scene((fs::path(folder) / kSceneFile).string());
  const fs::path summary = fs::path(folder) / kSummaryFile;
  if (fs::is_regular_file(summary, ec)) run.summary = read_json_file(summary.string());
  Cut cut;
  read_trajectory((fs::path(folder) / kTrajectoryFile).string(), max_frames, cut, run);
  const fs::path table = fs::path(folder) / kTargetsLimitsFile;
  if (fs::is_regular_file(table, ec)) {
    read_targets_limits(table.string(), cut, run);
  } else {
    goal_targets(run);
    run.notes.push_back(std::string("no ") + kTargetsLimitsFile +
                        ": targets are the scene's goals, joint limits are not shown");
  }
  const fs::path contacts = fs::path(folder) / kContactsFile;
  if (fs::is_regular_file(contacts, ec)) read_contacts(contacts.string(), cut, run);
  apply_cut(cut, run);
  if (run.rows_recorded > max_frames) {
    run.notes.push_back("decimated: " + std::to_string(run.rows_recorded) +
                        " recorded rows shown as " + std::to_string(max_frames) +
                        " frames, evenly spread, the first and the last among them (the cap is " +
                        std::to_string(max_frames) + " frames per run: --max-frames)");
  }
  return run;
}

void check_overlay(const std::vector<ViewRun>& runs) {
  for (std::size_t k = 1; k < runs.size(); ++k) {
    const Rig &a = runs[0].scene.rig, &b = runs[k].scene.rig;
    const std::string ctx = "scene.json rig";
    const std::string why = ": an overlay draws runs of the same bones";
    if (a.nbone != b.nbone) {
      throw_input_error(runs[k].folder, ctx, "bones",
                        std::to_string(b.nbone) + " bones, " + std::to_string(a.nbone) + " in " +
                            runs[0].folder + why);
    }
    for (int i = 0; i < a.nbone; ++i) {
      const std::string pa = a.bone_parent[i] < 0 ? "(root)" : a.bone_name[a.bone_parent[i]];
      const std::string pb = b.bone_parent[i] < 0 ? "(root)" : b.bone_name[b.bone_parent[i]];
      if (a.bone_name[i] != b.bone_name[i] || pa != pb) {
        throw_input_error(runs[k].folder, ctx, "bones[" + std::to_string(i) + "]",
                          "'" + b.bone_name[i] + "' (parent " + pb + ") where " + runs[0].folder +
                              " has '" + a.bone_name[i] + "' (parent " + pa + ")" + why);
      }
    }
  }
}

std::vector<std::string> default_labels(const std::vector<std::string>& folders) {
  std::vector<std::string> labels;
  for (const std::string& f : folders) {
    fs::path p = fs::path(f).lexically_normal();
    if (p.filename().empty()) p = p.parent_path();  // a trailing slash
    std::string name = p.filename().string();
    if (name.empty() || name == "." || name == "..") name = f;
    labels.push_back(name);
  }
  for (std::size_t k = 0; k < labels.size(); ++k) {
    const std::string name = labels[k];
    if (std::count(labels.begin(), labels.end(), name) > 1) {
      for (std::size_t j = 0; j < labels.size(); ++j) {
        if (labels[j] == name) labels[j] = folders[j];
      }
    }
  }
  return labels;
}

}  // namespace physik::viewer
