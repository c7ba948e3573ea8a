#include "physik/io/scene_io.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <optional>
#include <sstream>

#include "physik/io/bvh.h"
#include "physik/io/rig_io.h"
#include "physik/io/scene_warnings.h"
#include "physik/model/bone_targets.h"
#include "physik/model/errors.h"
#include "physik/model/input_bounds.h"
#include "physik/model/joint_coordinates.h"
#include "physik/model/names.h"

namespace physik {

namespace {

double non_negative(const JsonContext& ctx, const Json& obj, const std::string& key,
                    double fallback) {
  const double v = ctx.number_or(obj, key, fallback);
  if (v < 0.0) ctx.fail(key, "must not be negative");
  return v;
}

// obj[key] read by the row's kind and checked against its range; absent or null: nothing
std::optional<ParamValue> param_from_json(const JsonContext& ctx, const Json& obj,
                                          const std::string& key, const ParamRow& row) {
  const auto it = obj.find(key);
  if (it == obj.end() || it->is_null()) return std::nullopt;
  ParamValue v = 0.0;
  switch (row.kind) {
    case ParamKind::kReal:
      v = ctx.number_value(*it, key);
      break;
    case ParamKind::kInteger:
      v = ctx.integer(obj, key);
      break;
    case ParamKind::kBoolean:
      v = ctx.boolean_or(obj, key, false) ? 1.0 : 0.0;
      break;
    case ParamKind::kChoice: {
      const std::string name = ctx.choice_or(obj, key, row.choices, "");
      v = static_cast<ParamValue>(std::find(row.choices.begin(), row.choices.end(), name) -
                                  row.choices.begin());
      break;
    }
  }
  const std::string why = range_violation(row, v);
  if (!why.empty()) ctx.fail(key, why);
  return v;
}

// a position (rig units) or velocity (rig units/s) within +-kMaxCoordinate, so squared distances
// and energies stay finite (rig.h)
static_assert(kMaxCoordinate == 1e9, "the message below quotes it");
Vec3 bounded_vec3(const JsonContext& ctx, const Json& obj, const std::string& key) {
  const Vec3 v = ctx.vec3(obj, key);
  if (v.cwiseAbs().maxCoeff() > kMaxCoordinate) {
    ctx.fail(key, "a coordinate beyond +-1e9 (rig.h kMaxCoordinate)");
  }
  return v;
}

// a rotation vector in degrees (rotation_deg) within +-kMaxAngleDeg per component, so its
// length and the turn's sine and cosine are exact enough (input_bounds.h)
static_assert(kMaxAngleDeg == 1e6, "the message below quotes it");
Vec3 bounded_angles(const JsonContext& ctx, const Json& v, const std::string& field) {
  const Vec3 r = ctx.vec3_value(v, field);
  if (!(r.cwiseAbs().maxCoeff() <= kMaxAngleDeg)) {
    ctx.fail(field, "beyond +-1e6 degrees (input_bounds.h kMaxAngleDeg)");
  }
  return r;
}

// a rotation vector in degrees (its direction the axis, its length the angle) as a quaternion
Quat rotation_from_deg(const Vec3& v_deg) {
  const Vec3 v = v_deg * (kPi / 180.0);
  const double angle = v.norm();
  return angle > 0.0 ? Quat(Eigen::AngleAxisd(angle, v / angle)) : Quat::Identity();
}

int control_point_ref(const JsonContext& ctx, const Json& v, const std::vector<ControlPoint>& cps) {
  if (v.is_number_integer()) {
    const int i = v.get<int>();
    if (i < 0 || i >= static_cast<int>(cps.size())) {
      ctx.fail("control_point", "index " + std::to_string(i) + " out of range (" +
                                    std::to_string(cps.size()) + " control points)");
    }
    return i;
  }
  if (v.is_string()) {
    ctx.check_name(v.get<std::string>(), "control_point");
    for (std::size_t i = 0; i < cps.size(); ++i) {
      if (cps[i].name == v.get<std::string>()) return static_cast<int>(i);
    }
    ctx.fail("control_point", "no control point named '" + v.get<std::string>() + "'");
  }
  ctx.fail("control_point", "expected an index or a control point name");
}

// --- the stages of scene_from_json -----------------------------------------------------------

// the rig: the rig object itself (rig_file stays empty), or a path, relative to the scene file
// unless absolute
void read_rig(const JsonContext& top, const Json& doc, const std::string& base_dir, Scene& s) {
  if (doc.contains("rig") && doc["rig"].is_object()) {
    s.rig = rig_from_json(doc["rig"], top.file + ": rig");
    return;
  }
  const std::string rig_ref = top.string(doc, "rig");
  s.rig_ref = rig_ref;
  std::filesystem::path rig_path(rig_ref);
  if (rig_path.is_relative()) rig_path = std::filesystem::path(base_dir) / rig_path;
  s.rig_file = rig_path.lexically_normal().string();
  // exists() throws on a name the filesystem refuses (longer than NAME_MAX): bad input too
  std::error_code ec;
  if (!std::filesystem::exists(s.rig_file, ec)) {
    top.fail("rig",
             "rig file '" + s.rig_file + "' " +
                 (ec ? "cannot be read (" + ec.message() + ")" : std::string("does not exist")));
  }
  s.rig = load_rig(s.rig_file);
}

// a point's own spring, k and cap are checked like the params they stand in for
ControlPoint control_point_from_json(const JsonContext& ctx, const Json& c, const Scene& s) {
  ctx.require_object(c, "");
  ctx.only_keys(c, {"name", "bone", "alpha", "target", "spring", "k", "cap", "comment"});
  ControlPoint cp;
  cp.name = ctx.name_or(c, "name", "");
  const std::string bone = ctx.name(c, "bone");
  cp.bone = s.rig.find_bone(bone);
  if (cp.bone < 0) ctx.fail("bone", unknown_bone(bone, s.rig) + " in rig " + s.rig_file);
  cp.alpha = ctx.number_or(c, "alpha", 1.0);
  if (cp.alpha < 0.0 || cp.alpha > 1.0)
    ctx.fail("alpha", "must lie in [0, 1] (0 = head, 1 = tail)");
  cp.target_world = bounded_vec3(ctx, c, "target");
  if (const auto v = param_from_json(ctx, c, "spring", param_row("control_spring"))) {
    cp.spring = static_cast<SpringLaw>(static_cast<int>(*v));
  }
  cp.k = param_from_json(ctx, c, "k", param_row("control_k"));
  cp.cap = param_from_json(ctx, c, "cap", param_row("control_cap"));
  return cp;
}

void read_control_points(const JsonContext& top, const Json& doc, Scene& s) {
  if (!doc.contains("control_points")) return;
  const Json& cps = doc["control_points"];
  if (!cps.is_array()) top.fail("control_points", "expected an array");
  for (std::size_t i = 0; i < cps.size(); ++i) {
    const JsonContext ctx{top.file, "control_points[" + std::to_string(i) + "]"};
    s.control_points.push_back(control_point_from_json(ctx, cps[i], s));
  }
}

// The bone targets: the JSON's shapes here, their values checked by physik/model/bone_targets.h
// as PosingSession's and the command line's are (the same messages), each error naming the file
// and the element.

// a bone a target names, in the rig
int target_bone(const JsonContext& ctx, const Json& obj, const Scene& s, const TargetSource& at) {
  return target_bone_index(s, ctx.name(obj, "bone"), at);
}

// a turning target's own spring, k and cap: k in N m/rad and cap in rad, checked against the
// control spring's rows' ranges
void read_turn_spring(const JsonContext& ctx, const Json& c, const TargetSource& at,
                      TurnSpring& t) {
  std::optional<std::string> spring;
  std::optional<double> k, cap;
  if (c.contains("spring")) spring = ctx.string(c, "spring");
  if (c.contains("k")) k = ctx.number(c, "k");
  if (c.contains("cap")) cap = ctx.number(c, "cap");
  set_turn_spring(spring, k, cap, at, t);
}

// an orientation target: a bone and its target frame, "quaternion": [w, x, y, z], world<-bone
void read_orientation_targets(const JsonContext& top, const Json& doc, Scene& s,
                              std::vector<std::string>& warnings) {
  if (!doc.contains("orientation_targets")) return;
  const Json& all = doc["orientation_targets"];
  if (!all.is_array()) top.fail("orientation_targets", "expected an array");
  for (std::size_t i = 0; i < all.size(); ++i) {
    const JsonContext ctx{top.file, "orientation_targets[" + std::to_string(i) + "]"};
    const TargetSource at{ctx.file, ctx.element};
    const Json& c = all[i];
    ctx.require_object(c, "");
    ctx.only_keys(c, {"name", "bone", "quaternion", "spring", "k", "cap", "comment"});
    OrientationTarget t;
    t.name = ctx.name_or(c, "name", "");
    t.bone = target_bone(ctx, c, s, at);
    const Json& q = ctx.require(c, "quaternion");
    if (!q.is_array() || q.size() != 4) ctx.fail("quaternion", "expected [w, x, y, z]");
    t.target_world = target_quaternion(
        ctx.number_value(q[0], "quaternion"), ctx.number_value(q[1], "quaternion"),
        ctx.number_value(q[2], "quaternion"), ctx.number_value(q[3], "quaternion"), at, warnings);
    read_turn_spring(ctx, c, at, t);
    s.orientation_targets.push_back(t);
  }
}

// an aim's axis (the bone's frame; default its own, head to tail) and point; the point is checked
// against the bone's head once the initial pose is read (check_aim_points)
void read_aim_targets(const JsonContext& top, const Json& doc, Scene& s) {
  if (!doc.contains("aim_targets")) return;
  const Json& all = doc["aim_targets"];
  if (!all.is_array()) top.fail("aim_targets", "expected an array");
  for (std::size_t i = 0; i < all.size(); ++i) {
    const JsonContext ctx{top.file, "aim_targets[" + std::to_string(i) + "]"};
    const TargetSource at{ctx.file, ctx.element};
    const Json& c = all[i];
    ctx.require_object(c, "");
    ctx.only_keys(c, {"name", "bone", "point", "axis", "spring", "k", "cap", "comment"});
    AimTarget t;
    t.name = ctx.name_or(c, "name", "");
    t.bone = target_bone(ctx, c, s, at);
    t.point_world = bounded_vec3(ctx, c, "point");
    // no axis: the bone's forward axis where the rig's human template gives it one, else +Y
    t.axis_bone = c.contains("axis") ? ctx.vec3(c, "axis") : default_aim_axis(s.rig, t.bone);
    read_turn_spring(ctx, c, at, t);
    s.aim_targets.push_back(t);
  }
}

// a pin's point: given, or (pin_at_start) where it is in the initial pose
void read_pins(const JsonContext& top, const Json& doc, Scene& s, std::vector<bool>& pin_at_start) {
  if (!doc.contains("pins")) return;
  const Json& all = doc["pins"];
  if (!all.is_array()) top.fail("pins", "expected an array");
  for (std::size_t i = 0; i < all.size(); ++i) {
    const JsonContext ctx{top.file, "pins[" + std::to_string(i) + "]"};
    const TargetSource at{ctx.file, ctx.element};
    const Json& c = all[i];
    ctx.require_object(c, "");
    ctx.only_keys(c, {"name", "bone", "alpha", "point", "k", "comment"});
    Pin pin;
    pin.name = ctx.name_or(c, "name", "");
    pin.bone = target_bone(ctx, c, s, at);
    pin.alpha = ctx.number_or(c, "alpha", 0.0);
    pin_at_start.push_back(!c.contains("point"));
    if (c.contains("point")) pin.point_world = bounded_vec3(ctx, c, "point");
    if (c.contains("k")) pin.k = ctx.number(c, "k");
    check_pin(s, pin, at);
    s.pins.push_back(pin);
  }
}

// one target of a kind per bone (as PosingSession and the command line keep them)
template <class Target>
void check_one_per_bone(const Scene& s, const std::vector<Target>& list, const char* kind) {
  for (std::size_t i = 0; i < list.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      if (list[j].bone != list[i].bone) continue;
      throw_input_error(s.file, std::string(kind) + "[" + std::to_string(i) + "]", "bone",
                        "a second target for bone '" + s.rig.bone_name[list[i].bone] + "' (" +
                            kind + "[" + std::to_string(j) +
                            "] is the first): one of a kind per bone");
    }
  }
}

// after the initial pose: each aim's axis, and its point off its bone's head at the start
void check_aim_points(Scene& s) {
  if (s.aim_targets.empty()) return;
  const BoneFrames f = forward_kinematics(s.rig, s.initial_pose);
  for (std::size_t i = 0; i < s.aim_targets.size(); ++i) {
    check_aim_target(s, f, s.aim_targets[i], {s.file, "aim_targets[" + std::to_string(i) + "]"});
  }
}

// schedule of target changes, sorted by step
void read_schedule(const JsonContext& top, const Json& doc, Scene& s) {
  if (!doc.contains("schedule")) return;
  const Json& sch = doc["schedule"];
  if (!sch.is_array()) top.fail("schedule", "expected an array");
  for (std::size_t i = 0; i < sch.size(); ++i) {
    const JsonContext ctx{top.file, "schedule[" + std::to_string(i) + "]"};
    ctx.require_object(sch[i], "");
    ctx.only_keys(sch[i], {"step", "control_point", "target", "comment"});
    TargetChange t;
    t.step = ctx.integer(sch[i], "step");
    if (t.step < 0 || t.step >= s.steps) {
      ctx.fail("step", "must lie in [0, steps) = [0, " + std::to_string(s.steps) + ")");
    }
    t.control_point =
        control_point_ref(ctx, ctx.require(sch[i], "control_point"), s.control_points);
    t.target_world = bounded_vec3(ctx, sch[i], "target");
    s.schedule.push_back(t);
  }
  std::stable_sort(s.schedule.begin(), s.schedule.end(),
                   [](const TargetChange& a, const TargetChange& b) { return a.step < b.step; });
}

void read_convergence(const JsonContext& top, const Json& doc, Scene& s) {
  if (!doc.contains("convergence")) return;
  const Json& c = doc["convergence"];
  const JsonContext ctx{top.file, "convergence"};
  ctx.require_object(c, "convergence");
  ctx.only_keys(c, {"residual_tol", "speed_tol", "settle_steps", "stop_when_converged",
                    "stop_at_residual_tol", "divergence_energy"});
  s.convergence.residual_tol = non_negative(ctx, c, "residual_tol", 0.0);
  s.convergence.speed_tol = non_negative(ctx, c, "speed_tol", 0.0);
  s.convergence.settle_steps = ctx.integer_or(c, "settle_steps", s.convergence.settle_steps);
  if (s.convergence.settle_steps < 1) ctx.fail("settle_steps", "must be at least 1");
  s.convergence.stop_when_converged = ctx.boolean_or(c, "stop_when_converged", false);
  s.convergence.stop_at_residual_tol = ctx.boolean_or(c, "stop_at_residual_tol", false);
  s.convergence.divergence_energy = non_negative(ctx, c, "divergence_energy", 0.0);
}

// initial pose from a frame of a clip of the rig's source skeleton: {"bvh": path, "frame": N},
// the path relative to the scene's folder, N from 0 (bvh.h source_clip_pose)
void read_initial_pose_bvh(const JsonContext& ctx, const Json& ip, const std::string& base_dir,
                           Scene& s) {
  ctx.only_keys(ip, {"bvh", "frame"});
  const std::string ref = ctx.string(ip, "bvh");
  std::filesystem::path path(ref);
  if (path.is_relative()) path = std::filesystem::path(base_dir) / path;
  const std::string file = path.lexically_normal().string();
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) {
    ctx.fail("bvh", "cannot read '" + file + "': no such file");
  }
  if (s.rig.source_skeleton.empty()) {
    ctx.fail("bvh",
             "the rig has no source skeleton (a rig made by `physik rig from-bvh` from "
             "this clip's skeleton has one)");
  }
  const BvhFile clip = read_bvh_file(file);
  const std::string mismatch = source_skeleton_mismatch(s.rig.source_skeleton, clip);
  if (!mismatch.empty()) {
    ctx.fail("bvh", "'" + file + "' is not a clip of the rig's source skeleton: " + mismatch);
  }
  const int frame = ctx.integer(ip, "frame");
  const int nframe = static_cast<int>(clip.frames.size());
  if (frame < 0) ctx.fail("frame", "must be 0 (the clip's first frame) or more");
  if (frame >= nframe) {
    ctx.fail("frame", "frame " + std::to_string(frame) + " is past the end of '" + file + "' (" +
                          std::to_string(nframe) + " frames, 0 to " + std::to_string(nframe - 1) +
                          ")");
  }
  BoneFrames scratch;
  checked_clip_pose(s.rig, clip, frame, ctx.file, ctx.element, scratch, s.initial_pose);
  s.initial_source_row = clip.frames[frame];
}

