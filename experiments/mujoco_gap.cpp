// How far PhysIK's heuristic is from exact constrained dynamics: PhysIK against MuJoCo on the
// same rig from the same pose, in both reference modes (reference/compare.h):
//   same-forces        MuJoCo gets exactly PhysIK's control, torsion and damping forces each
//                      step, so only the joint-force heuristic (and the articulated
//                      integration) differ;
//   exact-constraints  MuJoCo's joint types and limits replace the torsion springs.
// Whether a final gap measures the heuristic or path dependence depends on whether the control
// points fix the pose (free_endpoint_dof = 0) or leave a family of equilibria.
// Beside Gauss-Seidel, PhysIK's exact joint solve (scheme exact: the articulated-body
// algorithm with MuJoCo's Euler step, same forces) is compared with MuJoCo too: with the same
// forces it agrees to round-off, so the Gauss-Seidel gap is the heuristic's own (its joint forces
// and its integration), not MuJoCo's integrator; in exact-constraints mode the exact gap is the
// model's (the rig's joints and hard limits against balls and torsion springs).

#include "experiments/columns.h"
#include "experiments/common.h"
#include "experiments/report.h"
#include "physik/io/pose_io.h"
#include "reference/compare.h"

namespace physik::experiments {

namespace {

// PhysIK with scheme exact on the scene (same forces, MuJoCo's Euler step)
RecordedRun exact_run(const Scene& scene) {
  Scene exact = scene;
  exact.params.scheme = Scheme::kExact;
  RecordOptions every_frame;
  every_frame.all_frames = true;
  return record_run(exact, every_frame);
}

struct ExactGaps {
  GapStats exact_vs_mujoco, gauss_seidel_vs_exact;
};

ExactGaps exact_gaps(const RecordedRun& exact, const Comparison& c) {
  return {trajectory_gap(exact.frames, c.mujoco.frames, exact.summary.final_frames,
                         c.mujoco.summary.final_frames),
          trajectory_gap(c.physik.frames, exact.frames, c.physik.summary.final_frames,
                         exact.summary.final_frames)};
}

nlohmann::json gap_json(const GapStats& g) {
  return {{"rms_gap", g.rms_gap},
          {"max_gap", g.max_gap},
          {"final_pose_gap", g.final_pose_gap},
          {"steps_compared", g.steps_compared}};
}

// "rms / max / final" in rig units
std::string gap_cell(const GapStats& g) {
  return num(g.rms_gap, 2) + " / " + num(g.max_gap, 2) + " / " + num(g.final_pose_gap, 2);
}

// the report's gap table (Gauss-Seidel vs MuJoCo beside exact vs MuJoCo), notes and figures
void add_exact_table_and_notes(Report& report, const nlohmann::json& gap_rows) {
  report
      .table(
          "Gap to MuJoCo, rig units (rms / largest / final pose): Gauss-Seidel vs MuJoCo "
          "beside exact vs MuJoCo",
          {"scene", "mode", "Gauss-Seidel vs MuJoCo", "exact vs MuJoCo", "Gauss-Seidel vs exact"},
          gap_rows)
      .note("Table: results/mujoco_gap/gaps.csv (rig units; pinhead is 4.69 tall).")
      .note(
          "same-forces uses ball joints at every bone (PhysIK's own freedom) and PhysIK's "
          "torsion forces; exact-constraints uses the rig's joints and limits.")
      .note("The angular-velocity factor is a torque I (f - 1) w / dt in MuJoCo.")
      .note(
          "exact = PhysIK's scheme exact (articulated-body algorithm, MuJoCo's Euler step, "
          "PhysIK's forces). Same forces: exact vs MuJoCo is round-off, so the Gauss-Seidel gap "
          "is the heuristic's own (joint forces and its integration); exact-constraints: the "
          "exact gap is the joint model's (rig joints and hard limits vs balls and torsion "
          "springs).")
      .figures({"mujoco_gap.png", "mujoco_poses.png"});
}

// the viewer's runs: PhysIK and MuJoCo with PhysIK's forces
void write_view_runs(const Context& ctx, const Scene& scene) {
  write_run_folder(ctx, "physik", scene);
  write_reference_run_folder(scene, ReferenceMode::kSameForces, run_folder_path(ctx, "mujoco"),
                             run_folder_every(scene));
}

// gap_over_time.csv: the pose gaps every 5th step
Table gap_over_time_table() {
  using namespace columns;
  return Table("gap_over_time", "gap_over_time.csv",
               {kScene, text("mode", "the reference mode: same-forces or exact-constraints"), kStep,
                real("gap", "rig units", "the largest bone-end distance, Gauss-Seidel vs MuJoCo"),
                real("exact_gap", "rig units", "the same, PhysIK's scheme exact vs MuJoCo")});
}

// gaps.csv: one row per scene and mode
Table gaps_table() {
  using namespace columns;
  const auto gap = [](std::string name, std::string doc) {
    return real(std::move(name), "rig units", std::move(doc));
  };
  const Column steps = integer("", "steps", "steps to converge (-1: not converged)");
  const Column violation = real("", "deg", "the largest joint-limit excess");
  return Table(
      "gaps", "gaps.csv",
      {kScene, text("mode", "the reference mode: same-forces or exact-constraints"),
       gap("rms_gap", "Gauss-Seidel vs MuJoCo: rms over the run"),
       gap("max_gap", "Gauss-Seidel vs MuJoCo: largest over the run"),
       gap("final_pose_gap", "Gauss-Seidel vs MuJoCo: the final poses"),
       real("final_pose_gap_over_height", "", "final_pose_gap / the rig's height"),
       integer("free_endpoint_dof", "", "endpoint freedom the control points leave (0: unique)"),
       steps.named("physik_steps_to_converge"), steps.named("mujoco_steps_to_converge"),
       violation.named("physik_limit_violation_deg"), violation.named("mujoco_limit_violation_deg"),
       gap("free_rods_joint_separation", "free rods: the largest joint separation"),
       gap("exact_rms_gap", "exact vs MuJoCo: rms over the run"),
       gap("exact_max_gap", "exact vs MuJoCo: largest over the run"),
       gap("exact_final_pose_gap", "exact vs MuJoCo: the final poses"),
       gap("gauss_seidel_vs_exact_max_gap", "Gauss-Seidel vs exact: largest over the run")});
}

// one scene and mode's rows of gap_over_time.csv (every 5th step) and gaps.csv
void tabulate(const std::string& name, const std::string& m, double h, const Comparison& c,
              const RecordedRun& exact, const ExactGaps& eg, Table& gap_over_time, Table& gaps) {
  const std::size_t n = std::min(c.physik.frames.size(), c.mujoco.frames.size());
  for (std::size_t k = 0; k < n; k += 5) {
    gap_over_time.add(
        {name, m, k + 1, pose_gap(c.physik.frames[k], c.mujoco.frames[k]),
         k < exact.frames.size() ? Cell(pose_gap(exact.frames[k], c.mujoco.frames[k])) : Cell()});
  }
  const auto steps = [](const RunSummary& s) { return s.converged ? s.steps_to_converge : -1; };
  gaps.add({name, m, c.gap.rms_gap, c.gap.max_gap, c.gap.final_pose_gap, c.gap.final_pose_gap / h,
            c.free_endpoint_dof, steps(c.physik.summary), steps(c.mujoco.summary),
            c.physik.summary.max_limit_violation_deg, c.mujoco.summary.max_limit_violation_deg,
            c.free_rods.summary.max_joint_separation, eg.exact_vs_mujoco.rms_gap,
            eg.exact_vs_mujoco.max_gap, eg.exact_vs_mujoco.final_pose_gap,
            eg.gauss_seidel_vs_exact.max_gap});
}

// the same-forces claim of one scene: does Gauss-Seidel approximate the exact dynamics?
void add_claim(Report& report, const std::string& name, double h, const Comparison& c,
               const ExactGaps& eg) {
  const bool unique = c.free_endpoint_dof == 0;
  report.claim(
      "Sec. 3.2: Gauss-Seidel inter-joint forces approximate the exact articulated dynamics (" +
          name + ")",
      "same forces: rms trajectory gap " + num(c.gap.rms_gap) + ", final pose gap " +
          num(c.gap.final_pose_gap) + " (" + num(100 * c.gap.final_pose_gap / h, 2) +
          "% of height); exact vs MuJoCo (same forces) largest gap " +
          num(eg.exact_vs_mujoco.max_gap, 2) + "; " +
          (unique ? "unique equilibrium"
                  : "a family of equilibria (" + std::to_string(c.free_endpoint_dof) +
                        " free endpoint DOF): the final gap is path dependence"),
      !unique                           ? "n/a (path dependent)"
      : c.gap.final_pose_gap < 0.01 * h ? "yes"
                                        : "no");
}

void run(const Context& ctx) {
  const std::vector<std::string> scenes =
      ctx.quick ? std::vector<std::string>{"fig6_elbow_linear"}
                : std::vector<std::string>{"pinhead_two_hands", "fig5_running", "fig6_elbow_linear",
                                           "fig7_cannon_capped"};
  nlohmann::json rows = nlohmann::json::array();
  Report report("PhysIK against MuJoCo (exact constrained dynamics)");
  Table gap_over_time = gap_over_time_table(), gaps = gaps_table();
  nlohmann::json gap_rows = nlohmann::json::array();  // the report's table
  for (const std::string& name : scenes) {
    Scene scene = scene_named(ctx, name);
    if (ctx.quick) scene.steps = 60;
    const RecordedRun exact = exact_run(scene);
    for (ReferenceMode mode : {ReferenceMode::kSameForces, ReferenceMode::kExactConstraints}) {
      const Comparison c = compare_with_mujoco(scene, mode);
      if (name == scenes.front() && mode == ReferenceMode::kSameForces) write_view_runs(ctx, scene);
      const ExactGaps eg = exact_gaps(exact, c);
      const std::string m = to_string(mode);
      const double h = scene.rig.height();
      tabulate(name, m, h, c, exact, eg, gap_over_time, gaps);
      gap_rows.push_back({name, m, gap_cell(c.gap), gap_cell(eg.exact_vs_mujoco),
                          gap_cell(eg.gauss_seidel_vs_exact)});
      // final poses, for drawing side by side
      const std::string tag = name + "_" + m;
      write_bones_table(ctx.out_dir + "/" + tag + "_physik.csv", scene.rig,
                        c.physik.summary.final_frames);
      write_bones_table(ctx.out_dir + "/" + tag + "_mujoco.csv", scene.rig,
                        c.mujoco.summary.final_frames);
      rows.push_back({{"scene", name},
                      {"mode", m},
                      {"comparison", comparison_to_json(scene, c)},
                      {"exact_vs_mujoco", gap_json(eg.exact_vs_mujoco)},
                      {"gauss_seidel_vs_exact", gap_json(eg.gauss_seidel_vs_exact)},
                      {"physik_csv", tag + "_physik.csv"},
                      {"mujoco_csv", tag + "_mujoco.csv"}});
      if (ctx.log) {
        *ctx.log << "  " << name << " " << m << ": rms gap " << c.gap.rms_gap << ", final gap "
                 << c.gap.final_pose_gap << " (" << 100 * c.gap.final_pose_gap / h
                 << "% of height), free endpoint DOF " << c.free_endpoint_dof
                 << "; exact vs MuJoCo max gap " << eg.exact_vs_mujoco.max_gap << "\n";
      }
      if (mode == ReferenceMode::kSameForces) add_claim(report, name, h, c, eg);
    }
  }
  gap_over_time.write_csv(ctx.out_dir);
  gaps.write_csv(ctx.out_dir);
  add_exact_table_and_notes(report, gap_rows);
  write_summary(ctx, {{"experiment", "mujoco_gap"}, {"rows", rows}}, report,
                {&gap_over_time, &gaps});
}

const Registration registered{
    230, {"mujoco_gap", "reference", "PhysIK vs MuJoCo: trajectory and final-pose gaps", run}};

}  // namespace

}  // namespace physik::experiments
