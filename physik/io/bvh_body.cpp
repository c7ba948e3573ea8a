// The body inside a converted BVH skeleton (bvh_body.h).
#include "physik/io/bvh_body.h"

#include <cmath>
#include <sstream>

#include "physik/io/bvh.h"
#include "physik/model/errors.h"
#include "physik/model/message_number.h"

namespace physik {

namespace {

// every joint as a pivot in file units and file axes (for heights: lengths do not turn)
std::vector<PivotNode> file_nodes(const BvhFile& bvh) {
  std::vector<Quat> rot;
  std::vector<Vec3> pos;
  bvh_world(bvh, -1, rot, pos);
  std::vector<PivotNode> nodes(bvh.joints.size());
  for (std::size_t j = 0; j < nodes.size(); ++j) {
    nodes[j].name = bvh.joints[j].name;
    nodes[j].parent = bvh.joints[j].parent;
    nodes[j].rest_world = pos[j];
    for (const Vec3& e : bvh.joints[j].end_sites) nodes[j].ends_world.push_back(pos[j] + e);
  }
  return nodes;
}

// file units: along the body's up (a human), else along the rig's Z under options.axes
double file_height(const BvhFile& bvh, const BvhImportOptions& options, const BvhBody& body) {
  const std::vector<PivotNode> nodes = file_nodes(bvh);
  if (body.human)
    return human_body_axes(nodes, inherit_segments(nodes, body.match.node_segment)).height;
  const Quat a = bvh_axes_to_rig(options.axes);
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const PivotNode& n : nodes) {
    for (const Vec3* p : {&n.rest_world})
      lo = std::min(lo, (a * *p).z()), hi = std::max(hi, (a * *p).z());
    for (const Vec3& e : n.ends_world)
      lo = std::min(lo, (a * e).z()), hi = std::max(hi, (a * e).z());
  }
  return nodes.empty() ? 0.0 : hi - lo;
}

// the names against the table (the compiled-in one, or the user's --mapping file)
void match_names(const BvhFile& bvh, const BvhImportOptions& options, BvhBody& body) {
  std::vector<std::string> names;
  for (const BvhJoint& j : bvh.joints) names.push_back(j.name);
  if (options.mapping.empty()) {
    body.match = match_skeleton(names, default_name_table());
  } else {
    body.match = match_skeleton(names, load_name_table(options.mapping), true);
  }
  body.human = body.match.human;
}

std::string joined(const std::vector<std::string>& items) {
  std::string out;
  for (const std::string& s : items) out += (out.empty() ? "" : ", ") + s;
  return out;
}

// the human unit rule (bvh_body.h "Units")
void unit_rule(BvhBody& body) {
  const double h = body.height_file * body.scale;
  if (!body.human || !(body.height_file > 0.0) || (h >= kHumanHeightMin && h <= kHumanHeightMax)) {
    return;
  }
  struct Unit {
    const char* name;
    double metres;
  };
  const Unit units[] = {
      {"metres", 1.0},    {"decimetres", 0.1},   {"CMU's unit (1/0.45 inch, 5.64 cm)", 0.0564444},
      {"inches", 0.0254}, {"centimetres", 0.01}, {"millimetres", 0.001}};
  const Unit* best = nullptr;
  for (const Unit& u : units) {
    const double m = body.height_file * u.metres;
    if (m < kHumanHeightMin || m > kHumanHeightMax) continue;
    if (!best || std::abs(m - kReferenceHeight) <
                     std::abs(body.height_file * best->metres - kReferenceHeight)) {
      best = &u;
    }
  }
  std::ostringstream s;
  s << "a human figure " << message_number(h) << " rig units tall (rig units are read as metres; "
    << message_number(body.height_file) << " file units from the feet to the head) ";
  if (best) {
    body.suggested_scale = best->metres;
    s << "looks like a file in " << best->name << ": --scale " << best->metres << " makes it "
      << message_number(body.height_file * best->metres) << " m";
  } else {
    body.suggested_scale = kReferenceHeight / body.height_file;
    s << "fits no unit of length: --scale " << message_number(body.suggested_scale)
      << " makes it the reference adult's " << kReferenceHeight << " m";
  }
  s << " (or --height H for H metres)";
  body.unit_warning = s.str();
}

}  // namespace

const char* to_string(BodyKind body) {
  switch (body) {
    case BodyKind::kGeneric:
      return "generic";
    case BodyKind::kHuman:
      return "human";
    case BodyKind::kAuto:
      return "auto";
  }
  return "?";
}