// initial pose: rest, optionally with a root position and per-bone rotation vectors (deg), or a
// frame of a clip
// The exact and implicit schemes start a locked joint on its set (rig.h "Locked axes": a hinge,
// a two-axis joint, a weld by its locks): an initial pose that turns one off it (a clip's elbow
// 15 deg out of its hinge's plane) is moved onto it by init_state, which one warning says, with
// each such joint and its angle (off by more than kOffSetWarnDeg: a file's own rounding is less)
constexpr double kOffSetWarnDeg = 0.1;

void warn_off_joint_sets(const Scene& s, std::vector<std::string>& warnings) {
  if (!s.params.joint_space()) return;  // the paper's scheme holds its locks by springs
  std::string off;
  int count = 0;
  for (int b = 0; b < s.rig.nbone; ++b) {
    const double deg = rad2deg(off_joint_set(s.rig, b, s.initial_pose.bone_local_rotation[b]));
    if (deg <= kOffSetWarnDeg) continue;
    if (++count <= 8) {
      std::ostringstream o;
      o << (count > 1 ? ", " : "") << s.rig.bone_name[b] << " " << std::setprecision(3) << deg
        << " deg off its " << to_string(s.rig.bone_joint_type[b]);
      off += o.str();
    }
  }
  if (count == 0) return;
  if (count > 8) off += " and " + std::to_string(count - 8) + " more";
  warnings.push_back(s.file + ": initial_pose: " + std::to_string(count) +
                     " joint(s) start off their locked axes' set, which the " +
                     to_string(s.params.scheme) +
                     " scheme keeps; the start is the nearest pose on it: " + off +
                     " (the paper's scheme, preset original, keeps such a start and holds the "
                     "locks by torsion springs)");
}

