// Paper Fig 9 / Sec. 4 "Intuitiveness": PhysIK against a classic IK solver on a pose with one
// outstretched hand and 3 control points (right hand tip, both toes). The paper compares with
// Blender's iTaSC (seed 000 ref. [3]). When Blender is present (experiments/blender_peer.h:
// PHYSIK_BLENDER or `blender` on PATH) iTaSC solves the same scene file, rig and limits through
// blender/itasc_solve.py (ANIMATION mode, SDLS, every chain to the root; its docstring says why);
// its pose must meet the control points (the scene's residual tolerance) before it is compared.
// The damped-least-squares solver of physik/ik_solver.h (same limits and goals) is the baseline
// that is always there.
//
// Secondary-motion measures, each against the initial (rest) pose, world frame, Z up, the
// character facing -Y (models/rigs/pinhead.json), so the viewer of a front view is at -Y:
//   shoulder_turn_deg   yaw of the shoulder line s = tail(collar.L) - tail(collar.R) about +Z:
//                       atan2(s_y, s_x) - atan2(s0_y, s0_x). Positive = the right shoulder comes
//                       forward (toward -Y, the viewer).
//   lean_deg            angle between the torso's up direction u = head(torso) - tail(torso) and
//                       +Z; lean_forward_deg = atan2(-u_y, u_z) (positive = leaning toward -Y),
//                       lean_side_deg = atan2(u_x, u_z), both minus their rest values.
//   head_tilt_deg       angle turned by the head bone's axis (tail - head) from its rest direction
//                       (world); neck_bend_deg: change of the angle between the head's axis and
//                       the torso's axis (the head relative to the body).
//   off_chain_rotation  sum over bones not on any control point's chain to the root of their
//                       world rotation angle (experiments/common.h), rad
//   off_reach_rotation  the same over bones not on the reaching hand's chain to the root, rad
//   limit_excess_deg    largest amount by which any limited axis is outside its range, in the
//                       project's convention (rotation vector of the rest-relative rotation;
//                       physik/model/joint_angles.h max_limit_violation, in the scheme's joints),
//                       deg
// Every row is measured by the same functions from world frames: iTaSC's from the forward
// kinematics of the pose it wrote (rolls included), checked against the bones it posed.
// The IK solvers anchor the root bone's head; pinhead's root is the head bone, so the DLS pose
// hangs from the top of the head, while PhysIK's root translates freely (noted in the report).
#include <cmath>
#include <filesystem>
#include <map>

#include "experiments/blender_peer.h"
#include "experiments/common.h"
#include "experiments/table.h"
#include "physik/ik/ik_solver.h"
#include "physik/io/pose_io.h"
#include "physik/io/summary_io.h"
#include "physik/model/errors.h"
#include "physik/model/joint_angles.h"
#include "reference/mujoco_runner.h"

