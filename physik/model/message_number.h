// Numbers in the messages a user reads (warnings, divergence hints): %g style, 3 significant
// digits, enough to act on.
#pragma once

#include <sstream>
#include <string>

namespace physik {

inline std::string message_number(double v) {
  std::ostringstream o;
  o.precision(3);
  o << v;
  return o.str();
}

}  // namespace physik