BvhBody plan_bvh_body(const BvhFile& bvh, const std::string& source,
                      const BvhImportOptions& options) {
  BvhBody body;
  if (options.height != 0.0 && !(options.height > 0.0 && std::isfinite(options.height))) {
    throw_input_error(
        "--height", "", "",
        "must be a positive finite number (metres), got " + message_number(options.height));
  }
  if (options.body != BodyKind::kGeneric) match_names(bvh, options, body);
  if (options.body == BodyKind::kHuman && !body.human) {
    throw_input_error(
        "--body", "", "",
        "human: " + source + " is not a human skeleton by its joint names (" +
            (body.match.convention.empty()
                 ? std::string("no convention of the table names its joints")
                 : "the " + body.match.convention + " names " + std::to_string(body.match.named) +
                       " of its " + std::to_string(bvh.joints.size()) + " joints") +
            "; missing: " + joined(body.match.missing) +
            "); --mapping FILE names them (models/human/joint_names.json's form)");
  }
  if (body.human && options.sizing.mass_per_length > 0.0) {
    throw_input_error("--mass-per-length", "", "",
                      "a human body's masses come from de Leva's table (--total-mass scales "
                      "them); --body generic gives rods of a mass per length");
  }
  body.height_file = file_height(bvh, options, body);
  body.scale = options.scale;
  if (options.height > 0.0) {
    if (!(body.height_file > 0.0)) {
      throw_input_error("--height", "", "",
                        source + " has no height to scale: its joints all lie at one level");
    }
    body.scale = options.height / body.height_file;
  }
  unit_rule(body);
  if (options.height > 0.0) body.unit_warning.clear();
  return body;
}

namespace {

// the joint's channels hold one value over the clip; `at_rest`: that value is its rest
void constant_channels(const BvhFile& bvh, const BvhJoint& joint, bool& constant, bool& at_rest,
                       Vec3& angles_deg) {
  constant = !bvh.frames.empty();
  at_rest = constant;
  const std::vector<double>& first = constant ? bvh.frames[0] : std::vector<double>{};
  for (std::size_t c = 0; c < joint.channels.size() && constant; ++c) {
    const std::size_t col = joint.channel_start + c;
    for (const std::vector<double>& row : bvh.frames) {
      if (std::abs(row[col] - first[col]) > 1e-9 * std::max(1.0, std::abs(first[col]))) {
        constant = false;
      }
    }
  }
  if (!constant) return;
  const Quat q = bvh_local_rotation(joint, first);
  angles_deg = rotation_vector(q) * (180.0 / kPi);
  const Vec3 t = bvh_local_translation(joint, first);
  at_rest = q.vec().norm() <= 1e-9 * kPi / 180.0 &&
            (t - joint.offset).norm() <= 1e-9 * std::max(1.0, joint.offset.norm());
}

}  // namespace

void weld_constant_joints(const BvhFile& bvh, PivotBones& bones, BvhBody& body) {
  for (std::size_t j = 1; j < bvh.joints.size(); ++j) {
    if (bones.node_specs[j].empty()) continue;  // no bone of its own: nothing turns with it
    bool constant = false, at_rest = false;
    Vec3 angles = Vec3::Zero();
    constant_channels(bvh, bvh.joints[j], constant, at_rest, angles);
    if (!constant) continue;
    const int s = bones.node_specs[j][0];
    BoneSpec& b = bones.specs[s];
    if (!at_rest) {
      std::ostringstream o;
      o.precision(4);
      o << bvh.joints[j].name << " (constant at a turn of " << angles.norm() << " deg)";
      body.constant_not_welded.push_back(o.str());
      continue;
    }
    const int p = bones.spec_parent[s];
    if (p < 0 || !b.weld.empty()) continue;
    // the bone it would be welded to must turn with this joint's parent: a parent joint with no
    // bone of its own (CMU's LeftHand) still turns the joints below it
    if (bones.spec_node[p] != bvh.joints[j].parent) {
      body.constant_not_welded.push_back(bvh.joints[j].name + " (its parent joint '" +
                                         bvh.joints[bvh.joints[j].parent].name +
                                         "' has no bone of its own, and turns)");
      continue;
    }
    b.weld = bones.specs[p].name;
    body.welded_constant.push_back(b.name + " to " + b.weld);
  }
}

