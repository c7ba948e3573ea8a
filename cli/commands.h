// The `physik` command line program: each command family registers itself on the app.
// One file per family (cmd_<family>.cpp); main.cpp only dispatches and maps errors to exit codes.
#pragma once

#include <CLI/CLI.hpp>

namespace physik::cli {

// Every command's --help ends with this (main.cpp sets it as the app's footer before the
// commands are added, and CLI11 copies a parent's footer into each subcommand it creates);
// physik/model/errors.h has the codes.
inline constexpr const char* kExitStatusHelp =
    "Exit status: 0 success, 1 an unexpected failure, 2 bad input, 3 a diverged run.";

void add_rig_commands(CLI::App& app);
void add_interchange_commands(CLI::App& app);  // after add_rig_commands: adds to `rig`
void add_experiment_commands(CLI::App& app);
void add_simulate_commands(CLI::App& app);
void add_reference_commands(CLI::App& app);
void add_tune_commands(CLI::App& app);
void add_solve_commands(CLI::App& app);
void add_params_commands(CLI::App& app);
void add_view_commands(CLI::App& app);

}  // namespace physik::cli