void read_initial_pose(const JsonContext& top, const Json& doc, const std::string& base_dir,
                       Scene& s) {
  s.initial_pose = rest_pose(s.rig);
  if (!doc.contains("initial_pose")) return;
  const Json& ip = doc["initial_pose"];
  const JsonContext ctx{top.file, "initial_pose"};
  ctx.require_object(ip, "initial_pose");
  if (ip.contains("bvh")) {
    read_initial_pose_bvh(ctx, ip, base_dir, s);
    return;
  }
  ctx.only_keys(ip, {"root_head", "rotation_deg"});
  if (ip.contains("root_head")) s.initial_pose.root_head_world = bounded_vec3(ctx, ip, "root_head");
  if (!ip.contains("rotation_deg")) return;
  const Json& rot = ip["rotation_deg"];
  ctx.require_object(rot, "rotation_deg");
  for (auto it = rot.begin(); it != rot.end(); ++it) {
    const std::string bad = name_problem(it.key());
    if (!bad.empty()) ctx.fail("rotation_deg", "a bone name: " + bad);
    const int b = s.rig.find_bone(it.key());
    if (b < 0) ctx.fail("rotation_deg." + it.key(), unknown_bone(it.key(), s.rig));
    s.initial_pose.bone_local_rotation[b] =
        rotation_from_deg(bounded_angles(ctx, *it, "rotation_deg." + it.key()));
  }
}

