// The targets-and-limits table of a run folder (targets_and_limits.csv): what a viewer needs
// beside trajectory.csv and cannot rebuild from heads and tails. A bone's twist about its own
// axis moves neither end, so a bone past a joint limit cannot be told from trajectory.csv; and
// an interpolated target (linear, polar) is the engine's, not the scene file's.
//
//   step,<cp>.target_x,<cp>.target_y,<cp>.target_z,...,<bone>.limit_excess_x,..._y,..._z,...,
//   <bone>.orient_w,..._x,..._y,..._z,...
//
// One row per row of trajectory.csv (the recorder writes both together, same steps):
//   <cp>.target_*        the target the control point's spring pulls toward after the step
//                        (SimState::target_effective_world), world, rig units; named like the
//                        residual columns (the index when the point has no name)
//   <bone>.limit_excess_* the signed excess of the bone's joint angle past its limit on each
//                        local axis (physik/model/joint_angles.h), rad; 0 within the limits
//   <bone>.orient_*      the bone's orientation, the unit quaternion world <- bone (w, x, y, z):
//                        its local axes in the world, twist included (the viewer draws them)
// Names are CSV-quoted where they need it (RFC 4180), 9 significant digits.
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "physik/engine/state.h"
#include "physik/model/scene.h"

namespace physik {

// The file's name in a run folder.
inline constexpr const char* kTargetsLimitsFile = "targets_and_limits.csv";

// The column names after `step`, CSV-quoted: every control point's target, every bone's excess,
// every bone's orientation.
std::vector<std::string> targets_limits_column_names(const Scene& scene);

class TargetsLimitsCsv {
 public:
  // Writes the header to `out`, which must outlive the writer.
  TargetsLimitsCsv(const Scene& scene, std::ostream& out);
  // One row for the state after a step (or the initial state); false (nothing written) if a
  // value is not finite.
  bool write_row(const SimState& state);

 private:
  const Scene& scene_;
  std::ostream& out_;
  std::vector<Vec3> angles_, excess_;  // per bone, reused per row
};

}  // namespace physik
