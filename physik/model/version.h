// The testbed's version, defined once: `physik --version` prints it (cli/main.cpp) and the Python
// module exports it as physik.__version__ (python/module.cpp). Semantic Versioning 2.0.0
// (semver.org): while the major version is 0, a minor release may change the file formats, the
// command line and the Python API.
#pragma once

namespace physik {

inline constexpr char kVersion[] = "0.1.0";

}  // namespace physik