// --- contacts and gravity ---------------------------------------------------------------------

void read_ground(const JsonContext& top, const Json& doc, Scene& s) {
  if (!doc.contains("ground") || doc["ground"].is_null()) return;
  const Json& g = doc["ground"];
  const JsonContext ctx{top.file, "ground"};
  ctx.require_object(g, "ground");
  ctx.only_keys(g, {"height", "normal", "comment"});
  GroundPlane plane;
  plane.height = ctx.number_or(g, "height", 0.0);
  if (std::abs(plane.height) > kMaxCoordinate) {
    ctx.fail("height", "beyond +-1e9 (rig.h kMaxCoordinate)");
  }
  if (g.contains("normal")) {
    const Vec3 n = bounded_vec3(ctx, g, "normal");
    // a normal far below any coordinate's scale is as good as zero: its direction is round-off
    if (!(n.norm() > 1e-12)) ctx.fail("normal", "zero length: the plane has no direction");
    plane.normal_world = n.normalized();
  }
  s.collision.ground = plane;
}

// a box: centre (rig units, world), half extents (rig units, each > 0), an optional rotation
void read_box(const JsonContext& ctx, const Json& b, BoxObstacle& box) {
  ctx.require_object(b, "box");
  ctx.only_keys(b, {"center", "half_extents", "rotation_deg"});
  box.center_world = bounded_vec3(ctx, b, "center");
  box.half_extents = bounded_vec3(ctx, b, "half_extents");
  if (!(box.half_extents.minCoeff() > 0.0)) {
    ctx.fail("half_extents", "each must be positive (rig units, half the box's side)");
  }
  if (b.contains("rotation_deg")) {
    box.orient_world = rotation_from_deg(bounded_angles(ctx, b["rotation_deg"], "rotation_deg"));
  }
}