void weld_turn_warnings(const BvhFile& bvh, const PivotRig& pr, std::vector<std::string>& out) {
  const Rig& rig = pr.rig;
  std::vector<double> turn(rig.nbone, 0.0);  // rad, the largest turn of each welded bone's joint
  std::vector<Quat> rot;
  std::vector<Vec3> pos;
  for (std::size_t f = 0; f < bvh.frames.size(); ++f) {
    bvh_world(bvh, static_cast<int>(f), rot, pos);
    for (int b = 0; b < rig.nbone; ++b) {
      const int w = rig.bone_weld[b];
      if (w < 0 || pr.bone_node[b] == pr.bone_node[w]) continue;
      turn[b] = std::max(turn[b], rot[pr.bone_node[w]].angularDistance(rot[pr.bone_node[b]]));
    }
  }
  for (int b = 0; b < rig.nbone; ++b) {
    if (!(turn[b] > deg2rad(1e-6))) continue;
    const BvhJoint& j = bvh.joints[pr.bone_node[b]];
    std::ostringstream s;
    s.precision(3);
    s << "joint '" << j.name << "' (line " << j.line << ", bone '" << rig.bone_name[b]
      << "') is welded to '" << rig.bone_name[rig.bone_weld[b]] << "' but turns up to "
      << rad2deg(turn[b]) << " deg against it in the clip: the rig holds its rest shape there, "
      << "so the joints below it move off the file";
    out.push_back(s.str());
  }
}

namespace {

// the --axes hint of a human whose up axis is far from the rig's +Z (bvh_body.h "Axes")
std::string axes_hint(const Vec3& up_world, BvhAxes used) {
  if (up_world.z() >= std::cos(deg2rad(45.0))) return "";
  const Vec3 up_file = bvh_axes_to_rig(used).conjugate() * up_world;
  std::string stands;
  for (BvhAxes option : {BvhAxes::kYUp, BvhAxes::kZUp}) {
    if ((bvh_axes_to_rig(option) * up_file).z() >= std::cos(deg2rad(45.0))) {
      stands = to_string(option);
    }
  }
  std::ostringstream s;
  s.precision(3);
  s << "the figure does not stand: its up axis (the hips to the neck) is (" << up_world.x() << ", "
    << up_world.y() << ", " << up_world.z() << ") in the rig, "
    << rad2deg(std::acos(std::clamp(up_world.z(), -1.0, 1.0))) << " deg from +Z; ";
  if (stands.empty()) {
    s << "it lies along the file's (" << up_file.x() << ", " << up_file.y() << ", " << up_file.z()
      << "), which neither --axes y-up nor --axes z-up turns upright";
  } else {
    s << "convert with --axes " << stands << " (the file's up axis is its "
      << (stands == "y-up" ? "Y" : "Z") << ")";
  }
  return s.str();
}

}  // namespace

void fit_bvh_human(const std::vector<PivotNode>& nodes, const BvhImportOptions& options,
                   PivotBones& bones, BvhBody& body) {
  HumanBodyOptions o;
  o.total_mass = options.sizing.total_mass;
  body.fit = fit_human_body(nodes, inherit_segments(nodes, body.match.node_segment), bones, o);
  body.axes_hint = axes_hint(body.fit.up_world, options.axes);
}

std::vector<std::string> bvh_body_notes(const BvhBody& body) {
  std::vector<std::string> notes;
  std::ostringstream s;
  s.precision(6);
  if (!body.human) {
    if (!body.match.node_segment.empty()) {
      s << "body: generic (not recognised as human: "
        << (body.match.convention.empty() ? std::string("no convention names its joints")
                                          : "the " + body.match.convention + " names " +
                                                std::to_string(body.match.named) + " joints")
        << "; missing " << joined(body.match.missing) << ")";
      notes.push_back(s.str());
    }
  } else {
    s << "body: human (joint names of the " << body.match.convention << " convention, "
      << body.match.named << " of " << body.match.node_segment.size() << " joints named"
      << (body.match.prefix.empty() ? "" : ", prefix '" + body.match.prefix + "' taken off")
      << (body.match.unnamed.empty()
              ? ""
              : "; taking their parent's segment: " + joined(body.match.unnamed))
      << "); masses de Leva 1996 for " << body.fit.total_mass << " kg, ranges AAOS; height "
      << body.fit.height << " rig units";
    notes.push_back(s.str());
    if (!body.fit.welded.empty()) {
      notes.push_back("welded (the rigid pelvis and long bones): " + joined(body.fit.welded));
    }
    if (!body.fit.widened.empty()) {
      notes.push_back("limits widened to start at the rest pose (their torsion band held it): " +
                      joined(body.fit.widened));
    }
    for (const std::string& w : body.fit.warnings) notes.push_back("warning: " + w);
    if (!body.unit_warning.empty()) notes.push_back("warning: " + body.unit_warning);
    if (!body.axes_hint.empty()) notes.push_back("warning: " + body.axes_hint);
  }
  if (!body.welded_constant.empty()) {
    notes.push_back("welded (--weld-constant, constant at rest over the clip): " +
                    joined(body.welded_constant));
  }
  if (!body.constant_not_welded.empty()) {
    notes.push_back("not welded (constant away from rest): " + joined(body.constant_not_welded));
  }
  return notes;
}

}  // namespace physik
