// Errors and process exit codes.
//
// Bad input is caught at the edge (file loaders, CLI) and reported as one line naming the file,
// the element and the field; the engine then trusts its inputs. Exit codes are part of the CLI
// contract: 0 success, 1 an unexpected failure, 2 bad input, 3 a diverged run, 4 not converged
// (`physik solve` or `physik equilibrium` stopped short of its tolerance without diverging: it
// writes its last iterate, says why on stderr and exits 4; `physik tune` when the tuned run
// converges later than the scene's, or never).
#pragma once

#include <stdexcept>
#include <string>

namespace physik {

constexpr int kExitOk = 0;
constexpr int kExitRuntimeFailure = 1;
constexpr int kExitBadInput = 2;
constexpr int kExitDiverged = 3;
constexpr int kExitNotConverged = 4;

// A malformed or contradictory input file or argument. what() is the full one-line message:
// "<file>: <element>: <field>: <reason>".
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A simulation that diverged (non-finite state or energy past its bound). The CLI exits 3.
class DivergedRun : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Compose "<file>: <element>: field '<field>': <reason>", leaving out empty parts.
std::string input_error_message(const std::string& file, const std::string& element,
                                const std::string& field, const std::string& reason);

[[noreturn]] void throw_input_error(const std::string& file, const std::string& element,
                                    const std::string& field, const std::string& reason);

}  // namespace physik