// static obstacles, each a named shape (a box is the one shape)
void read_obstacles(const JsonContext& top, const Json& doc, Scene& s) {
  if (!doc.contains("obstacles")) return;
  const Json& obs = doc["obstacles"];
  if (!obs.is_array()) top.fail("obstacles", "expected an array of obstacles");
  for (std::size_t i = 0; i < obs.size(); ++i) {
    const JsonContext ctx{top.file, "obstacles[" + std::to_string(i) + "]"};
    ctx.require_object(obs[i], "");
    for (auto it = obs[i].begin(); it != obs[i].end(); ++it) {
      if (it.key() != "name" && it.key() != "box" && it.key() != "comment") {
        ctx.fail(it.key(), "unknown shape or field (an obstacle has \"name\" and \"box\")");
      }
    }
    BoxObstacle box;
    box.name = ctx.name(obs[i], "name");
    if (box.name.empty()) ctx.fail("name", "must not be empty");
    for (const BoxObstacle& o : s.collision.obstacles) {
      if (o.name == box.name) ctx.fail("name", "duplicate obstacle name '" + box.name + "'");
    }
    const JsonContext box_ctx{top.file, ctx.element + " box"};
    read_box(box_ctx, ctx.require(obs[i], "box"), box);
    s.collision.obstacles.push_back(box);
  }
}

// one [bone, bone] pair of collision_exclude, as (lower index, higher index)
std::pair<int, int> excluded_pair(const JsonContext& top, const Json& e, const std::string& field,
                                  const Rig& rig) {
  if (!e.is_array() || e.size() != 2 || !e[0].is_string() || !e[1].is_string()) {
    top.fail(field, "expected a pair of bone names [\"a\", \"b\"]");
  }
  int b[2];
  for (int k = 0; k < 2; ++k) {
    const std::string name = e[k].get<std::string>();
    top.check_name(name, field);
    b[k] = rig.find_bone(name);
    if (b[k] < 0) top.fail(field, unknown_bone(name, rig));
  }
  if (b[0] == b[1]) {
    top.fail(field, "bone '" + rig.bone_name[b[0]] +
                        "' is paired with itself (an exclusion names two different bones)");
  }
  return {std::min(b[0], b[1]), std::max(b[0], b[1])};
}

// self_collision and the bone pairs it leaves out (bones sharing a joint are left out anyway)
void read_self_collision(const JsonContext& top, const Json& doc, Scene& s) {
  s.collision.self_collision = top.boolean_or(doc, "self_collision", false);
  if (!doc.contains("collision_exclude")) return;
  const Json& ex = doc["collision_exclude"];
  if (!ex.is_array()) top.fail("collision_exclude", "expected an array of [bone, bone] pairs");
  if (!s.collision.self_collision && !ex.empty()) {
    top.fail("collision_exclude", "applies only with \"self_collision\": true");
  }
  auto& pairs = s.collision.excluded_pairs;
  for (std::size_t i = 0; i < ex.size(); ++i) {
    pairs.push_back(
        excluded_pair(top, ex[i], "collision_exclude[" + std::to_string(i) + "]", s.rig));
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
}

void read_contacts_and_gravity(const JsonContext& top, const Json& doc, Scene& s) {
  read_ground(top, doc, s);
  read_obstacles(top, doc, s);
  read_self_collision(top, doc, s);
  if (doc.contains("gravity")) s.gravity_world = bounded_vec3(top, doc, "gravity");
}

}  // namespace

namespace {

// damping and damping_auto are one setting ("damping": 3 or "damping": "auto"): an override of
// either replaces what the file gave for both
bool overridden(const ParamOverrides& overrides, const std::string& name) {
  const bool damping = name == "damping" || name == "damping_auto";
  return overrides.has(name) ||
         (damping && (overrides.has("damping") || overrides.has("damping_auto")));
}

// Refuse explicitly given values the run would not use (ParamRow::conflict), naming where each
// came from: the file's params, or the override.
void check_conflicts(const EngineParams& p, const std::vector<std::string>& from_file,
                     const ParamOverrides& overrides, const std::string& source,
                     const ParamScene& scene) {
  std::vector<std::string> given = from_file;
  // overrides apply in order, later wins: of damping and damping_auto only the last one given
  // stands (--set damping=1 --set damping=auto is auto)
  int last_damping = -1;
  for (std::size_t i = 0; i < overrides.values.size(); ++i) {
    const std::string& name = overrides.values[i].first->name;
    if (name == "damping" || name == "damping_auto") last_damping = static_cast<int>(i);
  }
  for (std::size_t i = 0; i < overrides.values.size(); ++i) {
    const std::string& name = overrides.values[i].first->name;
    const bool damping = name == "damping" || name == "damping_auto";
    if (!damping || static_cast<int>(i) == last_damping) given.push_back(name);
  }
  // an override is the user's latest word: name it first
  const auto conflicts = param_conflicts(p, given, scene);
  for (const auto& [name, why] : conflicts) {
    if (overrides.has(name)) throw_input_error(overrides.source, "", name, why);
  }
  if (!conflicts.empty())
    throw_input_error(source, "params", conflicts[0].first, conflicts[0].second);
}

// The keys scheme replaced (integration, joint_solve), mapped onto scheme and free_rods unless an
// override gives the scheme; a file that gives both forms is refused.
void read_old_scheme_keys(const JsonContext& ctx, const Json& params,
                          const ParamOverrides& overrides, EngineParams& p,
                          std::vector<std::string>& from_file) {
  if (params.is_null()) return;
  const std::string integration = ctx.string_or(params, "integration", "");
  const std::string joint_solve = ctx.string_or(params, "joint_solve", "");
  if (integration.empty() && joint_solve.empty()) return;
  if (params.contains("scheme")) {
    ctx.fail(integration.empty() ? "joint_solve" : "integration",
             "beside \"scheme\", which replaced it: give scheme only");
  }
  if (overrides.has("scheme")) return;
  apply_old_scheme_keys(p, integration, joint_solve, ctx.file, ctx.element);
  from_file.push_back("scheme");
  if (integration == "free-rods") from_file.push_back("free_rods");
}

}  // namespace

