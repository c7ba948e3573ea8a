// The viewer's page (view_page.h): three.js, the viewer's script and the runs' data, inlined
// into viewer/page.html.
#include "viewer/view_page.h"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

#include "physik/io/output_files.h"
#include "physik/model/errors.h"
#include "physik/model/version.h"
#include "viewer_assets.h"  // generated from viewer/viewer.js and viewer/page.html (CMake)

namespace physik::viewer {

namespace {

constexpr const char* kThreeRevision = "111";

std::string base64(const void* data, std::size_t bytes) {
  static const char* abc = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const auto* p = static_cast<const unsigned char*>(data);
  std::string out;
  out.reserve((bytes + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes; i += 3) {
    const std::uint32_t n = (std::uint32_t(p[i]) << 16) |
                            (i + 1 < bytes ? std::uint32_t(p[i + 1]) << 8 : 0) |
                            (i + 2 < bytes ? std::uint32_t(p[i + 2]) : 0);
    out += abc[(n >> 18) & 63];
    out += abc[(n >> 12) & 63];
    out += i + 1 < bytes ? abc[(n >> 6) & 63] : '=';
    out += i + 2 < bytes ? abc[n & 63] : '=';
  }
  return out;
}

// typed arrays as the page decodes them (little-endian, as every WebGL platform is)
template <class T>
std::string b64(const std::vector<T>& v) {
  static_assert(sizeof(float) == 4 && sizeof(double) == 8 && sizeof(int) == 4, "layout");
  return base64(v.data(), v.size() * sizeof(T));
}

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw_input_error(path, "", "PHYSIK_THREE_DIR",
                      "not found: the viewer inlines Debian's libjs-three (scripts/install-deps.sh "
                      "installs it); PHYSIK_THREE_DIR names another folder holding three.min.js "
                      "and examples/js/controls/OrbitControls.js");
  }
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// text that could end or confuse the <script> element it is inlined into
void check_inlinable(const std::string& text, const std::string& path) {
  std::string lower(text.size(), ' ');
  std::transform(text.begin(), text.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (lower.find("</script") != std::string::npos || lower.find("<!--") != std::string::npos) {
    throw_input_error(path, "", "", "holds '</script' or '<!--': it cannot be inlined");
  }
}

std::string html_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&#39;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

// JSON text that no HTML parser reads as markup inside a <script> element
std::string script_safe(const std::string& json) {
  std::string out;
  out.reserve(json.size());
  for (char c : json) {
    if (c == '<')
      out += "\\u003c";
    else if (c == '>')
      out += "\\u003e";
    else if (c == '&')
      out += "\\u0026";
    else
      out += c;
  }
  return out;
}

nlohmann::json summary_fields(const nlohmann::json& summary) {
  nlohmann::json out = nlohmann::json::object();
  if (!summary.is_object()) return out;
  for (const char* key :
       {"scene", "kind", "solver", "engine", "mode", "converged", "diverged", "divergence_reason",
        "steps_run", "steps_to_converge", "max_limit_violation_deg", "short_goals"}) {
    if (summary.contains(key)) out[key] = summary[key];
  }
  return out;
}

// the scene's bone targets, only where it has some (they hold still through a run: a scene's
// schedule moves control points only): "bone_targets" {"orientations": [{bone, quaternion x y z
// w, world<-bone}], "aims": [{bone, point}], "pins": [{bone, alpha, point}]}, points world, rig
// units; the page draws a triad at the bone's head, a line from its head, a marker
void add_bone_targets(const Scene& s, nlohmann::json& out) {
  if (s.orientation_targets.empty() && s.aim_targets.empty() && s.pins.empty()) return;
  const auto vec = [](const Vec3& v) { return nlohmann::json{v.x(), v.y(), v.z()}; };
  nlohmann::json turns = nlohmann::json::array(), aims = nlohmann::json::array(),
                 pins = nlohmann::json::array();
  for (const OrientationTarget& t : s.orientation_targets) {
    const Quat q = t.target_world.normalized();
    turns.push_back({{"bone", t.bone}, {"quaternion", {q.x(), q.y(), q.z(), q.w()}}});
  }
  for (const AimTarget& t : s.aim_targets) {
    aims.push_back({{"bone", t.bone}, {"point", vec(t.point_world)}});
  }
  for (const Pin& p : s.pins) {
    pins.push_back({{"bone", p.bone}, {"alpha", p.alpha}, {"point", vec(p.point_world)}});
  }
  out["bone_targets"] = {{"orientations", turns}, {"aims", aims}, {"pins", pins}};
}

// the scene's ground plane, box obstacles and bone targets, each only where the scene has it (the
// page draws them; other runs' JSON stays as it was)
void add_world(const Scene& s, nlohmann::json& out) {
  // the ground plane
  if (s.collision.ground) {
    const GroundPlane& g = *s.collision.ground;
    out["ground"] = {{"height", g.height},
                     {"normal", {g.normal_world.x(), g.normal_world.y(), g.normal_world.z()}}};
  }
  // the box obstacles, each in its own frame: centre and half extents in rig units, world frame,
  // along the box's own axes, and the rotation turning those axes into the world
  // (physik/model/scene.h BoxObstacle) as a unit quaternion in three.js's order, x y z w
  if (!s.collision.obstacles.empty()) {
    nlohmann::json boxes = nlohmann::json::array();
    for (const BoxObstacle& b : s.collision.obstacles) {
      const Quat q = b.orient_world.normalized();
      boxes.push_back(
          {{"name", b.name},
           {"center", {b.center_world.x(), b.center_world.y(), b.center_world.z()}},
           {"half_extents", {b.half_extents.x(), b.half_extents.y(), b.half_extents.z()}},
           {"quaternion", {q.x(), q.y(), q.z(), q.w()}}});
    }
    out["boxes"] = boxes;
  }
  add_bone_targets(s, out);
}

nlohmann::json run_json(const ViewRun& r) {
  const Rig& rig = r.scene.rig;
  // each bone's rest frame in its parent's (x y z w) and its limits per local axis (rad; null
  // for a free axis): the viewer draws a limit's range in the frame the parent carries
  nlohmann::json rest_in_parent = nlohmann::json::array(), limits = nlohmann::json::array();
  for (int b = 0; b < rig.nbone; ++b) {
    const Quat& q = rig.bone_rest_orient_parent[b];
    rest_in_parent.push_back({q.x(), q.y(), q.z(), q.w()});
    nlohmann::json axes = nlohmann::json::array();
    for (const AxisLimit& l : rig.bone_limit[b]) {
      axes.push_back(l.limited && rig.bone_parent[b] >= 0 ? nlohmann::json({l.min, l.max})
                                                          : nlohmann::json(nullptr));
    }
    limits.push_back(axes);
  }
  nlohmann::json cps = {{"names", nlohmann::json::array()},
                        {"bones", nlohmann::json::array()},
                        {"alphas", nlohmann::json::array()}};
  for (const ControlPoint& c : r.scene.control_points) {
    cps["names"].push_back(c.name);
    cps["bones"].push_back(c.bone);
    cps["alphas"].push_back(c.alpha);
  }
  nlohmann::json out = {
      {"label", r.label},
      {"folder", r.folder},
      {"rig", rig.name},
      {"bones",
       {{"names", rig.bone_name},
        {"parents", rig.bone_parent},
        {"radii", rig.bone_radius},
        {"lengths", rig.bone_length},
        {"rest_in_parent", rest_in_parent},
        {"limits", limits}}},
      {"control_points", cps},
      {"dt", r.scene.params.dt},
      {"frames", r.steps.size()},
      {"rows_recorded", r.rows_recorded},
      {"summary", summary_fields(r.summary)},
      {"notes", r.notes},
      {"steps", b64(r.steps)},
      {"times", b64(r.times)},
      {"kinetic_energy", b64(r.kinetic_energy)},
      {"max_residual", b64(r.max_residual)},
      {"max_residual_point", b64(r.max_residual_point)},
      {"positions", b64(r.positions)},
      {"targets", b64(r.targets)},
      {"limit_excess",
       r.limit_excess.empty() ? nlohmann::json(nullptr) : nlohmann::json(b64(r.limit_excess))},
      {"orientations",
       r.orientations.empty() ? nlohmann::json(nullptr) : nlohmann::json(b64(r.orientations))}};
  add_world(r.scene, out);
  // the contacts of each frame, only where the folder has contacts.csv
  if (r.has_contacts) {
    out["contacts"] = {{"start", b64(r.contact_start)},
                       {"bones", b64(r.contact_bones)},
                       {"values", b64(r.contact_values)}};
  }
  return out;
}

// `text` with each marker of `markers` (in order of appearance) replaced by its content;
// contents are never scanned again, so no data can inject a marker
std::string fill_template(const std::string& text,
                          const std::vector<std::pair<std::string, const std::string*>>& markers) {
  std::string out;
  std::size_t at = 0;
  for (const auto& [marker, content] : markers) {
    const std::size_t k = text.find(marker, at);
    if (k == std::string::npos) throw std::logic_error("viewer/page.html: no marker " + marker);
    out.append(text, at, k - at);
    out += *content;
    at = k + marker.size();
  }
  out.append(text, at, std::string::npos);
  return out;
}

}  // namespace

ThreeJs load_three_js() {
  ThreeJs t;
  const char* env = std::getenv("PHYSIK_THREE_DIR");
  t.folder = env && *env ? env : PHYSIK_THREE_DIR_DEFAULT;
  const std::string three_path = t.folder + "/three.min.js";
  const std::string orbit_path = t.folder + "/examples/js/controls/OrbitControls.js";
  t.three = read_text(three_path);
  t.orbit_controls = read_text(orbit_path);
  const std::string key = "REVISION=\"";
  const std::size_t k = t.three.find(key);
  t.revision =
      k == std::string::npos
          ? std::string("unknown")
          : t.three.substr(k + key.size(), t.three.find('"', k + key.size()) - k - key.size());
  if (t.revision != kThreeRevision) {
    throw_input_error(three_path, "", "REVISION",
                      "three.js r" + t.revision + ": the viewer is written for r" + kThreeRevision +
                          " (Debian's libjs-three)");
  }
  check_inlinable(t.three, three_path);
  check_inlinable(t.orbit_controls, orbit_path);
  return t;
}

std::string view_data_json(const std::vector<ViewRun>& runs, const std::string& title) {
  nlohmann::json doc = {{"title", title},
                        {"generator", std::string("physik view ") + kVersion},
                        {"three_revision", kThreeRevision},
                        {"runs", nlohmann::json::array()}};
  for (const ViewRun& r : runs) doc["runs"].push_back(run_json(r));
  return script_safe(doc.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
}

std::string view_page_html(const std::vector<ViewRun>& runs, const std::string& title,
                           const ThreeJs& three) {
  check_inlinable(kViewerJs, "viewer/viewer.js");
  const std::string title_html = html_escape(title);
  const std::string viewer_js = kViewerJs;
  const std::string data = view_data_json(runs, title);
  return fill_template(kPageHtml, {{"@TITLE@", &title_html},
                                   {"/*@THREE@*/", &three.three},
                                   {"/*@ORBIT@*/", &three.orbit_controls},
                                   {"/*@VIEWER@*/", &viewer_js},
                                   {"/*@DATA@*/", &data}});
}

std::size_t write_view_page(const std::vector<std::string>& folders, const ViewOptions& o,
                            const std::string& out) {
  if (folders.empty()) throw_input_error("RUN_DIR", "", "", "give at least one run folder");
  if (!o.labels.empty() && o.labels.size() != folders.size()) {
    throw_input_error("--label", "", "",
                      std::to_string(o.labels.size()) + " labels for " +
                          std::to_string(folders.size()) + " run folders");
  }
  const std::vector<std::string> labels = o.labels.empty() ? default_labels(folders) : o.labels;
  std::vector<ViewRun> runs;
  for (std::size_t k = 0; k < folders.size(); ++k) {
    runs.push_back(read_run_folder(folders[k], o.max_frames));
    runs.back().label = labels[k];
  }
  check_overlay(runs);
  // after the folders (a default --out lies in the first), before the page is assembled
  check_output_file(out, "--out");
  const ThreeJs three = load_three_js();
  std::string title = o.title;  // by default the labels, "a vs b vs c"
  for (std::size_t j = 0; o.title.empty() && j < labels.size(); ++j) {
    title += (j ? " vs " : "") + labels[j];
  }
  const std::string html = view_page_html(runs, title, three);
  std::ofstream file = open_output_file(out, "--out");
  file << html;
  file.close();
  if (!file) throw_input_error(out, "", "--out", "could not write the whole page");
  return html.size();
}

}  // namespace physik::viewer
