// One recorder for every run that keeps more than its summary (`physik simulate`, the MuJoCo side
// of `simulate --reference`, the comparison with MuJoCo, the experiments): a step observer that
// writes the trajectory table and keeps what its options ask for.
//
// The trajectory table (docs/engine.md "Run outputs"), one row per recorded step:
//   step,time,kinetic_energy,passes,joint_mismatch,joint_separation,residual_<name>...,
//   <bone>.head_x ... <bone>.tail_z
// time in s, KE in J, residuals (each control point to its goal target, named after the point,
// or its index when it has no name) and positions (world) in rig units, 9 significant digits.
// Step 0 is the initial state; step k (1 for the first step) gets a row when k % every == 0, or
// when the row rule adds it (k == scene.steps, or k == 1); a row with a non-finite value (a
// diverging state) is never written: the divergence is reported in the summary. `passes` is the
// joint solve's passes (gauss-seidel), 1 (exact), or the substeps of the implicit step.
#pragma once

#include <fstream>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

#include "physik/engine/run_summary.h"
#include "physik/io/contacts_table.h"
#include "physik/io/targets_limits.h"
#include "physik/model/scene.h"

namespace physik {

// Which steps besides every N-th get a trajectory row.
enum class RowRule {
  kEveryAndLast,   // and the scene's last step, scene.steps (`physik simulate`, simulate
                   // --reference)
  kEveryAndFirst,  // and step 1 (the experiments' tables)
};

// The residual columns' names: residual_<control point name> (its index when it has none),
// unique, CSV-quoted where needed.
std::vector<std::string> residual_column_names(const Scene& scene);

// The one writer of the trajectory table.
class TrajectoryCsv {
 public:
  // Writes the header to `out`, which must outlive the writer.
  TrajectoryCsv(const Scene& scene, std::ostream& out, int every, RowRule rule);

  // Step `step` gets a row under the rule.
  bool wants(int step) const;
  // One row for the state after a step; false (nothing written) if a value is not finite.
  // `residuals`: one per control point, rig units (engine.h control_residuals).
  bool write_row(const SimState& state, const StepStats& stats,
                 const std::vector<double>& residuals);

 private:
  std::ostream& out_;
  int every_;
  RowRule rule_;
  int last_step_;            // scene.steps
  std::vector<double> row_;  // KE, mismatch, separation, residuals, bone values: reused per row
};

struct RecordOptions {
  // the trajectory table: to csv_path (opened here; InputError naming it if it cannot be), or to
  // csv_stream (the caller's, which reports its own errors); neither = no table
  std::string csv_path;
  std::ostream* csv_stream = nullptr;
  int csv_every = 1;  // a row every N steps (N >= 1)
  RowRule csv_rows = RowRule::kEveryAndLast;
  // the targets-and-limits table (targets_limits.h), a row beside every trajectory row written
  // (the caller's stream; needs the trajectory table)
  std::ostream* targets_limits_stream = nullptr;
  // the contacts table (contacts_table.h), the state's contacts beside every trajectory row
  // written (the caller's stream; needs the trajectory table)
  std::ostream* contacts_stream = nullptr;
  // kept in memory
  bool all_frames = false;       // the frames after every step
  std::vector<int> frame_steps;  // else only at these steps (0 = the initial pose, kept first)
  bool stats = false;            // every step's StepStats (KE, passes, ...)
  bool residuals = false;        // every step's control residuals
  bool poses = false;            // every step's local pose
};

// What a recorder kept. Per-step vectors are indexed by step - 1 while the run lasts.
struct RecordedRun {
  RunSummary summary;
  std::vector<int> frame_steps;    // the step of every kept frame
  std::vector<BoneFrames> frames;  // the poses at those steps
  std::vector<StepStats> stats;    // per step, when asked
  std::vector<std::vector<double>>
      residuals;            // per step, per control point (rig units), when asked
  std::vector<Pose> poses;  // per step, when asked
};

class Recorder {
 public:
  // The scene must outlive the recorder. Opens the table (header written) and keeps the initial
  // pose if step 0 is among the frame steps.
  Recorder(const Scene& scene, RecordOptions options);
  Recorder(const Recorder&) = delete;  // its observer points at it
  Recorder& operator=(const Recorder&) = delete;

  // The observer to hand to a run (run_scene, run_mujoco); valid while the recorder lives.
  StepObserver observer();
  // Record one step (what the observer calls); step 0, the initial state, gets its table row
  // only.
  void observe(const SimState& state, const StepStats& stats);
  // The run should show it the initial state (run_scene's observe_initial): it writes a table.
  bool wants_initial() const { return csv_ != nullptr; }
  // The recording with the run's summary; flushes the table. Call once, after the run.
  RecordedRun finish(RunSummary summary);

 private:
  bool wants_frame(int step) const;
  void write_rows(const SimState& state, const StepStats& stats);

  const Scene& scene_;
  RecordOptions opt_;
  std::ofstream file_;
  std::unique_ptr<TrajectoryCsv> csv_;
  std::unique_ptr<TargetsLimitsCsv> targets_limits_;
  std::unique_ptr<ContactsCsv> contacts_;
  std::vector<double> res_;  // this step's control residuals
  RecordedRun run_;
};

// Run the PhysIK engine on a scene with a recorder; `also` (if given) sees every step after it.
RecordedRun record_run(const Scene& scene, const RecordOptions& options,
                       const StepObserver& also = nullptr);

// A bones table (pose_io.h) for each recorded frame: <folder>/<prefix><step>.csv. Returns the
// file names (relative to the folder).
std::vector<std::string> write_frames(const Scene& scene, const RecordedRun& run,
                                      const std::string& folder, const std::string& prefix);

}  // namespace physik
