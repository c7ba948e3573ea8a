#include "reference/compare.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>

#include <Eigen/SVD>

#include "physik/io/json_fields.h"
#include "physik/io/output_files.h"
#include "physik/io/pose_io.h"
#include "physik/io/run_folder.h"
#include "physik/io/summary_io.h"
#include "physik/model/errors.h"

namespace physik {

ReferenceMode parse_reference_spec(const std::string& spec, const std::string& source) {
  if (spec == "mujoco" || spec == "mujoco:same-forces") return ReferenceMode::kSameForces;
  if (spec == "mujoco:exact-constraints") return ReferenceMode::kExactConstraints;
  throw_input_error(source, "", spec,
                    "expected mujoco, mujoco:same-forces or mujoco:exact-constraints");
}

double pose_gap(const BoneFrames& a, const BoneFrames& b) {
  double g = 0.0;
  for (std::size_t i = 0; i < a.head_world.size(); ++i) {
    g = std::max({g, (a.head_world[i] - b.head_world[i]).norm(),
                  (a.tail_world[i] - b.tail_world[i]).norm()});
  }
  return g;
}

namespace {

double squared_gap_sum(const BoneFrames& a, const BoneFrames& b) {
  double s = 0.0;
  for (std::size_t i = 0; i < a.head_world.size(); ++i) {
    s += (a.head_world[i] - b.head_world[i]).squaredNorm() +
         (a.tail_world[i] - b.tail_world[i]).squaredNorm();
  }
  return s;
}

int matrix_rank(const Eigen::MatrixXd& a) {
  if (a.size() == 0) return 0;
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(a);
  const auto& sv = svd.singularValues();
  const double tol = 1e-9 * std::max(1.0, sv(0));
  int r = 0;
  for (int k = 0; k < sv.size(); ++k) r += sv(k) > tol ? 1 : 0;
  return r;
}

}  // namespace

GapStats trajectory_gap(const std::vector<BoneFrames>& a, const std::vector<BoneFrames>& b,
                        const BoneFrames& final_a, const BoneFrames& final_b) {
  GapStats g;
  g.steps_compared = static_cast<int>(std::min(a.size(), b.size()));
  double sum = 0.0;
  long count = 0;
  for (int k = 0; k < g.steps_compared; ++k) {
    sum += squared_gap_sum(a[k], b[k]);
    count += 2 * static_cast<long>(a[k].head_world.size());
    g.max_gap = std::max(g.max_gap, pose_gap(a[k], b[k]));
  }
  g.rms_gap = count ? std::sqrt(sum / count) : 0.0;
  g.final_pose_gap = pose_gap(final_a, final_b);
  g.final_pose_rms_gap = std::sqrt(squared_gap_sum(final_a, final_b) /
                                   std::max<std::size_t>(1, 2 * final_a.head_world.size()));
  return g;
}

int free_endpoint_dof(const Scene& scene, const BoneFrames& frames) {
  const Rig& rig = scene.rig;
  MjcfOptions o;
  o.joints = JointModel::kRigJoints;
  o.dt = scene.params.dt;
  o.source = scene.rig_file;
  const MjModelPtr m = rig_to_mjmodel(rig, o);
  const MjDataPtr d = make_rig_mjdata(rig, o, m.get());
  SimState s;
  init_state(scene, s);
  s.frames = frames;
  for (int i = 0; i < rig.nbone; ++i) {
    s.com_world[i] = 0.5 * (frames.head_world[i] + frames.tail_world[i]);
    s.vel_world[i].setZero();
    s.omega_world[i].setZero();
  }
  local_rotations_from_world(rig, frames, s.pose);
  set_mujoco_state(rig, s, m.get(), d.get());
  mj_forward(m.get(), d.get());

  // rows: 3 per control point, then 3 per bone endpoint
  const int nv = m->nv, nc = static_cast<int>(scene.control_points.size());
  Eigen::MatrixXd jc(3 * nc, nv), je(6 * rig.nbone, nv);
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> jacp(3, nv);
  const auto jac_at = [&](int bone, const Vec3& point) {
    const mjtNum p[3] = {point.x(), point.y(), point.z()};
    mj_jac(m.get(), d.get(), jacp.data(), nullptr, p, bone + 1);
    return Eigen::MatrixXd(jacp);
  };
  for (int c = 0; c < nc; ++c) {
    const ControlPoint& cp = scene.control_points[c];
    jc.middleRows(3 * c, 3) = jac_at(cp.bone, point_on_bone(frames, cp.bone, cp.alpha));
  }
  for (int i = 0; i < rig.nbone; ++i) {
    je.middleRows(6 * i, 3) = jac_at(i, frames.head_world[i]);
    je.middleRows(6 * i + 3, 3) = jac_at(i, frames.tail_world[i]);
  }
  Eigen::MatrixXd both(jc.rows() + je.rows(), nv);
  both << jc, je;
  return matrix_rank(both) - matrix_rank(jc);
}

RecordedRun record_mujoco(const Scene& scene, ReferenceMode mode, const RecordOptions& options,
                          const StepObserver& also) {
  Recorder rec(scene, options);
  RunSummary summary = run_mujoco(
      scene, mode,
      [&](const SimState& s, const StepStats& st) {
        rec.observe(s, st);
        if (also && s.step > 0) also(s, st);
      },
      rec.wants_initial());
  return rec.finish(std::move(summary));
}

Comparison compare_with_mujoco(const Scene& scene, ReferenceMode mode,
                               const RecordOptions& mujoco_record) {
  RecordOptions every_frame;
  every_frame.all_frames = true;
  RecordOptions mujoco_options = mujoco_record;
  mujoco_options.all_frames = true;
  Comparison c;
  c.mode = mode;
  c.physik = record_run(scene, every_frame);
  c.mujoco = record_mujoco(scene, mode, mujoco_options);
  Scene free_scene = scene;  // free rods are a form of the gauss-seidel scheme
  free_scene.params.scheme = Scheme::kGaussSeidel;
  free_scene.params.free_rods = true;
  c.free_rods = record_run(free_scene, every_frame);
  c.gap = trajectory_gap(c.physik.frames, c.mujoco.frames, c.physik.summary.final_frames,
                         c.mujoco.summary.final_frames);
  c.free_rods_gap = trajectory_gap(c.free_rods.frames, c.mujoco.frames,
                                   c.free_rods.summary.final_frames, c.mujoco.summary.final_frames);
  c.free_endpoint_dof = free_endpoint_dof(scene, c.mujoco.summary.final_frames);
  return c;
}

namespace {

nlohmann::json run_json(const RunSummary& s) {
  return {{"steps_run", s.steps_run},
          {"converged", s.converged},
          {"steps_to_converge",
           s.steps_to_converge < 0 ? nlohmann::json(nullptr) : nlohmann::json(s.steps_to_converge)},
          {"diverged", s.diverged},
          {"divergence_reason", s.divergence_reason},
          {"max_limit_violation_deg", s.max_limit_violation_deg},
          {"max_joint_separation", s.max_joint_separation},
          {"final_residuals", s.final_residuals},
          {"final_kinetic_energy", s.final_kinetic_energy},
          {"wall_time_s", s.wall_time_s}};
}

nlohmann::json gap_json(const GapStats& g, double height) {
  return {{"steps_compared", g.steps_compared},
          {"rms_gap", g.rms_gap},
          {"max_gap", g.max_gap},
          {"final_pose_gap", g.final_pose_gap},
          {"final_pose_rms_gap", g.final_pose_rms_gap},
          {"rms_gap_over_height", g.rms_gap / height},
          {"max_gap_over_height", g.max_gap / height},
          {"final_pose_gap_over_height", g.final_pose_gap / height}};
}

}  // namespace

std::vector<std::string> diverged_runs(const Comparison& c) {
  std::vector<std::string> out;
  if (c.physik.summary.diverged) out.push_back("physik");
  if (c.mujoco.summary.diverged) out.push_back("mujoco");
  return out;
}

nlohmann::json comparison_to_json(const Scene& scene, const Comparison& c) {
  // over the height, or the mean bone length for a flat rig (no inf or nan: Rig::reference_length)
  const double h = scene.rig.reference_length();
  const std::vector<std::string> diverged = diverged_runs(c);
  // a gap to a run that blew up measures nothing: the gaps are null then
  nlohmann::json j = gap_json(c.gap, h);
  if (!diverged.empty()) {
    for (auto& [key, value] : j.items()) value = nullptr;
  }
  j["diverged"] = diverged;
  j["scene"] = scene.file;
  j["rig"] = scene.rig_file;
  j["mode"] = to_string(c.mode);
  j["mujoco_version"] = mj_versionString();
  j["physik_scheme"] = to_string(scene.params.scheme);
  j["rig_height"] = scene.rig.height();
  j["free_endpoint_dof"] = c.free_endpoint_dof;
  j["equilibrium"] =
      c.free_endpoint_dof == 0
          ? "unique: the control points fix every bone endpoint; the final gap measures the "
            "joint-force heuristic"
          : "family: the control points leave " + std::to_string(c.free_endpoint_dof) +
                " endpoint degrees of freedom free; the final gap measures path dependence";
  j["physik"] = run_json(c.physik.summary);
  j["mujoco"] = run_json(c.mujoco.summary);
  j["mujoco"]["mean_solver_iterations"] = c.mujoco.summary.mean_passes_per_step;
  j["physik"]["mean_passes_per_step"] = c.physik.summary.mean_passes_per_step;
  j["free_rods"] = gap_json(c.free_rods_gap, h);
  j["free_rods"]["max_joint_separation"] = c.free_rods.summary.max_joint_separation;
  j["free_rods"]["run"] = run_json(c.free_rods.summary);
  j["notes"] = {
      "gaps: bone head/tail distances (rig units) between PhysIK and MuJoCo after the same step",
      "same-forces: MuJoCo gets PhysIK's control, torsion and damping forces from its own state, "
      "with ball joints; exact-constraints: the rig's joint types and limits, no torsion springs",
      "angular velocity factor f applied in MuJoCo as the torque I (f - 1) w / dt per body",
      "MuJoCo 'passes' in mujoco/trajectory.csv are constraint-solver iterations; its "
      "joint_mismatch is 0 (exact joints)"};
  return j;
}

namespace {

// a MuJoCo run's summary.json: simulate's keys, the engine and the mode
nlohmann::json mujoco_summary_json(const Scene& scene, const RunSummary& s, ReferenceMode mode) {
  nlohmann::json sum = summary_to_json(scene, s);
  sum["engine"] = std::string("mujoco ") + mj_versionString();
  sum["mode"] = to_string(mode);
  sum["passes_are"] = "MuJoCo constraint-solver iterations";
  return sum;
}

}  // namespace

RunSummary write_reference_run_folder(const Scene& scene, ReferenceMode mode,
                                      const std::string& dir, int every) {
  RunFolderWriter folder(scene, dir, "--out");
  RecordedRun run = record_mujoco(scene, mode, folder.record_options(every));
  folder.finish(mujoco_summary_json(scene, run.summary, mode), run.summary.final_frames);
  return std::move(run.summary);
}

nlohmann::json write_reference_comparison(const Scene& scene, const std::string& spec,
                                          const std::string& out_dir, int every, bool verbose) {
  const ReferenceMode mode = parse_reference_spec(spec);
  if (verbose)
    std::cerr << "reference: MuJoCo " << mj_versionString() << ", " << to_string(mode) << "\n";
  // the reference run as a run folder of its own (physik/io/run_folder.h), beside PhysIK's
  RunFolderWriter folder(scene, out_dir + "/" + kReferenceFolder, "--out");
  const Comparison c = compare_with_mujoco(scene, mode, folder.record_options(every));
  folder.finish(mujoco_summary_json(scene, c.mujoco.summary, mode), c.mujoco.summary.final_frames);
  const nlohmann::json j = comparison_to_json(scene, c);
  write_json(j, out_dir + "/" + kComparisonFile);
  if (verbose && j["diverged"].empty()) {
    std::cerr << "reference: rms gap " << c.gap.rms_gap << ", max gap " << c.gap.max_gap
              << ", final pose gap " << c.gap.final_pose_gap << " ("
              << j["equilibrium"].get<std::string>() << ") -> " << out_dir << "/" << kComparisonFile
              << "\n";
  }
  return j;
}

}  // namespace physik