EngineParams params_from_json(const Json& params, const std::string& source,
                              const ParamOverrides& overrides, std::vector<std::string>* given_out,
                              const ParamScene& scene) {
  const JsonContext ctx{source, "params"};
  const bool given = !params.is_null();
  if (given) {
    ctx.require_object(params, "params");
    for (auto it = params.begin(); it != params.end(); ++it) {
      if (it.key() != "preset" && it.key() != "integration" && it.key() != "joint_solve" &&
          !find_param(it.key())) {
        ctx.fail(it.key(), unknown_param_reason(it.key()));
      }
    }
  }
  // the base preset (an override swaps it), then the file's values, then the overrides
  const std::string preset = !overrides.preset.empty() ? overrides.preset
                             : given ? ctx.string_or(params, "preset", kDefaultPreset)
                                     : std::string(kDefaultPreset);
  EngineParams p = preset_params(preset, source);
  std::vector<std::string> from_file;  // the rows the file gave, in table order
  read_old_scheme_keys(ctx, params, overrides, p, from_file);
  // "damping": "auto" is damping_auto: true (the damping row keeps the preset's value)
  const bool damping_auto = given && params.contains("damping") && params["damping"].is_string() &&
                            params["damping"].get<std::string>() == "auto";
  if (damping_auto && params.contains("damping_auto")) {
    ctx.fail("damping_auto", "beside \"damping\": \"auto\": give one or the other");
  }
  if (damping_auto && !overridden(overrides, "damping_auto")) {
    p.damping_auto = true;
    from_file.push_back("damping_auto");
  }
  for (const ParamRow& row : param_table()) {
    if (!given || overridden(overrides, row.name)) continue;  // an overridden value is not read
    if (damping_auto && row.name == "damping") continue;
    if (const auto v = param_from_json(ctx, params, row.name, row)) {
      row.set(p, *v);
      from_file.push_back(row.name);
    }
  }
  overrides.apply(p);
  check_conflicts(p, from_file, overrides, source, scene);
  if (given_out) {
    *given_out = from_file;
    for (const auto& [row, v] : overrides.values) given_out->push_back(row->name);
  }
  return p;
}

Json param_value_json(const ParamRow& row, ParamValue v) {
  switch (row.kind) {
    case ParamKind::kReal:
      return v;
    case ParamKind::kInteger:
      return static_cast<int>(v);
    case ParamKind::kBoolean:
      return v != 0.0;
    case ParamKind::kChoice:
      return row.choices.at(static_cast<std::size_t>(v));
  }
  return nullptr;
}

Json params_to_json(const EngineParams& p) {
  Json j = {{"preset", p.preset}};
  const int preset = std::max(0, preset_index(p.preset));
  for (const ParamRow& row : param_table()) {
    // damping auto is written as the scene format says it: "damping": "auto"
    if (row.name == "damping_auto") continue;
    if (row.name == "damping" && p.damping_auto) {
      j[row.name] = "auto";
      continue;
    }
    const ParamValue v = row.get(p);
    if (!row.written_at_default && v == row.defaults[preset]) continue;
    // a value the run does not use, other than the preset's, would be refused when read back
    if (row.conflict && v != row.defaults[preset] && !row.conflict_reason(p).empty()) continue;
    j[row.name] = param_value_json(row, v);
  }
  return j;
}

Json params_as_run_json(const Scene& scene) {
  const EngineParams& p = scene.params;
  Json j = params_to_json(p);
  for (const ParamRow& row : param_table()) {
    // damping_auto is the damping row's "auto"; a row already written stays as it is
    if (row.name == "damping_auto" || j.contains(row.name)) continue;
    // the scheme does not read it, or the scene has nothing for it (no contacts)
    if (!row.conflict_reason(p, param_scene(scene)).empty()) continue;
    j[row.name] = param_value_json(row, row.get(p));
  }
  return j;
}

Json param_table_json() {
  Json rows = Json::array();
  for (const ParamRow& r : param_table()) {
    Json defaults = Json::object();
    for (int i = 0; i < kPresetCount; ++i)
      defaults[kPresetNames[i]] = param_value_json(r, r.defaults[i]);
    Json row = {{"name", r.name},       {"kind", to_string(r.kind)}, {"unit", r.unit},
                {"defaults", defaults}, {"valid", valid_text(r)},    {"doc", r.doc}};
    if (!r.choices.empty()) row["choices"] = r.choices;
    if (r.valid.lo) row["range"].update({{"lo", *r.valid.lo}, {"lo_allowed", r.valid.lo_allowed}});
    if (r.valid.hi) row["range"].update({{"hi", *r.valid.hi}, {"hi_allowed", r.valid.hi_allowed}});
    if (!r.zero_means.empty()) row["zero_means"] = r.zero_means;
    row["tune"] = r.tune ? Json{r.tune->first, r.tune->second} : Json(nullptr);
    rows.push_back(row);
  }
  return {{"presets", kPresetNames}, {"default_preset", kDefaultPreset}, {"params", rows}};
}

Scene scene_from_json(const Json& doc, const std::string& source, const std::string& base_dir,
                      const ParamOverrides& overrides) {
  std::vector<std::string> warnings;  // dropped: this reader's caller takes none
  return scene_from_json(doc, source, base_dir, overrides, warnings);
}

