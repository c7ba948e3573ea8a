// The main() of the benchmark tools (physik_count, physik_solve_cost): parse the options, run, and
// map each failure to the project's exit status (2 bad input, 1 an unexpected failure) with one
// line on stderr naming the tool.
#pragma once

#include <exception>
#include <iostream>

#include <CLI/CLI.hpp>

#include "physik/model/errors.h"

namespace physik::bench {

template <class Run>
int tool_main(const char* name, CLI::App& app, int argc, char** argv, Run run) {
  try {
    app.parse(argc, argv);
    return run();
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return kExitBadInput;
  } catch (const InputError& e) {
    std::cerr << name << ": error: " << e.what() << "\n";
    return kExitBadInput;
  } catch (const std::exception& e) {
    std::cerr << name << ": internal error: " << e.what() << "\n";
    return kExitRuntimeFailure;
  }
}

}  // namespace physik::bench
