// Blender's own IK (iTaSC) as an outside peer for the experiments (Fig 9): find Blender, run
// blender/itasc_solve.py on a scene file, read its pose back. Blender is optional: when it is
// absent, fails or hangs, the run says why in one line and the experiment goes on without it.
//
// Finding Blender: the environment variable PHYSIK_BLENDER, when set, is the binary (a path, or
// a name looked up on PATH); "none", "off" or "0" turn the peer off. Unset: `blender` on PATH.
//
// The run, with no shell (arguments passed as they are, so paths need no quoting):
//   BLENDER -b --factory-startup --python-exit-code 1 --python SCRIPT --
//       --scene SCENE --out DIR/itasc_final.csv --report DIR/itasc_report.json
//       --pose DIR/itasc_pose.json
// stdout and stderr go to DIR/itasc_log.txt; killed after the timeout. The bones CSV is what
// Blender posed; the pose file (the scene format's initial_pose) is rebuilt here with the rig's
// forward kinematics, so the full pose (rolls included) is measured by the same code as the
// other solvers, and its heads and tails are checked against the CSV (fk_gap). On any failure
// itasc_final.csv is removed, so no figure shows an unchecked pose.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "physik/model/kinematics.h"
#include "physik/model/scene.h"

namespace physik::experiments {

struct BlenderLocation {
  std::string path;     // the binary; empty when there is none to use
  std::string why_not;  // when path is empty: one line saying why
};
BlenderLocation find_blender();

struct ItascRun {
  std::string status = "absent";  // "ok" (solved and read back), "absent", "failed"
  std::string reason;             // when not ok: one line
  std::string blender;            // the binary used
  nlohmann::json report;          // itasc_solve.py's report (mode, solver, chains, residuals, ...)
  Pose pose;                      // the solved pose (from the pose file)
  BoneFrames frames;              // its forward kinematics on the scene's rig
  double fk_gap = 0.0;            // largest |FK - bones CSV| over heads and tails, rig units
  double seconds = 0.0;           // wall time of the Blender run
  bool ok() const { return status == "ok"; }
};

// The largest allowed fk_gap: Blender keeps bones in single precision (~1e-7 of their size);
// 1e-5 of the rig's height means the pose file and the bones describe the same pose.
constexpr double kItascFkGapFraction = 1e-5;

// Solve scene (its file, scene.file, is what Blender reads) with iTaSC via `script`
// (blender/itasc_solve.py), outputs in out_dir. Never throws for Blender's failures.
ItascRun run_itasc(const Scene& scene, const std::string& script, const std::string& out_dir,
                   double timeout_seconds = 300.0);

}  // namespace physik::experiments