Scene scene_from_json(const Json& doc, const std::string& source, const std::string& base_dir,
                      const ParamOverrides& overrides, std::vector<std::string>& warnings) {
  const JsonContext top{source, ""};
  top.require_object(doc, "");
  top.only_keys(doc, {"name", "comment", "rig", "params", "control_points", "orientation_targets",
                      "aim_targets", "pins", "schedule", "steps", "convergence", "initial_pose",
                      "initial_velocity", "solve", "gravity", "ground", "obstacles",
                      "self_collision", "collision_exclude"});
  if (doc.contains("solve")) solve_options_from_json(doc["solve"], source);  // checked at load
  top.name_or(doc, "name", "");  // a label the run does not use, checked like every name
  Scene s;
  s.file = source;
  read_rig(top, doc, base_dir, s);
  // the contacts first: the parameter rows' conflict rules see them (a contact row without any)
  read_contacts_and_gravity(top, doc, s);
  s.params = params_from_json(doc.contains("params") ? doc["params"] : Json(nullptr), source,
                              overrides, &s.params_given, param_scene(s));
  s.steps = top.integer_or(doc, "steps", s.steps);
  if (s.steps < 1) top.fail("steps", "must be at least 1");
  read_control_points(top, doc, s);
  read_orientation_targets(top, doc, s, warnings);
  check_one_per_bone(s, s.orientation_targets, "orientation_targets");
  read_aim_targets(top, doc, s);
  check_one_per_bone(s, s.aim_targets, "aim_targets");
  std::vector<bool> pin_at_start;
  read_pins(top, doc, s, pin_at_start);
  check_one_per_bone(s, s.pins, "pins");
  read_schedule(top, doc, s);
  read_convergence(top, doc, s);
  read_initial_pose(top, doc, base_dir, s);
  warn_off_joint_sets(s, warnings);
  if (doc.contains("initial_velocity")) {
    s.initial_velocity_world = bounded_vec3(top, doc, "initial_velocity");
  }
  check_aim_points(s);
  if (!s.pins.empty()) {
    const BoneFrames f = forward_kinematics(s.rig, s.initial_pose);
    for (std::size_t i = 0; i < s.pins.size(); ++i) {
      if (pin_at_start[i])
        s.pins[i].point_world = point_on_bone(f, s.pins[i].bone, s.pins[i].alpha);
    }
  }
  check_scene_joints(s);
  return s;
}

SceneSolveOptions solve_options_from_json(const Json& solve, const std::string& source) {
  const JsonContext ctx{source, "solve"};
  ctx.require_object(solve, "solve");
  SceneSolveOptions out;
  for (auto it = solve.begin(); it != solve.end(); ++it) {
    const SolveOptionRow* row = find_solve_option(it.key());
    if (!row) {
      std::string all;
      for (const SolveOptionRow& r : solve_option_table())
        all += (all.empty() ? "" : ", ") + r.name;
      ctx.fail(it.key(), "unknown option (known: " + all + ")");
    }
    SolveOptionValue v;
    switch (row->kind) {
      case SolveOptionKind::kChoice:
        v.text = ctx.string(solve, it.key());
        break;
      case SolveOptionKind::kBoolean:
        v.number = ctx.boolean_or(solve, it.key(), false) ? 1.0 : 0.0;
        break;
      case SolveOptionKind::kInteger:
        v.number = ctx.integer(solve, it.key());
        break;
      case SolveOptionKind::kReal:
        v.number = ctx.number(solve, it.key());
        break;
      case SolveOptionKind::kVec3: {
        const Vec3 g = ctx.vec3(solve, it.key());
        v.vec = {g.x(), g.y(), g.z()};
        break;
      }
    }
    try {
      set_solve_option(out, *row, v, OptionSpelling::kName);
    } catch (const InputError& e) {  // the row's reason, named as the file's field
      const std::string msg = e.what();
      ctx.fail(it.key(), msg.substr(msg.find(": ") + 2));
    }
  }
  return out;
}

SceneSolveOptions load_solve_options(const std::string& scene_path) {
  const Json doc = read_json_file(scene_path);
  if (!doc.is_object() || !doc.contains("solve")) return SceneSolveOptions{};
  return solve_options_from_json(doc["solve"], scene_path);
}

Scene load_scene(const std::string& path) {
  return load_scene(path, ParamOverrides{});
}

Scene load_scene(const std::string& path, const ParamOverrides& overrides) {
  std::vector<std::string> warnings;
  return load_scene(path, overrides, warnings);
}

Scene load_scene(const std::string& path, const ParamOverrides& overrides,
                 std::vector<std::string>& warnings) {
  const Json doc = read_json_file(path);
  const std::string base = std::filesystem::path(path).parent_path().string();
  return scene_from_json(doc, path, base.empty() ? "." : base, overrides, warnings);
}

