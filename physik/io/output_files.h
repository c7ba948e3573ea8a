// Output folders and files the user names (--out, --report, --bones, ...): created or opened
// here, so that a path that cannot be written is bad input (exit 2) naming the path, the option
// and the system's reason, never an internal error.
#pragma once

#include <fstream>
#include <string>

namespace physik {

// Creates `dir` and its parents (an existing folder is fine). InputError
// "<dir>: field '<option>': cannot create the folder (<reason>)".
void create_output_dir(const std::string& dir, const std::string& option);

// Opens `path` for writing, creating its parent folders. InputError
// "<path>: field '<option>': cannot write the file (<reason>)".
std::ofstream open_output_file(const std::string& path, const std::string& option);

// The same checks before the work, so a long command fails at once on a path it could not
// write: the parent folders are created, the file is neither created nor changed.
void check_output_file(const std::string& path, const std::string& option);

}  // namespace physik
