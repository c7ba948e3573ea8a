// Animation interchange: physik rig from-bvh | to-bvh | limits | from-mjcf, physik bvh convert.
// The formats are documented in physik/bvh.h, physik/joint_limits.h, reference/mjcf_import.h and
// models/README.md.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <iostream>
#include <memory>
#include <sstream>
#include <vector>

#include "cli/commands.h"
#include "physik/io/bvh.h"
#include "physik/io/joint_limits.h"
#include "physik/io/json_fields.h"
#include "physik/io/rig_io.h"
#include "physik/model/errors.h"
#include "physik/model/message_number.h"
#include "physik/model/rig_sizing.h"
#include "reference/mjcf_import.h"

namespace physik::cli {

namespace {

BvhAxes parse_axes(const std::string& s) {
  if (s == "y-up") return BvhAxes::kYUp;
  if (s == "z-up") return BvhAxes::kZUp;
  throw_input_error("--axes", "", "", "expected y-up or z-up, got '" + s + "'");
}

// options are checked before any file is read, so their messages name the option
void check_order_option(const std::string& order) {
  std::string s = order;
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  std::sort(s.begin(), s.end());
  if (s != "XYZ") {
    throw_input_error("--order", "", "", "'" + order + "' is not a permutation of XYZ");
  }
}

void check_scale_option(double scale) {
  if (!(scale > 0.0) || !std::isfinite(scale)) {
    throw_input_error("--scale", "", "", "must be a positive finite number");
  }
}

// --radius, --mass-per-length, --total-mass (rig_sizing.h); checked by the converters. Each one
// given must be positive: 0 (or -0) is what the options are when left out, so a given 0 would
// silently mean "the default" (check_sizing_given says so instead)
struct SizingGiven {
  CLI::Option* radius = nullptr;
  CLI::Option* mass_per_length = nullptr;
  CLI::Option* total_mass = nullptr;
};

SizingGiven add_sizing_options(CLI::App* cmd, SizingOptions& z, const char* default_radius,
                               const char* default_mass) {
  SizingGiven given;
  given.radius = cmd->add_option("--radius", z.radius,
                                 std::string("Every bone's radius and collision radius, rig units "
                                             "(after --scale; positive); default: ") +
                                     default_radius);
  given.mass_per_length = cmd->add_option(
      "--mass-per-length", z.mass_per_length,
      "Every bone's mass per rig unit of its length (kg per rig unit, positive); default: a "
      "rod of the bone's radius at 1000 kg per cubic rig unit (BVH), the model's masses "
      "(MJCF)");
  given.total_mass = cmd->add_option(
      "--total-mass", z.total_mass,
      std::string("Scale every bone's mass so that the rig weighs this (kg, positive); default: ") +
          default_mass);
  return given;
}

void check_sizing_given(const SizingGiven& given, const SizingOptions& z) {
  const auto check = [](const CLI::Option* o, double v, const char* unit) {
    if (o->count() > 0 && !(v > 0.0)) {
      throw_input_error(o->get_name(), "", "",
                        std::string("must be a positive finite number (") + unit + "), got " +
                            message_number(v) + " (leave the option out for the default)");
    }
  };
  check(given.radius, z.radius, "rig units");
  check(given.mass_per_length, z.mass_per_length, "kg per rig unit");
  check(given.total_mass, z.total_mass, "kg");
  check_sizing_options(z);
}

// a list of names on stderr, one line: "<heading> (n): a; b; c"
void print_named(const std::string& command, const std::string& heading,
                 const std::vector<std::string>& items) {
  if (items.empty()) return;
  std::cerr << command << ": " << heading << " (" << items.size() << "):";
  for (std::size_t i = 0; i < items.size(); ++i) std::cerr << (i ? "; " : " ") << items[i];
  std::cerr << "\n";
}

void add_axes_option(CLI::App* cmd, std::string& axes) {
  cmd->add_option("--axes", axes,
                  "y-up: the file is Y up (BVH habit, Blender's default), mapped to the rig's Z "
                  "up; z-up: file axes used as they are")
      ->capture_default_str();
}

// physik rig from-bvh's options
struct FromBvh {
  std::string path, out, axes = "y-up", body = "auto", mapping, root;
  double scale = 1.0;
  double height = 0.0;  // m; 0: not given
  bool weld_constant = false;
  SizingOptions sizing;
  SizingGiven given;
  CLI::Option* scale_option = nullptr;
  CLI::Option* height_option = nullptr;
};

BodyKind parse_body(const std::string& s) {
  if (s == "auto") return BodyKind::kAuto;
  if (s == "human") return BodyKind::kHuman;
  if (s == "generic") return BodyKind::kGeneric;
  throw_input_error("--body", "", "", "expected auto, human or generic, got '" + s + "'");
}

// the options checked before the file is read, so their messages name the option
BvhImportOptions from_bvh_options(const FromBvh& fb) {
  check_scale_option(fb.scale);
  check_sizing_given(fb.given, fb.sizing);
  BvhImportOptions o;
  o.axes = parse_axes(fb.axes);
  o.scale = fb.scale;
  o.sizing = fb.sizing;
  o.body = parse_body(fb.body);
  o.mapping = fb.mapping;
  o.weld_constant = fb.weld_constant;
  if (fb.root == "free" || fb.root == "pinned") {
    o.root = fb.root == "free" ? RootJoint::kFree : RootJoint::kPinned;
  } else if (!fb.root.empty()) {
    throw_input_error("--root", "", "", "expected free or pinned, got '" + fb.root + "'");
  }
  if (fb.height_option->count() > 0) {
    if (!(fb.height > 0.0) || !std::isfinite(fb.height)) {
      throw_input_error(
          "--height", "", "",
          "must be a positive finite number (metres), got " + message_number(fb.height));
    }
    if (fb.scale_option->count() > 0) {
      throw_input_error("--height", "", "",
                        "give --height (the figure's height in metres) or --scale (rig units per "
                        "file unit), not both");
    }
    o.height = fb.height;
  }
  if (!fb.mapping.empty() && o.body == BodyKind::kGeneric) {
    throw_input_error("--mapping", "", "",
                      "names the joints' segments of a human body: --body generic has none");
  }
  return o;
}

// what the body is, its units and axes, on stderr
void report_body(const BvhAnimation& anim, double scale) {
  const Rig& rig = anim.rig();
  const BvhBody& body = anim.body;
  const std::vector<std::string> notes = bvh_body_notes(body);
  for (const std::string& note : notes) std::cerr << "from-bvh: " << note << "\n";
  if (body.human) return;
  double suggested = 0.0;
  const std::string unit = guess_bvh_units(rig.height(), suggested);
  if (!unit.empty()) {
    std::cerr << "from-bvh: warning: a figure " << rig.height()
              << " rig units tall looks like a file in " << unit
              << " (rig units are read as metres): convert it with --scale " << suggested * scale
              << "\n";
  }
}

// physik rig from-bvh
void add_from_bvh(CLI::App* rig) {
  auto fb = std::make_shared<FromBvh>();
  auto* from_bvh = rig->add_subcommand(
      "from-bvh",
      "Rig of a BVH/qBVH file (bones from offsets, End Sites as tails); a skeleton whose joint "
      "names make a human gets a human body (de Leva's masses, AAOS joint ranges, welded "
      "pelvis); prints JSON");
  from_bvh->add_option("FILE", fb->path, "BVH or qBVH file")->required();
  from_bvh->add_option("--out", fb->out, "Write the rig JSON here instead of stdout");
  add_axes_option(from_bvh, fb->axes);
  fb->scale_option =
      from_bvh->add_option("--scale", fb->scale, "Rig units per file unit (e.g. 0.01 for cm)")
          ->capture_default_str();
  fb->height_option = from_bvh->add_option(
      "--height", fb->height,
      "Scale the figure to this height (m: its feet to its head along its up axis for a human, "
      "its extent along the rig's Z otherwise) instead of --scale");
  from_bvh
      ->add_option("--body", fb->body,
                   "auto: a human body when the joint names make one (models/human/"
                   "joint_names.json), else generic; human: insist (exit 2 if the names do "
                   "not make one); generic: rods, no limits")
      ->capture_default_str();
  from_bvh->add_option("--root", fb->root,
                       "The root's joint to the world: free or pinned (turns in place); default: "
                       "pinned when the file's root has no position channels, else free");
  from_bvh->add_option("--mapping", fb->mapping,
                       "Joint-name file naming each joint's segment (the form of models/human/"
                       "joint_names.json) instead of the built-in table");
  from_bvh->add_flag("--weld-constant", fb->weld_constant,
                     "Weld every joint whose channels stay at rest over the whole clip");
  fb->given = add_sizing_options(from_bvh, fb->sizing, "0.14 x the bone's length",
                                 "none (rods); 73 kg for a human body");
  from_bvh->callback([fb] {
    const BvhImportOptions o = from_bvh_options(*fb);
    const BvhAnimation anim = load_bvh(fb->path, o);
    const Rig& rig = anim.rig();
    std::cerr << "from-bvh: " << rig.nbone << " bones, " << anim.poses.size()
              << " frames, max |FK - BVH| = " << anim.max_position_error << " rig units\n";
    std::cerr << "from-bvh: height " << rig.height() << " rig units, mass " << rig.total_mass()
              << " kg\n";
    report_body(anim, anim.body.scale);
    for (const std::string& n : anim.notes) std::cerr << "from-bvh: note: " << n << "\n";
    for (const std::string& w : anim.warnings) std::cerr << "from-bvh: warning: " << w << "\n";
    if (anim.max_position_error > 1e-6 * std::max(1.0, rig.height())) {
      std::cerr << "from-bvh: warning: the rig puts joints up to " << anim.max_position_error
                << " rig units from where the file does (the joints named above: position "
                   "channels on non-root joints, welded joints that turn)\n";
    }
    std::vector<std::string> pairs;
    for (const BoneOverlap& p : anim.rest_overlaps) {
      pairs.push_back(rig.bone_name[p.a] + "/" + rig.bone_name[p.b]);
    }
    print_named("from-bvh", "collision_exclude: bone pairs whose capsules overlap at rest", pairs);
    write_json(rig_to_json(rig), fb->out);
  });
}

// physik rig to-bvh
void add_to_bvh(CLI::App* rig) {
  struct ToBvh {
    std::string path, out, axes = "y-up", order;
    double scale = 1.0;
    bool qbvh = false, own = false;
  };
  auto tb = std::make_shared<ToBvh>();
  auto* to_bvh = rig->add_subcommand(
      "to-bvh",
      "A rig's rest pose as BVH (or qBVH), one frame: on its source skeleton when it has one "
      "(a rig made by `rig from-bvh`: the file's joint names, hierarchy, channel order, units and "
      "axes), else one joint per bone");
  to_bvh->add_option("RIG", tb->path, "Rig file (JSON)")->required();
  to_bvh->add_option("--out", tb->out, "Write here (a .qbvh name writes qBVH) instead of stdout");
  to_bvh->add_flag("--qbvh", tb->qbvh, "Quaternion channels (qBVH)");
  to_bvh->add_option("--order", tb->order,
                     "Euler channel order (default: each source joint's own; ZXY for the rig's "
                     "own skeleton)");
  add_axes_option(to_bvh, tb->axes);
  to_bvh->add_option("--scale", tb->scale, "File units per rig unit (the rig's own skeleton)")
      ->capture_default_str();
  to_bvh->add_flag("--own-skeleton", tb->own, kOwnSkeletonHelp);
  to_bvh->callback([tb] {
    if (!tb->order.empty()) check_order_option(tb->order);
    check_scale_option(tb->scale);
    const Rig r = load_rig(tb->path);
    BvhExportOptions o;
    o.axes = parse_axes(tb->axes);
    o.euler_order = tb->order;
    o.scale = tb->scale;
    o.quaternion = tb->qbvh || is_qbvh_path(tb->out);
    o.source_skeleton = !tb->own;
    if (tb->out.empty() || tb->out == "-") {
      print_bvh_report("<stdout>", write_bvh(r, {}, o, std::cout));
    } else {
      print_bvh_report(tb->out, save_bvh(tb->out, r, {}, o));
    }
  });
}

// physik rig limits
void add_limits(CLI::App* rig) {
  struct Limits {
    std::string rig, limits, out;
  };
  auto lo = std::make_shared<Limits>();
  auto* limits = rig->add_subcommand(
      "limits", "Apply a joint-limit file to a rig by bone name (unknown bone: exit 2)");
  limits->add_option("RIG", lo->rig, "Rig file (JSON)")->required();
  limits->add_option("LIMITS", lo->limits, "Joint-limit file (JSON, see models/README.md)")
      ->required();
  limits->add_option("--out", lo->out, "Write the new rig here instead of stdout");
  limits->callback([lo] {
    Rig r = load_rig(lo->rig);
    apply_joint_limits(r, load_joint_limits(lo->limits));
    write_json(rig_to_json(r), lo->out);
  });
}

// physik rig from-mjcf
void add_from_mjcf(CLI::App* rig) {
  struct FromMjcf {
    std::string path, out, body;
    SizingOptions sizing;
  };
  auto fm = std::make_shared<FromMjcf>();
  auto* from_mjcf = rig->add_subcommand(
      "from-mjcf",
      "Rig of a MuJoCo model (loaded by MuJoCo): bodies -> bones, joint ranges -> "
      "limits, masses and inertias, capsule (or else sphere) geom radii -> bone radius and "
      "collision_radius; prints JSON");
  from_mjcf->add_option("MODEL", fm->path, "MJCF file")->required();
  from_mjcf->add_option("--out", fm->out, "Write the rig JSON here instead of stdout");
  from_mjcf->add_option("--body", fm->body,
                        "Body whose subtree becomes the rig (default: the largest top-level one)");
  const SizingGiven given = add_sizing_options(
      from_mjcf, fm->sizing, "the body's capsule or sphere geom, else 0.14 x the bone's length",
      "the model's");
  from_mjcf->callback([fm, given] {
    check_sizing_given(given, fm->sizing);
    MjcfImportOptions o;
    o.root_body = fm->body;
    o.sizing = fm->sizing;
    const MjcfRig mr = load_mjcf(fm->path, o);
    const MjcfImportReport& r = mr.report;
    std::cerr << "from-mjcf: " << mr.rig().nbone << " bones from " << r.nbody_used << " of "
              << r.nbody_model << " bodies; mass " << r.rig_mass << " kg (model " << r.model_mass
              << " kg)";
    if (!r.skipped_bodies.empty()) {
      std::cerr << "; left out " << r.skipped_bodies.size()
                << " other top-level bodies (first: " << r.skipped_bodies[0]
                << "; choose with --body)";
    }
    std::cerr << "\nfrom-mjcf: dropped: " << r.slide_joints_dropped << " slide joints, "
              << r.unaligned_hinges << " bones freed by unaligned hinges (mapped hinges within "
              << r.max_hinge_misalignment_deg << " deg), " << r.clamped_ranges
              << " ranges clamped to +-180 deg, off-diagonal inertia up to "
              << r.max_offdiag_inertia << " of the largest moment, centre of mass moved up to "
              << r.max_com_shift << ", " << r.mass_floor_bones << " massless bones floored, "
              << r.cylinder_inertia_bones << " bones with cylinder inertia\n";
    print_named("from-mjcf", "slide joints dropped", r.dropped_slides);
    print_named("from-mjcf", "bones freed by unaligned hinges", r.freed_bones);
    print_named("from-mjcf", "ranges clamped to +-180 deg", r.clamped);
    std::ostringstream band;
    band << "limits widened: the rest angle was inside the torsion band (torsion_tolerance "
         << r.fitted_tolerance << "), now at its edge";
    print_named("from-mjcf", band.str(), r.widened_limits);
    print_named("from-mjcf", "collision_exclude: bone pairs whose capsules overlap at rest",
                r.rest_overlaps);
    if (fm->sizing.radius <= 0.0) {
      std::ostringstream fit;
      fit << "no capsule or sphere geom on their body: radius and collision radius "
          << kRadiusPerLength << " x length";
      print_named("from-mjcf", fit.str(), r.bones_fitted_radius);
    }
    write_json(rig_to_json(mr.rig()), fm->out);
  });
}

// physik bvh convert
void add_bvh_convert(CLI::App& app) {
  struct Convert {
    std::string in, out, axes = "y-up", order;
    bool own = false;
  };
  auto co = std::make_shared<Convert>();
  auto* bvh = app.add_subcommand("bvh", "BVH and qBVH animation files");
  bvh->require_subcommand(1);
  auto* convert = bvh->add_subcommand(
      "convert", "Read a BVH/qBVH animation and write it again (qBVH if OUT ends in .qbvh)");
  convert->add_option("IN", co->in, "BVH or qBVH file")->required();
  convert->add_option("OUT", co->out, "Output file (.bvh or .qbvh)")->required();
  convert->add_option("--order", co->order,
                      "Euler channel order of a .bvh output (default: each joint's own; ZXY for "
                      "--own-skeleton)");
  add_axes_option(convert, co->axes);
  convert->add_flag("--own-skeleton", co->own,
                    "Write the rig the file converts to (one joint per bone) instead of the "
                    "file's own skeleton");
  convert->callback([co] {
    if (!co->order.empty()) check_order_option(co->order);
    BvhImportOptions io;
    io.axes = parse_axes(co->axes);
    // the rig is written back at once: its collision exclusions (quadratic in the bones piled at
    // one point) are never read
    io.exclude_rest_overlaps = false;
    const BvhFile file = read_bvh_file(co->in);
    const BvhAnimation anim = bvh_to_rig(file, co->in, io);
    BvhExportOptions o;
    o.axes = io.axes;
    o.euler_order = co->order;
    o.frame_time = anim.frame_time;
    o.quaternion = is_qbvh_path(co->out);
    o.source_skeleton = !co->own;
    // the own skeleton is the rig's: what the conversion could not keep is lost there
    if (co->own) {
      for (const std::string& w : anim.warnings) std::cerr << "bvh convert: warning: " << w << "\n";
    }
    print_bvh_report(co->out, save_bvh(co->out, anim.rig(), anim.poses, o,
                                       co->own ? SourceFrames{} : SourceFrames::of_clip(file)));
    std::cerr << "bvh convert: " << anim.rig().nbone << " bones, " << anim.poses.size()
              << " frames -> " << co->out << "\n";
  });
}

}  // namespace

void print_bvh_report(const std::string& path, const BvhWriteReport& report) {
  for (const std::string& w : report.warnings) {
    std::cerr << "physik: warning: " << path << ": " << w << "\n";
  }
}

void add_interchange_commands(CLI::App& app) {
  CLI::App* rig = app.get_subcommand("rig");
  add_from_bvh(rig);
  add_to_bvh(rig);
  add_limits(rig);
  add_from_mjcf(rig);
  add_bvh_convert(app);
}

}  // namespace physik::cli
