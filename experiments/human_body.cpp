// Study: a human body inside a human skeleton. Four motion-capture skeletons in the shapes users
// bring (experiments/human_skeletons.h: CMU-like with zero-offset children, Mixamo-like,
// MakeHuman-like in decimetres and Z up with fingers, OptiTrack-like in centimetres) converted as
// `rig from-bvh` does (physik/io/bvh_body.h: the joint-name table, the human template of
// physik/model/human_body.h), and then:
//   names    the convention the table finds for each, and the joints it names
//   units    each file read as it is (--scale 1): the --scale the unit rule names; the Z-up file
//            read as Y up: the --axes hint
//   masses   the rig's share of each de Leva row beside the table's (human_template.h)
//   solve    both feet pinned (their heads held where they are), the head's forward axis (the
//            face) turned toward a point 1 m ahead, 0.8 m to the left and 0.3 m up (an aim with no
//            axis: the rig's forward axis), the engine's solve mode (`solve --solver physik`):
//            the hip width (the thighs' heads), the shoulder girdle's base (the clavicles' heads)
//            and the shoulder width (the upper arms' heads) before and after; every limited axis
//            of every bone against its range, past it by at most its torsion band
//            (torsion_tolerance x (max - min)) on the free axes, and each hinge's, two-axis
//            joint's and weld by locks' turn off its joint's set (its locked axes)
//   follow   the clip followed under gravity on a floor at the feet (physik/io/clip_follow.h,
//            the clip_following experiment's settings): the same widths at every clip frame
// Claims (each can say no): every shape recognised; the unit rule names each file's unit (CMU's
// 0.0564444, 0.01 for centimetres, 0.1 for decimetres) and the axes hint names --axes z-up; every
// de Leva row within 20 % of the table's share; the hip width and the girdle's base unchanged to
// 1e-6 m through the solve and the follow; no free axis past its range by more than its band.
// The shoulder width moves with the clavicles' own range (15 deg each way): reported, not
// claimed. Tables: human_body_shapes.csv (one row per shape), human_body_masses.csv (one row per
// shape and de Leva row).
#include <algorithm>
#include <cmath>
#include <sstream>

#include "experiments/experiment.h"
#include "experiments/human_skeletons.h"
#include "experiments/report.h"
#include "experiments/table.h"
#include "physik/engine/engine.h"
#include "physik/io/clip_follow.h"
#include "physik/io/rig_io.h"
#include "physik/io/scene_io.h"
#include "physik/model/joint_angles.h"
#include "physik/model/joint_coordinates.h"
#include "physik/model/params.h"
#include "physik/posing/scene_solve.h"

