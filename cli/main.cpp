// physik: the testbed's command line program.
// Exit status: 0 success, 1 an unexpected failure, 2 bad input, 3 a diverged run, 4 not converged
// (`physik solve`, `physik equilibrium` or `physik tune`; physik/model/errors.h).
#include <exception>
#include <filesystem>
#include <iostream>

#include "cli/commands.h"
#include "kdl/kdl_solve.h"
#include "physik/model/errors.h"
#include "physik/model/version.h"

int main(int argc, char** argv) {
  CLI::App app{
      "physik: physics-based inverse kinematics testbed (PhysIK engine, MuJoCo reference, "
      "Ceres tuning, classic IK baselines)."};
  app.footer(physik::cli::kExitStatusHelp);  // before the commands: each one inherits it
  app.require_subcommand(1);
  app.set_help_all_flag("--help-all", "Show help for every command");
  app.set_version_flag("--version", physik::kVersion, "Print the version and exit");
  physik::cli::add_rig_commands(app);
  physik::cli::add_interchange_commands(app);
  physik::cli::add_experiment_commands(app);
  physik::cli::add_simulate_commands(app);
  physik::cli::add_reference_commands(app);
  physik::cli::add_tune_commands(app);
  physik::kdl::register_solvers();  // --solver kdl | kdl-nr (kdl/kdl_solve.h)
  physik::cli::add_solve_commands(app);
  physik::cli::add_follow_commands(app);
  physik::cli::add_params_commands(app);
  physik::cli::add_view_commands(app);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);  // prints the usage error
    return physik::kExitBadInput;
  } catch (const physik::InputError& e) {
    std::cerr << "physik: error: " << e.what() << "\n";
    return physik::kExitBadInput;
  } catch (const physik::DivergedRun&) {
    return physik::kExitDiverged;  // already reported by the command
  } catch (const physik::cli::NotConverged&) {
    return physik::kExitNotConverged;  // solve, equilibrium or tune, already reported
  } catch (const std::filesystem::filesystem_error& e) {
    // a path the user gave that the system refuses (the commands name most of them first)
    std::cerr << "physik: error: " << e.path1().string() << ": " << e.code().message() << "\n";
    return physik::kExitBadInput;
  } catch (const std::exception& e) {
    std::cerr << "physik: internal error: " << e.what() << "\n";
    return physik::kExitRuntimeFailure;
  }
  return physik::kExitOk;
}
