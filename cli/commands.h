// The `physik` command line program: each command family registers itself on the app.
// One file per family (cmd_<family>.cpp); main.cpp only dispatches and maps errors to exit codes.
#pragma once

#include <string>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

namespace physik::cli {

void add_rig_commands(CLI::App& app);
void add_interchange_commands(CLI::App& app);  // after add_rig_commands: adds to `rig`
void add_experiment_commands(CLI::App& app);
void add_simulate_commands(CLI::App& app);
void add_reference_commands(CLI::App& app);
void add_tune_commands(CLI::App& app);
void add_solve_commands(CLI::App& app);
void add_params_commands(CLI::App& app);

// Where a command writes its JSON: a file (created with its parent folders) or stdout for "-" or "".
void write_json(const nlohmann::json& doc, const std::string& path);

}  // namespace physik::cli