namespace physik::experiments {

namespace {

namespace hs = human_skeletons;

constexpr double kWidthTol = 1e-6;     // m, the welded widths' claim
constexpr double kMassShareTol = 0.2;  // 1, of the table's share
constexpr int kSolveSteps = 4000;      // the solve's step cap
constexpr int kStepsPerFrame = 4;      // the follow's steps per clip frame
constexpr double kSag = 0.01;          // m, each followed point's sag under its share of weight

// the first bone of a segment that is not welded (-1 for none)
int segment_bone(const Rig& rig, const std::string& segment) {
  for (int b = 0; b < rig.nbone; ++b) {
    if (rig.bone_segment[b] == segment && !rig.welded(b)) return b;
  }
  return -1;
}

// the distance between the heads of the first bones of two segments (rig units)
double width(const Rig& rig, const BoneFrames& f, const char* left, const char* right) {
  const int l = segment_bone(rig, left), r = segment_bone(rig, right);
  return l < 0 || r < 0 ? std::nan("") : (f.head_world[l] - f.head_world[r]).norm();
}

struct Widths {
  double hips = 0.0, girdle = 0.0, shoulders = 0.0;  // rig units
};

Widths widths(const Rig& rig, const BoneFrames& f) {
  // the girdle's base: the clavicles' heads (one point in a CMU skeleton, width 0)
  return {width(rig, f, "thigh.L", "thigh.R"), width(rig, f, "clavicle.L", "clavicle.R"),
          width(rig, f, "upper_arm.L", "upper_arm.R")};
}

// the largest change of each width from `rest` over `frames`
Widths width_change(const Rig& rig, const Widths& rest, const std::vector<BoneFrames>& frames) {
  Widths d;
  for (const BoneFrames& f : frames) {
    const Widths w = widths(rig, f);
    d.hips = std::max(d.hips, std::abs(w.hips - rest.hips));
    d.girdle = std::max(d.girdle, std::abs(w.girdle - rest.girdle));
    d.shoulders = std::max(d.shoulders, std::abs(w.shoulders - rest.shoulders));
  }
  return d;
}

struct Excess {
  double free_deg = 0.0;    // deg, the largest excess past a free axis's range
  double free_band = 0.0;   // 1, that excess over its torsion band (the largest ratio)
  double locked_deg = 0.0;  // deg, the largest turn off a joint's set (its locked axes)
  std::string worst;        // "<bone> <axis>" of the largest free ratio
};

// every limited axis against its range in `pose` (the root and welded bones have none)
Excess limit_excess(const Rig& rig, const Pose& pose, double tolerance) {
  Excess e;
  for (int b = 1; b < rig.nbone; ++b) {
    // a locked joint's turn off its set (joint_coordinates.h off_joint_set; 0 for a ball)
    e.locked_deg =
        std::max(e.locked_deg, rad2deg(off_joint_set(rig, b, pose.bone_local_rotation[b])));
    const Vec3 angles = joint_angles(rig, LockedAxes::kRemoved, b, pose.bone_local_rotation[b]);
    for (int a = 0; a < 3; ++a) {
      const AxisLimit& l = rig.bone_limit[b][a];
      if (!l.limited || l.locked()) continue;
      const double past = std::max({0.0, angles[a] - l.max, l.min - angles[a]});
      const double ratio = past / (tolerance * (l.max - l.min));
      if (ratio > e.free_band) {
        e.free_band = ratio;
        e.worst = rig.bone_name[b] + " " + "xyz"[a];
      }
      e.free_deg = std::max(e.free_deg, rad2deg(past));
    }
  }
  return e;
}

BvhImportOptions options_of(double scale, BvhAxes axes) {
  BvhImportOptions o;
  o.axes = axes;
  o.scale = scale;
  o.body = BodyKind::kAuto;
  return o;
}

}  // namespace

namespace {

// a look: its solve's outcome, the face's angle to its point, the widths' change, the limits
struct LookRun {
  bool converged = false;
  double aim_deg = 0.0;  // deg, the face's angle to its point after the solve
  Widths change;         // rig units, each width's change from rest
  Excess excess;
};

struct ShapeRun {
  std::string name, convention, worst_limit;
  int joints = 0, named = 0, bones = 0, welded = 0;
  double height = 0.0, mass = 0.0, unit_scale = 0.0;
  bool axes_hint = false, follow_diverged = false;
  double round_trip = 0.0;  // the largest channel difference of the clip written back
  Widths rest, follow;
  LookRun ahead, behind;  // the face turned toward a point ahead (in reach), behind (out of it)
  std::vector<HumanMassRow> masses;
};

// the solve: both feet pinned, the face turned toward a point 1 m `forward` (behind for -1),
// 0.8 m to the left and 0.3 m up of the head
SceneSolveResult solve_look(const Rig& rig, const HumanBodyFit& fit, double forward) {
  const BoneFrames rest = forward_kinematics(rig, rest_pose(rig));
  const int head =
      segment_bone(rig, "head") >= 0 ? segment_bone(rig, "head") : segment_bone(rig, "neck");
  const Vec3 point = rest.head_world[head] + forward * fit.forward_world + 0.8 * fit.left_world +
                     0.3 * fit.up_world;
  const nlohmann::json scene = {
      {"rig", rig_to_json(rig)},
      {"params", {{"preset", "robust"}}},
      {"steps", kSolveSteps},
      {"pins",
       {{{"bone", rig.bone_name[segment_bone(rig, "foot.L")]}},
        {{"bone", rig.bone_name[segment_bone(rig, "foot.R")]}}}},
      {"aim_targets",
       {{{"bone", rig.bone_name[head]}, {"point", {point.x(), point.y(), point.z()}}}}}};
  SceneSolveOptions o;
  o.solver = "physik";
  return solve_scene(scene_from_json(scene, "human_body", "."), o);
}

// the face's angle to its point (deg)
double aim_angle(const Scene& scene, const BoneFrames& f) {
  const AimTarget& t = scene.aim_targets[0];
  const Vec3 axis = f.orient_world[t.bone] * t.axis_bone;
  const Vec3 to = (t.point_world - f.head_world[t.bone]).normalized();
  return rad2deg(std::acos(std::clamp(axis.dot(to), -1.0, 1.0)));
}

// a look: its solve (feet pinned, the face turned toward a point)
LookRun look(const Rig& rig, const HumanBodyFit& fit, const Widths& rest, double forward) {
  const SceneSolveResult s = solve_look(rig, fit, forward);
  LookRun l;
  l.converged = s.solve.converged && !s.diverged;
  l.aim_deg = aim_angle(s.scene, s.frames);
  l.change = width_change(rig, rest, {s.frames});
  l.excess = limit_excess(rig, s.pose, s.scene.params.torsion_tolerance);
  return l;
}

Widths larger(const Widths& a, const Widths& b) {
  return {std::max(a.hips, b.hips), std::max(a.girdle, b.girdle),
          std::max(a.shoulders, b.shoulders)};
}

Excess worse(const Excess& a, const Excess& b) {
  Excess e = a.free_band >= b.free_band ? a : b;
  e.free_deg = std::max(a.free_deg, b.free_deg);
  e.locked_deg = std::max(a.locked_deg, b.locked_deg);
  return e;
}

// the clip written back on the rig's source skeleton from the poses it came in as, read again:
// the largest difference of any channel value of any frame from the clip's (degrees for rotation
// channels, file units for positions)
double round_trip_difference(const BvhAnimation& a, const BvhFile& clip) {
  BvhExportOptions o;
  o.frame_time = clip.frame_time;
  std::ostringstream text;
  write_bvh(a.rig(), a.poses, o, text, SourceFrames::of_clip(clip));
  const BvhFile back = parse_bvh(text.str(), "round trip");
  double worst = 0.0;
  for (std::size_t f = 0; f < clip.frames.size() && f < back.frames.size(); ++f) {
    for (std::size_t c = 0; c < clip.frames[f].size(); ++c) {
      worst = std::max(worst, std::abs(back.frames[f][c] - clip.frames[f][c]));
    }
  }
  return back.frames.size() == clip.frames.size() ? worst : std::nan("");
}

// the clip followed under gravity on a floor at the feet: the frames at every step
std::vector<BoneFrames> follow_clip(const Rig& rig, const BvhFile& clip, bool& diverged) {
  EngineParams params = preset_params(kDefaultPreset);
  params.dt = clip.frame_time / kStepsPerFrame;
  const int npoint = static_cast<int>(default_follow_points(rig).size());
  params.control_k = rig.total_mass() * 9.81 / (npoint * kSag);
  const BoneFrames rest = forward_kinematics(rig, rest_pose(rig));
  double floor = rest.head_world[0].z();
  for (int b = 0; b < rig.nbone; ++b) {
    floor = std::min({floor, rest.head_world[b].z(), rest.tail_world[b].z()});
  }
  FollowOptions fo;
  fo.source = "human_body";
  fo.gravity = true;
  fo.ground = floor - 0.05;
  const Scene scene = follow_scene(rig, clip, params, fo);
  std::vector<BoneFrames> frames;
  const RunSummary sum =
      run_scene(scene, [&](const SimState& s, const StepStats&) { frames.push_back(s.frames); });
  diverged = sum.diverged;
  return frames;
}

ShapeRun run_shape(const hs::Shape& shape) {
  ShapeRun r;
  r.name = shape.name;
  const BvhFile clip = shape.clip(6);
  const BvhAnimation a = bvh_to_rig(clip, r.name, options_of(shape.scale, shape.axes));
  const Rig& rig = a.rig();
  r.convention = a.body.match.convention;
  r.joints = static_cast<int>(clip.joints.size());
  r.named = a.body.match.named;
  r.bones = rig.nbone;
  for (int b = 0; b < rig.nbone; ++b) r.welded += rig.welded(b) ? 1 : 0;
  r.height = a.body.fit.height;
  r.mass = rig.total_mass();
  r.masses = a.body.fit.masses;
  r.unit_scale = bvh_to_rig(clip, r.name, options_of(1.0, shape.axes)).body.suggested_scale;
  const BvhAxes other = shape.axes == BvhAxes::kYUp ? BvhAxes::kZUp : BvhAxes::kYUp;
  r.axes_hint = !bvh_to_rig(clip, r.name, options_of(shape.scale, other)).body.axes_hint.empty();
  r.round_trip = round_trip_difference(a, clip);
  r.rest = widths(rig, forward_kinematics(rig, rest_pose(rig)));
  r.ahead = look(rig, a.body.fit, r.rest, 1.0);
  r.behind = look(rig, a.body.fit, r.rest, -1.0);
  r.follow = width_change(rig, r.rest, follow_clip(rig, clip, r.follow_diverged));
  return r;
}

// the shapes table's columns, one row per skeleton
std::vector<Column> shapes_columns() {
  return {text("shape", "the skeleton (experiments/human_skeletons.h)"),
          text("convention", "the joint-name convention the table found").in_quotes(),
          integer("joints", "", "the file's joints"),
          integer("named", "", "joints the convention names"),
          integer("bones", "", "the rig's bones"),
          integer("welded", "", "welded bones"),
          real("height", "m", "feet to head along the body's up axis"),
          real("mass", "kg", "the rig's total mass"),
          real("unit_scale", "1", "the --scale the unit rule names for the file as it is"),
          flag("axes_hint", "read with the other --axes, the hint names the file's own"),
          flag("solve_converged",
               "the solve with the feet pinned and the face turned toward a "
               "point ahead converged"),
          real("aim_deg", "deg", "the face's angle to its point ahead after the solve"),
          real("aim_deg_behind", "deg",
               "the face's angle to a point behind (out of its joints' reach) after the solve"),
          real("hip_width", "m", "the thighs' heads apart at rest"),
          real("hip_change_solve", "m", "the hip width's largest change through the solves"),
          real("hip_change_follow", "m", "... through the follow under gravity"),
          real("girdle_change_solve", "m", "the clavicles' heads' distance, its change (solve)"),
          real("girdle_change_follow", "m", "... (follow)"),
          real("shoulder_width", "m", "the upper arms' heads apart at rest"),
          real("shoulder_change_solve", "m", "the shoulder width's largest change (solve)"),
          real("shoulder_change_follow", "m", "... (follow)"),
          real("free_excess_deg", "deg", "the largest turn past a free axis's range (solves)"),
          real("free_excess_band", "1", "the largest such excess over its torsion band"),
          text("free_excess_where", "the bone and axis of the largest ratio").in_quotes(),
          real("locked_excess_deg", "deg", "the largest turn about a locked axis (solves)"),
          flag("follow_diverged", "the follow diverged"),
          real("round_trip", "deg or file units",
               "the largest channel difference of the clip written back on the source skeleton "
               "from the poses it came in as")};
}

Table shapes_table(const std::vector<ShapeRun>& runs) {
  Table t("shapes", "human_body_shapes.csv", shapes_columns());
  for (const ShapeRun& r : runs) {
    const Widths solve = larger(r.ahead.change, r.behind.change);
    const Excess excess = worse(r.ahead.excess, r.behind.excess);
    t.add({r.name,
           r.convention,
           r.joints,
           r.named,
           r.bones,
           r.welded,
           r.height,
           r.mass,
           r.unit_scale,
           r.axes_hint,
           r.ahead.converged,
           r.ahead.aim_deg,
           r.behind.aim_deg,
           r.rest.hips,
           solve.hips,
           r.follow.hips,
           solve.girdle,
           r.follow.girdle,
           r.rest.shoulders,
           solve.shoulders,
           r.follow.shoulders,
           excess.free_deg,
           excess.free_band,
           excess.worst,
           excess.locked_deg,
           r.follow_diverged,
           r.round_trip});
  }
  return t;
}

Table masses_table(const std::vector<ShapeRun>& runs) {
  Table t("masses", "human_body_masses.csv",
          {text("shape", "the skeleton"), text("row", "de Leva's row, per side").in_quotes(),
           real("table_share", "1", "de Leva 1996's share of the body's mass"),
           real("rig_share", "1", "the rig's bones' share"),
           integer("bones", "", "the rig's bones that carry it (0: passed to another row)"),
           text("passed_to", "the row that took its mass when it has no bone").in_quotes()});
  for (const ShapeRun& r : runs) {
    for (const HumanMassRow& m : r.masses) {
      t.add({r.name, m.segment, m.table_share, m.rig_share, m.nbone, m.passed_to});
    }
  }
  return t;
}

}  // namespace

namespace {

std::string fmt(double v, int digits = 3) {
  std::ostringstream s;
  s.precision(digits);
  s << v;
  return s.str();
}

std::string yes_no(bool ok) {
  return ok ? "yes" : "no";
}

void names_and_units_claims(const std::vector<ShapeRun>& runs, Report& report) {
  std::string names, units;
  bool named = true, unit_ok = true, hint = true;
  for (std::size_t k = 0; k < runs.size(); ++k) {
    const ShapeRun& r = runs[k];
    const hs::Shape shape = hs::shapes()[k];
    named = named && r.convention == shape.expected;
    unit_ok = unit_ok && std::abs(r.unit_scale - shape.scale) <= 1e-12;
    hint = hint && r.axes_hint;
    names += (k ? "; " : "") + r.name + ": " + r.convention + " (" + std::to_string(r.named) +
             " of " + std::to_string(r.joints) + " joints)";
    units += (k ? "; " : "") + r.name + " --scale " + fmt(r.unit_scale, 6);
  }
  report
      .claim(
          "every skeleton is recognised as human by its joint names, each by its own "
          "convention",
          names, yes_no(named))
      .named("recognised");
  report
      .claim(
          "read as it is, each file gets the --scale of its unit (CMU's 0.0564444, "
          "centimetres 0.01, decimetres 0.1)",
          units, yes_no(unit_ok))
      .named("unit-rule");
  report
      .claim(
          "read with the other --axes, each figure lies down (or stands on its head) and "
          "the hint names the file's own --axes",
          hint ? "hint given for all four" : "a figure without the hint", yes_no(hint))
      .named("axes-hint");
}

void mass_claim(const std::vector<ShapeRun>& runs, Report& report) {
  double worst = 0.0;
  std::string where;
  for (const ShapeRun& r : runs) {
    for (const HumanMassRow& m : r.masses) {
      if (m.nbone == 0) continue;
      const double off = std::abs(m.rig_share - m.table_share) / m.table_share;
      if (off >= worst) worst = off, where = r.name + " " + m.segment;
    }
  }
  report
      .claim("every de Leva row's share of the rig's mass is within 20 % of the table's",
             "largest difference " + fmt(100.0 * worst) + " % (" + where +
                 "); the split is the table's by construction, so this checks that every bone "
                 "is assigned",
             yes_no(worst <= kMassShareTol))
      .named("mass-shares");
}

void width_claims(const std::vector<ShapeRun>& runs, Report& report) {
  Widths most;
  bool diverged = false;
  for (const ShapeRun& r : runs) {
    most = larger(most, larger(larger(r.ahead.change, r.behind.change), r.follow));
    diverged = diverged || r.follow_diverged;
  }
  report
      .claim(
          "the hip width (the thighs' heads) is unchanged to 1e-6 m through solves with "
          "both feet pinned and a head look-at, and through a follow under gravity",
          "largest change " + fmt(most.hips) + " m" + (diverged ? " (a follow diverged)" : ""),
          yes_no(most.hips <= kWidthTol && !diverged))
      .named("hip-width");
  report
      .claim(
          "the shoulder girdle's base (the clavicles' heads) is unchanged to 1e-6 m through "
          "the same solves and follow",
          "largest change " + fmt(most.girdle) + " m", yes_no(most.girdle <= kWidthTol))
      .named("girdle-width");
  report.note(
      "The shoulder width (the upper arms' heads) moves with the clavicles' own small range (15 "
      "deg each way): its largest change over the solves and follows is " +
      fmt(most.shoulders) + " m.");
}

void limit_claim(const std::vector<ShapeRun>& runs, Report& report) {
  Excess most;
  std::string ahead, behind;
  for (const ShapeRun& r : runs) {
    most = worse(most, worse(r.ahead.excess, r.behind.excess));
    if (most.worst.empty()) most.worst = "none";
    ahead += (ahead.empty() ? "" : ", ") + r.name + " " + fmt(r.ahead.aim_deg) + " deg" +
             (r.ahead.converged ? "" : " (not converged)");
    behind += (behind.empty() ? "" : ", ") + r.name + " " + fmt(r.behind.aim_deg) + " deg";
  }
  report
      .claim(
          "after solves with the feet pinned and the face turned toward a point ahead and one "
          "behind (out of the neck's and spine's reach), no free axis is past its range by "
          "more than its torsion band",
          "largest excess " + fmt(most.free_deg) + " deg, " + fmt(most.free_band) +
              " of its band (" + most.worst + "); the face ends " + ahead +
              " from the point ahead, " + behind + " from the point behind",
          yes_no(most.free_band <= 1.0))
      .named("limits");
  report.note(
      "Locked axes (a knee's two, an elbow's and a wrist's one) are no coordinates of the "
      "exact and implicit schemes (rig.h \"Locked axes\"): after the solves the largest turn "
      "of a hinge, a two-axis joint or a weld by locks off its joint's set is " +
      fmt(most.locked_deg) + " deg.");
}

// the clip's round trip today: a note (its claim belongs to the write-back)
void round_trip_claim(const std::vector<ShapeRun>& runs, Report& report) {
  double trip = 0.0;
  std::string each;
  for (const ShapeRun& r : runs) {
    // a NaN (frames lost on the way) stays NaN
    trip =
        std::isnan(r.round_trip) || std::isnan(trip) ? std::nan("") : std::max(trip, r.round_trip);
    each += (each.empty() ? "" : ", ") + r.name + " " + fmt(r.round_trip);
  }
  report
      .claim(
          "the clip written back on each source skeleton from the poses it came in as (the "
          "frames as their sources, as bvh convert writes) gives every channel value within "
          "1e-6, joints with no bone of their own and welded joints included",
          "largest channel difference " + fmt(trip) + " (degrees or file units; " + each + ")",
          yes_no(trip <= 1e-6))
      .named("round-trip");
}

void run(const Context& ctx) {
  std::vector<ShapeRun> runs;
  for (const hs::Shape& shape : hs::shapes()) {
    if (ctx.log) *ctx.log << "  " << shape.name << ": convert, solve, follow\n";
    runs.push_back(run_shape(shape));
  }
  const Table shapes = shapes_table(runs), masses = masses_table(runs);
  shapes.write_csv(ctx.out_dir);
  masses.write_csv(ctx.out_dir);
  Report report("A human body inside a human skeleton: names, units, masses, limits, welds");
  names_and_units_claims(runs, report);
  mass_claim(runs, report);
  width_claims(runs, report);
  limit_claim(runs, report);
  round_trip_claim(runs, report);
  shapes.add_to_report(report, "The four skeletons",
                       {{"shape", "shape"},
                        {"convention", "convention"},
                        {"bones", "bones"},
                        {"welded", "welded"},
                        {"height m", "height"},
                        {"--scale named", "unit_scale"},
                        {"hips d (solve) m", "hip_change_solve"},
                        {"hips d (follow) m", "hip_change_follow"},
                        {"shoulders d (solve) m", "shoulder_change_solve"},
                        {"free excess / band", "free_excess_band"},
                        {"locked excess deg", "locked_excess_deg"},
                        {"round trip", "round_trip"}});
  report.figures({"human_body_masses.png", "human_body_widths.png"});
  write_summary(ctx,
                {{"experiment", "human_body"},
                 {"shapes", shapes.rows_json()},
                 {"masses", masses.rows_json()}},
                report, {&shapes, &masses});
}

const Registration registered{
    285,
    {"human_body", "study",
     "four mocap skeletons (CMU-like, Mixamo-like, MakeHuman-like, OptiTrack-like) converted "
     "with a human body: names, units, de Leva masses, AAOS limits, welded pelvis, a solve and a "
     "follow",
     run}};

}  // namespace

}  // namespace physik::experiments
