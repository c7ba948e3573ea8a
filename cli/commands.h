// The `physik` command line program: each command family registers itself on the app.
// One file per family (cmd_<family>.cpp); main.cpp only dispatches and maps errors to exit codes.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace physik {
struct Scene;
struct BvhWriteReport;
}  // namespace physik

namespace physik::cli {

// The start-contact check (physik/engine/start_contacts.h) as every command that runs a scene
// reports it: its warning on stderr, named by the scene's file; a start through the ground or a
// box throws InputError (exit 2). Defined in cmd_simulate.cpp.
void warn_start_contacts(const Scene& scene);

// What a BVH written on a rig's source skeleton could not hold (bvh.h BvhWriteReport), one
// "physik: warning: <path>: ..." line each; and the help of the --own-skeleton flag that writes
// the rig's own skeleton instead. Defined in cmd_interchange.cpp.
void print_bvh_report(const std::string& path, const BvhWriteReport& report);
inline constexpr const char* kOwnSkeletonHelp =
    "Write the rig's own skeleton (one joint per bone, rig units and axes as --axes/--scale say) "
    "instead of its source skeleton (a rig made by `rig from-bvh` keeps the file's joints, "
    "channels, units and axes, and writes them by default)";

// Every command's --help ends with this (main.cpp sets it as the app's footer before the
// commands are added, and CLI11 copies a parent's footer into each subcommand it creates);
// physik/model/errors.h has the codes.
inline constexpr const char* kExitStatusHelp =
    "Exit status: 0 success, 1 an unexpected failure, 2 bad input, 3 a diverged run.";

// `physik solve`: a solve that stopped short of its tolerance (stalled, or out of iterations or
// steps) without diverging. It writes its last pose and summary.json, says why on stderr, and
// the CLI exits with kExitNotConverged (errors.h).
inline constexpr const char* kSolveExitStatusHelp =
    "Exit status: 0 success, 1 an unexpected failure, 2 bad input, 3 a diverged run, 4 not "
    "converged (the solve stopped short of its tolerance; final_pose.csv and summary.json hold "
    "its last pose).";
// `physik equilibrium`: Ceres stopped before converging (its output holds the last iterate).
inline constexpr const char* kEquilibriumExitStatusHelp =
    "Exit status: 0 success, 1 an unexpected failure, 2 bad input, 3 a diverged run (--compare's "
    "PhysIK run), 4 not converged (Ceres stopped short; the output holds its last iterate).";
// `physik tune`: the tuned run converges later than the scene's, or not at all (the tuned scene
// is written; stderr says both measures).
inline constexpr const char* kTuneExitStatusHelp =
    "Exit status: 0 success, 1 an unexpected failure, 2 bad input, 3 a diverged run (every "
    "candidate, the tuned run, or the mujoco objective's MuJoCo reference), 4 the tuned run "
    "converges later than the scene's (stderr: \"converged later\") or never (\"not "
    "converged\"); --out still holds the tuned values: 0 only when the tuned run converges no "
    "later than the scene's.";
// --orientation-target BONE=w,x,y,z, --aim BONE=x,y,z and --pin BONE[=x,y,z], repeated, as
// simulate and solve take them: added to the scene after it is read, checked as the scene file's
// bone targets (InputError naming the option, the value, the field and the reason). Defined in
// bone_target_options.cpp.
struct BoneTargetOptions {
  std::vector<std::string> orientation, aim, pin;
};
void add_bone_target_options(CLI::App* cmd, BoneTargetOptions& o);
void apply_bone_target_options(const BoneTargetOptions& o, Scene& scene);

class NotConverged : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

void add_rig_commands(CLI::App& app);
void add_interchange_commands(CLI::App& app);  // after add_rig_commands: adds to `rig`
void add_experiment_commands(CLI::App& app);
void add_simulate_commands(CLI::App& app);
void add_reference_commands(CLI::App& app);
void add_tune_commands(CLI::App& app);
void add_solve_commands(CLI::App& app);
void add_params_commands(CLI::App& app);
void add_view_commands(CLI::App& app);
void add_follow_commands(CLI::App& app);

}  // namespace physik::cli