namespace physik::experiments {

namespace {

constexpr double kDeg = 180.0 / 3.14159265358979323846;

struct Measures {
  double shoulder_turn_deg = 0, lean_deg = 0, lean_forward_deg = 0, lean_side_deg = 0;
  double head_tilt_deg = 0, neck_bend_deg = 0, off_chain_rad = 0, off_reach_rad = 0;
  double max_residual = 0, limit_excess_deg = 0;
};

double angle_between(const Vec3& a, const Vec3& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

int bone(const Rig& rig, const std::string& name) {
  const int b = rig.find_bone(name);
  if (b < 0) throw_input_error(rig.name, "bone '" + name + "'", "", "missing; fig9 needs pinhead");
  return b;
}

Measures measure(const Scene& scene, const BoneFrames& rest, const BoneFrames& f,
                 const std::vector<int>& controlled, const std::vector<int>& reach_chain) {
  const Rig& rig = scene.rig;
  const int cl = bone(rig, "collar.L"), cr = bone(rig, "collar.R"), torso = bone(rig, "torso"),
            head = bone(rig, "head");
  Measures m;
  const Vec3 s0 = rest.tail_world[cl] - rest.tail_world[cr];
  const Vec3 s = f.tail_world[cl] - f.tail_world[cr];
  // signed angle from the rest shoulder line to the current one, wrapped to (-180, 180]
  m.shoulder_turn_deg =
      kDeg * std::remainder(std::atan2(s.y(), s.x()) - std::atan2(s0.y(), s0.x()), 2 * kPi);
  const Vec3 u0 = rest.head_world[torso] - rest.tail_world[torso];
  const Vec3 u = f.head_world[torso] - f.tail_world[torso];
  m.lean_deg = kDeg * angle_between(u, Vec3::UnitZ());
  m.lean_forward_deg =
      kDeg * std::remainder(std::atan2(-u.y(), u.z()) - std::atan2(-u0.y(), u0.z()), 2 * kPi);
  m.lean_side_deg = kDeg * (std::atan2(u.x(), u.z()) - std::atan2(u0.x(), u0.z()));
  const Vec3 h0 = rest.tail_world[head] - rest.head_world[head];
  const Vec3 h = f.tail_world[head] - f.head_world[head];
  m.head_tilt_deg = kDeg * angle_between(h, h0);
  const Vec3 t0 = rest.tail_world[torso] - rest.head_world[torso];
  const Vec3 t = f.tail_world[torso] - f.head_world[torso];
  m.neck_bend_deg = kDeg * (angle_between(h, t) - angle_between(h0, t0));
  m.off_chain_rad = off_chain_rotation(rig, rest, f, controlled);
  m.off_reach_rad = off_chain_rotation(rig, rest, f, reach_chain);
  for (const ControlPoint& c : scene.control_points) {
    m.max_residual =
        std::max(m.max_residual, (point_on_bone(f, c.bone, c.alpha) - c.target_world).norm());
  }
  Pose local;
  local_rotations_from_world(rig, f, local);
  m.limit_excess_deg = kDeg * max_limit_violation(rig, scene.params.locked_axes(), local);
  return m;
}

using Rows = std::vector<std::pair<std::string, const Measures*>>;

// measures.csv, one row per solver: the summary's per-solver objects and the report's table too
Table measures_table(const Rows& rows) {
  const auto deg = [](std::string name, std::string doc) {
    return real(std::move(name), "deg", std::move(doc));
  };
  Table t(
      "measures", "measures.csv",
      {text("method", "the solver: physik, dls, itasc or mujoco_same_forces"),
       deg("shoulder_turn_deg", "yaw of the shoulder line (+: the right shoulder to the viewer)"),
       deg("lean_deg", "the torso's angle from +Z"),
       deg("lean_forward_deg", "the torso's lean toward -Y, against rest"),
       deg("lean_side_deg", "the torso's lean toward +X, against rest"),
       deg("head_tilt_deg", "the angle the head's axis turned"),
       deg("neck_bend_deg", "the change of the head-torso angle"),
       real("off_chain_rotation_rad", "rad", "rotation of the bones off every controlled chain"),
       real("off_reach_rotation_rad", "rad", "rotation of the bones off the reaching arm's chain"),
       real("max_residual", "rig units", "the largest control-point residual"),
       deg("max_limit_excess_deg", "the largest excursion of a limited axis past its range")});
  for (const auto& [name, m] : rows) {
    t.add({name, m->shoulder_turn_deg, m->lean_deg, m->lean_forward_deg, m->lean_side_deg,
           m->head_tilt_deg, m->neck_bend_deg, m->off_chain_rad, m->off_reach_rad, m->max_residual,
           m->limit_excess_deg});
  }
  return t;
}

// one solver's measures as the summary holds them: its row of measures_table without "method"
nlohmann::json to_json(const Measures& m) {
  nlohmann::json j = measures_table({{"", &m}}).rows_json()[0];
  j.erase("method");
  return j;
}

// The final poses from the same initial pose.
struct Solutions {
  RecordedRun physik;     // PhysIK, with its trajectory table
  IkOptions dls_options;  // damped least squares: same goals and limits
  IkReport dls;
  BoneFrames dls_frames;
  RunSummary mujoco;  // MuJoCo with PhysIK's forces (exact joints): where the joint-force
                      // heuristic alone would go
  ItascRun itasc;     // Blender's iTaSC, when Blender is present and runs
};

// blender/itasc_solve.py beside the models folder (the repository's)
std::string itasc_script(const Context& ctx) {
  return (std::filesystem::path(ctx.models_dir) / ".." / "blender" / "itasc_solve.py")
      .lexically_normal()
      .string();
}

Solutions solve_all(const Context& ctx, const Scene& scene) {
  Solutions out;
  out.physik = record_run(scene, trajectory_table(ctx.out_dir + "/physik_trajectory.csv", 5));
  if (ctx.log)
    *ctx.log << "  physik: " << out.physik.summary.steps_run << " steps, converged "
             << out.physik.summary.converged << "\n";
  std::vector<IkGoal> goals;
  for (const ControlPoint& c : scene.control_points)
    goals.push_back({c.bone, c.alpha, c.target_world});
  Pose dls_pose = scene.initial_pose;
  out.dls = solve_ik(IkMethod::kDampedLeastSquares, scene.rig, goals, dls_pose, out.dls_options);
  out.dls_frames = forward_kinematics(scene.rig, dls_pose);
  if (ctx.log)
    *ctx.log << "  dls: " << out.dls.iterations << " iterations, residual " << out.dls.residual
             << "\n";
  out.mujoco = run_mujoco(scene, ReferenceMode::kSameForces);
  out.itasc = run_itasc(scene, itasc_script(ctx), ctx.out_dir);
  if (ctx.log) {
    *ctx.log << "  itasc: "
             << (out.itasc.ok() ? "solved" : out.itasc.status + ": " + out.itasc.reason);
    if (out.itasc.ok())
      *ctx.log << " in " << num(out.itasc.seconds) << " s (Blender " << out.itasc.blender << ")";
    *ctx.log << "\n";
  }
  return out;
}

// The report's table: the measures the paper's figure is about, one row per solver.
void add_table(Report& report, const Table& measures) {
  measures.add_to_report(report, "Fig 9 measures against rest (deg; residual in rig units)",
                         {{"solver", "method"},
                          {"shoulder turn", "shoulder_turn_deg"},
                          {"forward lean", "lean_forward_deg"},
                          {"head tilt", "head_tilt_deg"},
                          {"largest residual", "max_residual"},
                          {"limit excess", "max_limit_excess_deg"}},
                         3,
                         {{"physik", "PhysIK"},
                          {"dls", "damped least squares (physik/ik)"},
                          {"itasc", "Blender iTaSC"},
                          {"mujoco_same_forces", "MuJoCo, PhysIK's forces"}});
}

// iTaSC takes part in the comparison only when it ran and its pose meets the control points
bool itasc_compared(const ItascRun& run, const Measures* mi, double tol) {
  return run.ok() && mi != nullptr && mi->max_residual <= tol;
}

// thresholds of 2 deg on angles (a visible change in a stick figure); stated in the notes
constexpr double kThresholdDeg = 2.0;

const char* direction_holds(double v) {
  return v > kThresholdDeg ? "yes" : (v > 0.5 ? "partly" : "no");
}

// the shoulder turn, the forward lean and the head tilt: PhysIK against DLS (and iTaSC)
void add_pose_claims(Report& report, const Measures& mp, const Measures& md, const Measures* mi,
                     bool with_itasc) {
  const double thr = kThresholdDeg;
  const auto turn_holds =
      mp.shoulder_turn_deg > thr && mp.shoulder_turn_deg > md.shoulder_turn_deg + thr
          ? "yes"
          : (mp.shoulder_turn_deg > 0.5 ? "partly" : "no");
  const auto with = [&](double v) {
    return with_itasc ? ", iTaSC " + num(v) + " deg" : std::string();
  };
  report.claim("Fig 9: PhysIK turns the shoulder toward the viewer",
               "shoulder-line yaw (+ = right shoulder toward the viewer, -Y): PhysIK " +
                   num(mp.shoulder_turn_deg) + " deg, DLS " + num(md.shoulder_turn_deg) + " deg" +
                   with(mi ? mi->shoulder_turn_deg : 0.0),
               turn_holds);
  report.claim("Fig 9: PhysIK leans slightly forward",
               "torso forward lean: PhysIK " + num(mp.lean_forward_deg) + " deg (sideways " +
                   num(mp.lean_side_deg) + " deg), DLS " + num(md.lean_forward_deg) +
                   " deg (sideways " + num(md.lean_side_deg) + " deg)" +
                   with(mi ? mi->lean_forward_deg : 0.0),
               direction_holds(mp.lean_forward_deg));
  report.claim("Fig 9: PhysIK tilts the head",
               "head axis turned: PhysIK " + num(mp.head_tilt_deg) + " deg (neck bend " +
                   num(mp.neck_bend_deg) + " deg), DLS " + num(md.head_tilt_deg) +
                   " deg (neck bend " + num(md.neck_bend_deg) + " deg)" +
                   with(mi ? mi->head_tilt_deg : 0.0),
               direction_holds(mp.head_tilt_deg));
}

// the stiffness claim is the paper's about iTaSC: judged on iTaSC when it took part, else DLS
void add_stiff_claim(Report& report, const Measures& mp, const Measures& md, const Measures* mi,
                     bool with_itasc, bool dls_reached) {
  const Measures& peer = with_itasc ? *mi : md;
  const std::string peer_name = with_itasc ? "iTaSC" : "DLS";
  const auto stiff_holds = !with_itasc && !dls_reached ? "n/a"
                           : peer.off_reach_rad < 0.5 * mp.off_reach_rad
                               ? "yes"
                               : (peer.off_reach_rad < mp.off_reach_rad ? "partly" : "no");
  std::string stiff = "rotation of bones off the reaching arm's chain: ";
  if (with_itasc) stiff += "iTaSC " + num(mi->off_reach_rad) + " rad, ";
  stiff += "DLS " + num(md.off_reach_rad) + " rad vs PhysIK " + num(mp.off_reach_rad) +
           " rad; off all controlled chains: ";
  if (with_itasc) stiff += "iTaSC " + num(mi->off_chain_rad) + ", ";
  stiff += "DLS " + num(md.off_chain_rad) + " vs PhysIK " + num(mp.off_chain_rad) +
           " rad (judged on " + peer_name + ")";
  if (!with_itasc && !dls_reached) {
    stiff +=
        " (DLS did not reach the targets: residual " + num(md.max_residual) + ", so no comparison)";
  }
  report.claim("Fig 9: the classic solver (iTaSC; DLS when iTaSC is absent) gives a stiff pose",
               stiff, stiff_holds);
}

// the paper's peer itself: its pose must meet the points before anything is compared
void add_itasc_claims(Report& report, const Measures& mp, const Measures& md, const Measures* mi,
                      const ItascRun& itasc, double tol, bool with_itasc) {
  if (!itasc.ok()) {
    const std::string absent = "n/a (" + itasc.status + ": " + itasc.reason + ")";
    report.claim("Fig 9: Blender's iTaSC meets the 3 control points (checked before comparing)",
                 "no iTaSC run", absent);
    report.claim("Fig 9: PhysIK leans and tilts the head where iTaSC stays stiff", "no iTaSC run",
                 absent);
    return;
  }
  report.claim("Fig 9: Blender's iTaSC meets the 3 control points (checked before comparing)",
               "largest control-point residual: iTaSC " + num(mi->max_residual) +
                   " rig units (the scene's tolerance " + num(tol) + "); limit excess " +
                   num(mi->limit_excess_deg) + " deg (PhysIK " + num(mp.limit_excess_deg) +
                   ", DLS " + num(md.limit_excess_deg) + ")",
               with_itasc ? "yes" : "no (so iTaSC is not compared)");
  const bool lean = mp.lean_forward_deg > mi->lean_forward_deg + kThresholdDeg;
  const bool tilt = mp.head_tilt_deg > mi->head_tilt_deg + kThresholdDeg;
  report.claim("Fig 9: PhysIK leans and tilts the head where iTaSC stays stiff",
               "forward lean: PhysIK " + num(mp.lean_forward_deg) + " deg, iTaSC " +
                   num(mi->lean_forward_deg) + " deg; head tilt: PhysIK " + num(mp.head_tilt_deg) +
                   " deg, iTaSC " + num(mi->head_tilt_deg) + " deg; shoulder turn: PhysIK " +
                   num(mp.shoulder_turn_deg) + " deg, iTaSC " + num(mi->shoulder_turn_deg) +
                   " deg (+ = right shoulder toward the viewer)",
               !with_itasc    ? "n/a (iTaSC missed the control points)"
               : lean && tilt ? "yes"
               : lean || tilt ? "partly"
                              : "no");
}

void add_claims(Report& report, const Measures& mp, const Measures& md, const Measures* mi,
                const ItascRun& itasc, double tol, double height) {
  const bool dls_reached = md.max_residual < 0.02 * height;
  const bool with_itasc = itasc_compared(itasc, mi, tol);
  add_pose_claims(report, mp, md, mi, with_itasc);
  add_stiff_claim(report, mp, md, mi, with_itasc, dls_reached);
  add_itasc_claims(report, mp, md, mi, itasc, tol, with_itasc);
  report.claim("Fig 9: both poses meet the 3 control points",
               "largest control-point residual: PhysIK " + num(mp.max_residual) + ", DLS " +
                   num(md.max_residual) + " rig units (rig height " + num(height) + ")",
               mp.max_residual < 0.02 * height && md.max_residual < 0.02 * height   ? "yes"
               : mp.max_residual < 0.02 * height || md.max_residual < 0.02 * height ? "partly"
                                                                                    : "no");
}

// How iTaSC was set up (from itasc_solve.py's report), or why it is missing.
std::string itasc_note(const ItascRun& run) {
  if (!run.ok()) {
    return "Blender's iTaSC: no row (" + run.status + ": " + run.reason +
           "). Set PHYSIK_BLENDER to "
           "Blender's binary or put `blender` on PATH to add it.";
  }
  const nlohmann::json& it = run.report.value("itasc", nlohmann::json::object());
  const auto str = [&](const char* key) {
    if (!it.contains(key)) return std::string("?");
    const nlohmann::json& v = it[key];
    if (v.is_number_integer()) return std::to_string(v.get<long long>());
    return v.is_string() ? v.get<std::string>() : v.is_number() ? num(v.get<double>()) : v.dump();
  };
  return "Blender's iTaSC (Blender " + run.report.value("blender", std::string("?")) +
         ", blender/itasc_solve.py, " + num(run.seconds) +
         " s): the same scene file, rig and "
         "limits; mode " +
         str("mode") +
         " (stateless: one IK solve from the scene's start pose, "
         "no frame history or velocity limits as SIMULATION would bring), solver " +
         str("solver") + " (Blender's default), iterations " + str("iterations") + ", precision " +
         str("precision") +
         "; one IK constraint per control point, weight 1 (PhysIK's equal k has no iTaSC "
         "counterpart), each chain to the root (chain " +
         str("chain") +
         "), so iTaSC may move "
         "every bone PhysIK and DLS move, as one tree; the root only turns about its head (no "
         "translation joint, like DLS; PhysIK's root translates). The armature's origin sits at "
         "the "
         "root head: Blender 3.4.1's iTaSC solves a chain holding the root as if the root head "
         "were "
         "at the object's origin (blender/README.md). Its pose is rebuilt here from the rotations "
         "it wrote (forward kinematics within " +
         num(run.fk_gap) + " rig units of Blender's bones) and measured like the others.";
}

void add_notes(Report& report, const Solutions& sol, const Measures& mm) {
  const RunSummary& pk = sol.physik.summary;
  report.note(itasc_note(sol.itasc))
      .note("Baseline: physik/ik_solver.h damped least squares (lambda = " +
            num(sol.dls_options.lambda_fraction) + " x reach, joint limits respected, " +
            std::to_string(sol.dls.iterations) + " iterations, converged " +
            (sol.dls.converged ? "yes" : "no") +
            "), always there (iTaSC needs Blender). The IK solvers anchor the root bone's head; "
            "pinhead's "
            "root is the head bone, so the DLS pose hangs from the top of the head and cannot "
            "translate, while PhysIK's root moves freely. DLS only moves bones on a goal's chain "
            "(the left arm keeps its local rotations).")
      .note(
          "Holds = yes when the PhysIK angle exceeds 2 deg in the claimed direction (and, for the "
          "shoulder, DLS's by 2 deg); partly when it is in the claimed direction but smaller; "
          "'stiff' = yes when the classic solver's off-reach-chain rotation is under half of "
          "PhysIK's; 'leans and tilts where iTaSC stays stiff' = yes when PhysIK's forward lean "
          "and "
          "head tilt each exceed iTaSC's by 2 deg, partly when one does. iTaSC is compared only "
          "when its pose meets every control point within the scene's residual tolerance.")
      .note(
          "Summed rotations count every bone's full world-orientation change, rolls about its own "
          "axis included (invisible in a stick figure).")
      .note("PhysIK run: " + std::to_string(pk.steps_run) + " steps, converged " +
            (pk.converged ? "yes" : "no") + " (at step " + std::to_string(pk.steps_to_converge) +
            "), peak KE " + num(pk.peak_kinetic_energy) + " J.")
      .note(
          "MuJoCo same forces (PhysIK's control, torsion and damping forces on an exactly jointed "
          "model): shoulder turn " +
          num(mm.shoulder_turn_deg) + " deg, forward lean " + num(mm.lean_forward_deg) +
          " deg, head tilt " + num(mm.head_tilt_deg) + " deg, off-reach-chain rotation " +
          num(mm.off_reach_rad) + " rad.");
}

// the viewer's runs: PhysIK's motion, the DLS and iTaSC (when it ran) poses
void write_view_runs(const Context& ctx, const Scene& scene, const Solutions& sol) {
  write_run_folder(ctx, "physik", scene);
  write_pose_run_folder(ctx, "dls", scene, sol.dls_frames,
                        {{"solver", "damped least squares"},
                         {"iterations", sol.dls.iterations},
                         {"residual", sol.dls.residual},
                         {"converged", sol.dls.converged}});
  if (sol.itasc.ok()) {
    write_pose_run_folder(ctx, "itasc", scene, sol.itasc.frames,
                          {{"solver", "Blender iTaSC"}, {"blender", sol.itasc.blender}});
  }
}

nlohmann::json itasc_json(const ItascRun& run, double tol, const Measures& mi) {
  nlohmann::json j = {{"status", run.status},
                      {"reason", run.reason},
                      {"blender", run.blender},
                      {"seconds", run.seconds}};
  if (run.ok()) {
    j["settings"] = run.report.value("itasc", nlohmann::json::object());
    j["chains"] = run.report.value("chains", nlohmann::json::object());
    j["blender_version"] = run.report.value("blender", std::string());
    j["fk_gap"] = run.fk_gap;
    j["residual_tol"] = tol;
    j["meets_control_points"] = mi.max_residual <= tol;
  }
  return j;
}

nlohmann::json targets_json(const Scene& scene) {
  nlohmann::json t = nlohmann::json::array();
  for (const ControlPoint& c : scene.control_points) {
    t.push_back({c.target_world.x(), c.target_world.y(), c.target_world.z()});
  }
  return t;
}

void run(const Context& ctx) {
  Scene scene = scene_named(ctx, "fig9_outstretched");
  if (ctx.quick) scene.steps = std::min(scene.steps, 100);
  const Rig& rig = scene.rig;
  const BoneFrames rest = forward_kinematics(rig, scene.initial_pose);
  std::vector<int> cp_bones;
  for (const ControlPoint& c : scene.control_points) cp_bones.push_back(c.bone);
  const std::vector<int> controlled = chains_to_root(rig, cp_bones);
  const std::vector<int> reach_chain = chains_to_root(rig, {bone(rig, "hand.R")});

  const Solutions sol = solve_all(ctx, scene);
  write_view_runs(ctx, scene, sol);
  const BoneFrames& pk_final = sol.physik.summary.final_frames;
  write_bones_table(ctx.out_dir + "/rest.csv", rig, rest);
  write_bones_table(ctx.out_dir + "/physik_final.csv", rig, pk_final);
  write_bones_table(ctx.out_dir + "/dls_final.csv", rig, sol.dls_frames);
  write_bones_table(ctx.out_dir + "/mujoco_final.csv", rig, sol.mujoco.final_frames);
  const Measures mp = measure(scene, rest, pk_final, controlled, reach_chain);
  const Measures md = measure(scene, rest, sol.dls_frames, controlled, reach_chain);
  const Measures mm = measure(scene, rest, sol.mujoco.final_frames, controlled, reach_chain);
  Measures mi;
  if (sol.itasc.ok()) mi = measure(scene, rest, sol.itasc.frames, controlled, reach_chain);
  Rows rows = {{"physik", &mp}, {"dls", &md}};
  if (sol.itasc.ok()) rows.push_back({"itasc", &mi});
  rows.push_back({"mujoco_same_forces", &mm});
  const Table measures = measures_table(rows);
  measures.write_csv(ctx.out_dir);

  Report report("Fig 9: outstretched hand, PhysIK vs Blender's iTaSC and damped least squares");
  add_claims(report, mp, md, sol.itasc.ok() ? &mi : nullptr, sol.itasc, scene.residual_tol(),
             rig.height());
  add_table(report, measures);
  add_notes(report, sol, mm);
  report.figures({"fig9_poses.png", "fig9_measures.png"})
      .settings(settings_json(scene, {{"dls_lambda_fraction", sol.dls_options.lambda_fraction}}));
  write_summary(ctx,
                {{"experiment", "fig9_outstretched"},
                 {"scene", scene.file},
                 {"targets", targets_json(scene)},
                 {"physik", to_json(mp)},
                 {"dls", to_json(md)},
                 {"mujoco_same_forces", to_json(mm)},
                 {"itasc", sol.itasc.ok() ? to_json(mi) : nlohmann::json()},
                 {"itasc_run", itasc_json(sol.itasc, scene.residual_tol(), mi)},
                 {"physik_run", summary_to_json(scene, sol.physik.summary)},
                 {"dls_report",
                  {{"iterations", sol.dls.iterations},
                   {"residual", sol.dls.residual},
                   {"converged", sol.dls.converged},
                   {"stalled", sol.dls.stalled}}}},
                report, {&measures});
}

const Registration registered{
    90,
    {"fig9_outstretched", "Fig 9",
     "outstretched hand: PhysIK vs Blender's iTaSC (when Blender is present) and damped "
     "least squares, secondary motion",
     run}};

}  // namespace

}  // namespace physik::experiments
