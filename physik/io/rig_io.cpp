#include "physik/io/rig_io.h"

#include <algorithm>
#include <cmath>

#include "physik/io/axis_limits.h"
#include "physik/io/source_skeleton_io.h"
#include "physik/model/errors.h"
#include "physik/model/names.h"

namespace physik {

namespace {

const char* const kAxisName[3] = {"x", "y", "z"};

// the rig's fallbacks for bones that give none (mass and radius: the original code's values)
struct BoneDefaults {
  double mass_per_length = 1.0;   // kg per rig unit
  double radius = 0.5;            // rig units, the inertia cylinder's
  double collision_radius = 0.0;  // rig units; 0 = kCollisionRadiusPerLength x the bone's length
};

void read_mass(const Json& b, const JsonContext& ctx, const BoneDefaults& d, BoneSpec& s);

// a collision radius as given (absent: `fallback`); a given one must be positive
double read_collision_radius(const Json& obj, const JsonContext& ctx, double fallback) {
  if (!obj.contains("collision_radius")) return fallback;
  const double r = ctx.number(obj, "collision_radius");
  if (!(r > 0.0)) ctx.fail("collision_radius", "must be positive");
  return r;
}

BoneSpec bone_from_json(const Json& b, const JsonContext& ctx, const BoneDefaults& d) {
  ctx.require_object(b, "");
  ctx.only_keys(b, {"name", "parent", "head", "tail", "rest_frame", "roll_deg", "limits_deg",
                    "mass_per_length", "mass", "radius", "inertia_local", "collision_radius",
                    "weld", "segment", "forward", "comment"});
  BoneSpec s;
  s.name = ctx.string(b, "name");  // checked by build_rig, which names the bone by its index
  const Json& parent = ctx.require(b, "parent");
  if (parent.is_null()) {
    s.parent.clear();
  } else if (parent.is_string()) {
    s.parent = parent.get<std::string>();
    if (s.parent.empty()) ctx.fail("parent", "empty name (use null for the root)");
    ctx.check_name(s.parent, "parent");
  } else {
    ctx.fail("parent", "expected a bone name or null");
  }
  s.head_world = ctx.vec3(b, "head");
  s.tail_world = ctx.vec3(b, "tail");
  if ((s.tail_world - s.head_world).norm() <= 1e-9) {
    ctx.fail("tail", "zero-length bone (head and tail coincide)");
  }

  if (b.contains("rest_frame") && b.contains("roll_deg")) {
    ctx.fail("rest_frame", "give either rest_frame or roll_deg, not both");
  }
  if (b.contains("rest_frame")) {
    const Json& f = b["rest_frame"];
    if (!f.is_array() || f.size() != 3) {
      ctx.fail("rest_frame", "expected three axes [[x],[y],[z]]");
    }
    for (int c = 0; c < 3; ++c) {
      s.rest_frame_world.col(c) = ctx.vec3_value(f[c], "rest_frame[" + std::to_string(c) + "]");
    }
  } else {
    const double roll = deg2rad(ctx.number_or(b, "roll_deg", 0.0));
    s.rest_frame_world = rest_frame_from_roll(s.head_world, s.tail_world, roll);
  }

  if (b.contains("limits_deg")) s.limit = parse_axis_limits(b["limits_deg"], ctx, "limits_deg");
  if (b.contains("weld")) {
    s.weld = ctx.string(b, "weld");
    if (s.weld.empty()) ctx.fail("weld", "empty name (leave the key out for a bone that turns)");
  }
  read_mass(b, ctx, d, s);
  s.collision_radius = read_collision_radius(b, ctx, d.collision_radius);
  // the human template's segment and forward axis (checked by build_rig)
  s.segment = ctx.string_or(b, "segment", "");
  if (b.contains("forward")) {
    s.forward_local = ctx.vec3(b, "forward");
    // (stableNorm: [0, 1e155, 0] squares past the largest double, and normalizes to zero)
    if (!(s.forward_local.stableNorm() > 1e-9)) ctx.fail("forward", "must be a nonzero vector");
  }
  return s;
}

// mass (or mass per length), radius and explicit moments of a bone whose head and tail are read
void read_mass(const Json& b, const JsonContext& ctx, const BoneDefaults& d, BoneSpec& s) {
  const double length = (s.tail_world - s.head_world).norm();
  if (b.contains("mass") && b.contains("mass_per_length")) {
    ctx.fail("mass", "give either mass or mass_per_length, not both");
  }
  if (b.contains("mass")) {
    s.mass = ctx.number(b, "mass");
    if (!(s.mass > 0.0)) ctx.fail("mass", "must be positive");
  } else {
    const double mpl = ctx.number_or(b, "mass_per_length", d.mass_per_length);
    if (!(mpl > 0.0)) ctx.fail("mass_per_length", "must be positive");
    s.mass = mpl * length;
  }
  s.radius = ctx.number_or(b, "radius", d.radius);
  if (!(s.radius > 0.0)) ctx.fail("radius", "must be positive");
  if (b.contains("inertia_local")) {
    s.inertia_local = ctx.vec3(b, "inertia_local");
    if (!(s.inertia_local.minCoeff() > 0.0)) ctx.fail("inertia_local", "moments must be positive");
  }
}

// the free text: comment, units, and source (one note, or a list of notes)
void read_notes(const Json& doc, const JsonContext& top, Rig& rig) {
  // comment and units are kept when they are text (any other value is free text too, unread)
  if (doc.contains("comment") && doc["comment"].is_string()) rig.comment = doc["comment"];
  if (doc.contains("units") && doc["units"].is_string()) rig.units = doc["units"];
  if (!doc.contains("source")) return;
  const Json& src = doc["source"];
  if (src.is_string()) {
    rig.source = {src.get<std::string>()};
    return;
  }
  if (!src.is_array()) top.fail("source", "expected a note or a list of notes (strings)");
  for (std::size_t i = 0; i < src.size(); ++i) {
    if (!src[i].is_string()) top.fail("source[" + std::to_string(i) + "]", "expected a string");
    rig.source.push_back(src[i].get<std::string>());
  }
}

// collision_exclude: [[bone, bone], ...], pairs of the rig's bones whose capsules never collide
void read_collision_exclude(const Json& doc, const JsonContext& top, Rig& rig) {
  if (!doc.contains("collision_exclude")) return;
  const Json& ex = doc["collision_exclude"];
  if (!ex.is_array()) top.fail("collision_exclude", "expected an array of [bone, bone] pairs");
  std::vector<std::pair<std::string, std::string>> pairs;
  for (std::size_t i = 0; i < ex.size(); ++i) {
    const Json& e = ex[i];
    if (!e.is_array() || e.size() != 2 || !e[0].is_string() || !e[1].is_string()) {
      top.fail("collision_exclude[" + std::to_string(i) + "]",
               "expected a pair of bone names [\"a\", \"b\"]");
    }
    pairs.emplace_back(e[0].get<std::string>(), e[1].get<std::string>());
  }
  set_collision_exclude(rig, pairs, top.file);
}

// the value most bones share (the first of the most common on ties); `values` not empty
double most_common(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  double best = values[0];
  std::size_t best_count = 0;
  for (std::size_t i = 0; i < values.size();) {
    std::size_t j = i;
    while (j < values.size() && values[j] == values[i]) ++j;
    if (j - i > best_count) {
      best_count = j - i;
      best = values[i];
    }
    i = j;
  }
  return best;
}

// a bone's collision radius is the default fraction of its length (what a bone that names none
// gets when the defaults name none either)
bool fraction_collision_radius(const Rig& rig, int i) {
  const double cr0 = kCollisionRadiusPerLength * rig.bone_length[i];
  return std::abs(rig.bone_collision_radius[i] - cr0) <= 1e-12 * cr0;
}

// the defaults the writer names: the radius most bones share, and the collision radius most
// bones share (none when most have the default fraction of their length); each bone then
// names only the values that differ
BoneDefaults shared_defaults(const Rig& rig) {
  BoneDefaults d;
  d.radius = most_common(rig.bone_radius);
  std::vector<double> explicit_cr;
  for (int i = 0; i < rig.nbone; ++i) {
    if (!fraction_collision_radius(rig, i)) explicit_cr.push_back(rig.bone_collision_radius[i]);
  }
  if (2 * explicit_cr.size() > static_cast<std::size_t>(rig.nbone)) {
    const double cr = most_common(explicit_cr);
    std::size_t count = 0;
    for (double v : explicit_cr) count += v == cr ? 1 : 0;
    if (2 * count > static_cast<std::size_t>(rig.nbone)) d.collision_radius = cr;
  }
  return d;
}

}  // namespace

Rig rig_from_json(const Json& doc, const std::string& source) {
  JsonContext top{source, ""};
  top.require_object(doc, "");
  top.only_keys(doc, {"name", "comment", "source", "units", "root", "defaults", "bones",
                      "collision_exclude", "source_skeleton"});
  RootJoint root = RootJoint::kFree;
  if (doc.contains("root")) {
    const std::string r = top.string(doc, "root");
    if (r == "free") {
      root = RootJoint::kFree;
    } else if (r == "pinned") {
      root = RootJoint::kPinned;
    } else if (r == "fixed") {
      root = RootJoint::kFixed;
    } else {
      top.fail("root", "expected \"free\", \"pinned\" or \"fixed\", got \"" + r + "\"");
    }
  }
  BoneDefaults defaults;
  if (doc.contains("defaults")) {
    const Json& d = doc["defaults"];
    JsonContext dctx{source, "defaults"};
    dctx.require_object(d, "defaults");
    dctx.only_keys(d, {"mass_per_length", "radius", "collision_radius"});
    defaults.mass_per_length = dctx.number_or(d, "mass_per_length", defaults.mass_per_length);
    defaults.radius = dctx.number_or(d, "radius", defaults.radius);
    if (!(defaults.mass_per_length > 0.0)) dctx.fail("mass_per_length", "must be positive");
    if (!(defaults.radius > 0.0)) dctx.fail("radius", "must be positive");
    defaults.collision_radius = read_collision_radius(d, dctx, 0.0);
  }
  const Json& bones = top.require(doc, "bones");
  if (!bones.is_array()) top.fail("bones", "expected an array of bones");
  std::vector<BoneSpec> specs;
  for (std::size_t i = 0; i < bones.size(); ++i) {
    std::string element = "bones[" + std::to_string(i) + "]";
    // a name that is not printable stays out of the element (build_rig says why)
    if (bones[i].is_object() && bones[i].contains("name") && bones[i]["name"].is_string() &&
        name_problem(bones[i]["name"].get<std::string>()).empty()) {
      element += " '" + bones[i]["name"].get<std::string>() + "'";
    }
    specs.push_back(bone_from_json(bones[i], JsonContext{source, element}, defaults));
  }
  Rig rig = build_rig(specs, source, top.name_or(doc, "name", ""), root);
  read_notes(doc, top, rig);
  read_collision_exclude(doc, top, rig);
  read_source_skeleton(doc, source, rig);
  return rig;
}

Rig rig_from_json_text(const std::string& text, const std::string& source) {
  return rig_from_json(parse_json_text(text, source), source);
}

Rig load_rig(const std::string& path) {
  return rig_from_json(read_json_file(path), path);
}

Json rig_to_json(const Rig& rig) {
  const BoneDefaults d = shared_defaults(rig);
  Json bones = Json::array();
  for (int i = 0; i < rig.nbone; ++i) {
    Json b;
    b["name"] = rig.bone_name[i];
    b["parent"] = rig.bone_parent[i] < 0 ? Json(nullptr) : Json(rig.bone_name[rig.bone_parent[i]]);
    const Vec3& h = rig.bone_rest_head_world[i];
    const Vec3& t = rig.bone_rest_tail_world[i];
    b["head"] = {h.x(), h.y(), h.z()};
    b["tail"] = {t.x(), t.y(), t.z()};
    const Mat3 f = rig.bone_rest_orient_world[i].toRotationMatrix();
    b["rest_frame"] = Json::array();
    for (int c = 0; c < 3; ++c) b["rest_frame"].push_back({f(0, c), f(1, c), f(2, c)});
    Json lim = Json::object();
    for (int a = 0; a < 3; ++a) {
      const AxisLimit& l = rig.bone_limit[i][a];
      if (l.limited) lim[kAxisName[a]] = {rad2deg(l.min), rad2deg(l.max)};
    }
    if (!lim.empty()) b["limits_deg"] = lim;
    if (rig.bone_weld[i] >= 0) b["weld"] = rig.bone_name[rig.bone_weld[i]];
    if (!rig.bone_segment[i].empty()) b["segment"] = rig.bone_segment[i];
    const Vec3& fw = rig.bone_forward_local[i];
    if (!fw.isZero()) b["forward"] = {fw.x(), fw.y(), fw.z()};
    b["mass"] = rig.bone_mass[i];
    if (rig.bone_radius[i] != d.radius) b["radius"] = rig.bone_radius[i];
    // explicit moments only where they are not the cylinder's
    const Vec3& in = rig.bone_inertia_local[i];
    const Vec3 cyl = cylinder_inertia(rig.bone_mass[i], rig.bone_radius[i], rig.bone_length[i]);
    if ((in - cyl).norm() > 1e-12 * cyl.norm()) b["inertia_local"] = {in.x(), in.y(), in.z()};
    // the collision radius only where the defaults do not give it
    const double cr = rig.bone_collision_radius[i];
    if (d.collision_radius > 0.0 ? cr != d.collision_radius : !fraction_collision_radius(rig, i)) {
      b["collision_radius"] = cr;
    }
    bones.push_back(b);
  }
  Json doc;
  if (!rig.name.empty()) doc["name"] = rig.name;
  if (rig.root_joint != RootJoint::kFree) doc["root"] = to_string(rig.root_joint);
  if (!rig.comment.empty()) doc["comment"] = rig.comment;
  if (!rig.units.empty()) doc["units"] = rig.units;
  if (rig.source.size() == 1) doc["source"] = rig.source[0];
  if (rig.source.size() > 1) doc["source"] = rig.source;
  doc["defaults"] = {{"radius", d.radius}};
  if (d.collision_radius > 0.0) doc["defaults"]["collision_radius"] = d.collision_radius;
  doc["bones"] = bones;
  if (!rig.collision_exclude.empty()) {
    Json ex = Json::array();
    for (const auto& [a, b] : rig.collision_exclude) {
      ex.push_back({rig.bone_name[a], rig.bone_name[b]});
    }
    doc["collision_exclude"] = ex;
  }
  if (!rig.source_skeleton.empty()) doc["source_skeleton"] = source_skeleton_to_json(rig);
  return doc;
}

}  // namespace physik