namespace {

Json vec_json(const Vec3& v) {
  return {v.x(), v.y(), v.z()};
}

// what a turning target gives itself: its spring, k and cap (the rest follows the params), its name
void add_turn_spring_json(const TurnSpring& t, const std::string& name, Json& j) {
  if (t.spring) j["spring"] = to_string(*t.spring);
  if (t.k) j["k"] = *t.k;
  if (t.cap) j["cap"] = *t.cap;
  if (!name.empty()) j["name"] = name;
}

// the orientation targets, aims and pins, only where the scene has them; each gives only what it
// sets itself (the rest follows the params)
void add_bone_targets_json(const Scene& s, Json& out) {
  Json turns = Json::array();
  for (const OrientationTarget& t : s.orientation_targets) {
    const Quat& q = t.target_world;
    Json j = {{"bone", s.rig.bone_name[t.bone]}, {"quaternion", {q.w(), q.x(), q.y(), q.z()}}};
    add_turn_spring_json(t, t.name, j);
    turns.push_back(j);
  }
  Json aims = Json::array();
  for (const AimTarget& t : s.aim_targets) {
    Json j = {{"bone", s.rig.bone_name[t.bone]},
              {"point", vec_json(t.point_world)},
              {"axis", vec_json(t.axis_bone)}};
    add_turn_spring_json(t, t.name, j);
    aims.push_back(j);
  }
  Json pins = Json::array();
  for (const Pin& pin : s.pins) {
    Json j = {{"bone", s.rig.bone_name[pin.bone]},
              {"alpha", pin.alpha},
              {"point", vec_json(pin.point_world)}};
    if (pin.k) j["k"] = *pin.k;
    if (!pin.name.empty()) j["name"] = pin.name;
    pins.push_back(j);
  }
  if (!turns.empty()) out["orientation_targets"] = turns;
  if (!aims.empty()) out["aim_targets"] = aims;
  if (!pins.empty()) out["pins"] = pins;
}

// gravity and the contact settings, only where the scene has them (older scenes stay as written)
void add_contacts_json(const Scene& s, Json& out) {
  if (!s.gravity_world.isZero(0.0)) out["gravity"] = vec_json(s.gravity_world);
  const ContactModel& c = s.collision;
  if (c.ground) {
    out["ground"] = {{"height", c.ground->height}, {"normal", vec_json(c.ground->normal_world)}};
  }
  if (!c.obstacles.empty()) {
    Json obs = Json::array();
    for (const BoxObstacle& b : c.obstacles) {
      const Eigen::AngleAxisd aa(b.orient_world);
      obs.push_back({{"name", b.name},
                     {"box",
                      {{"center", vec_json(b.center_world)},
                       {"half_extents", vec_json(b.half_extents)},
                       {"rotation_deg", vec_json(aa.axis() * aa.angle() * (180.0 / kPi))}}}});
    }
    out["obstacles"] = obs;
  }
  if (c.self_collision) out["self_collision"] = true;
  if (!c.excluded_pairs.empty()) {
    Json ex = Json::array();
    for (const auto& [a, b] : c.excluded_pairs) {
      ex.push_back({s.rig.bone_name[a], s.rig.bone_name[b]});
    }
    out["collision_exclude"] = ex;
  }
}

}  // namespace

namespace {

// the rig's path as scene_to_json writes it (scene_io.h)
std::string rig_path_for(const Scene& s, const std::string& written_to) {
  namespace fs = std::filesystem;
  const fs::path rig = fs::absolute(s.rig_file).lexically_normal();
  if (written_to.empty() || written_to == "-" || s.rig_ref.empty() ||
      fs::path(s.rig_ref).is_absolute()) {
    return rig.string();
  }
  const fs::path folder = fs::absolute(written_to).lexically_normal().parent_path();
  const fs::path relative = rig.lexically_relative(folder);
  return relative.empty() ? rig.string() : relative.string();
}

}  // namespace

Json scene_to_json(const Scene& s, bool rig_inline, const std::string& written_to) {
  Json cps = Json::array();
  for (const ControlPoint& c : s.control_points) {
    Json j = {{"bone", s.rig.bone_name[c.bone]},
              {"alpha", c.alpha},
              {"target", {c.target_world.x(), c.target_world.y(), c.target_world.z()}}};
    // only what the point gives itself: the rest follows the params
    if (c.spring) j["spring"] = to_string(*c.spring);
    if (c.k) j["k"] = *c.k;
    if (c.cap) j["cap"] = *c.cap;
    if (!c.name.empty()) j["name"] = c.name;
    cps.push_back(j);
  }
  Json sch = Json::array();
  for (const TargetChange& t : s.schedule) {
    sch.push_back({{"step", t.step},
                   {"control_point", t.control_point},
                   {"target", {t.target_world.x(), t.target_world.y(), t.target_world.z()}}});
  }
  Json rot = Json::object();
  for (int i = 0; i < s.rig.nbone; ++i) {
    const Vec3 v = rotation_vector(s.initial_pose.bone_local_rotation[i]) * (180.0 / kPi);
    if (v.norm() > 0.0) rot[s.rig.bone_name[i]] = {v.x(), v.y(), v.z()};
  }
  const Vec3& r = s.initial_pose.root_head_world;
  Json out = {
      {"rig",
       rig_inline || s.rig_file.empty() ? rig_to_json(s.rig) : Json(rig_path_for(s, written_to))},
      {"params", params_to_json(s.params)},
      {"control_points", cps},
      {"schedule", sch},
      {"steps", s.steps},
      {"convergence",
       {{"residual_tol", s.convergence.residual_tol},
        {"speed_tol", s.convergence.speed_tol},
        {"settle_steps", s.convergence.settle_steps},
        {"stop_when_converged", s.convergence.stop_when_converged},
        {"stop_at_residual_tol", s.convergence.stop_at_residual_tol},
        {"divergence_energy", s.convergence.divergence_energy}}},
      {"initial_pose", {{"root_head", {r.x(), r.y(), r.z()}}, {"rotation_deg", rot}}},
      {"initial_velocity",
       {s.initial_velocity_world.x(), s.initial_velocity_world.y(), s.initial_velocity_world.z()}}};
  add_bone_targets_json(s, out);
  add_contacts_json(s, out);
  return out;
}

}  // namespace physik
