#include "physik/io/output_files.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <system_error>

#include "physik/model/errors.h"

namespace physik {

void create_output_dir(const std::string& dir, const std::string& option) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  // create_directories reports an existing folder as no error; a file in the way as one
  if (ec || !std::filesystem::is_directory(dir, ec)) {
    const std::string why = ec ? ec.message() : "a file of that name is in the way";
    throw_input_error(dir, "", option, "cannot create the folder (" + why + ")");
  }
}

namespace {

[[noreturn]] void cannot_write(const std::string& path, const std::string& option) {
  const std::string why = errno != 0 ? std::strerror(errno) : "unknown reason";
  throw_input_error(path, "", option, "cannot write the file (" + why + ")");
}

}  // namespace

void check_output_file(const std::string& path, const std::string& option) {
  const std::filesystem::path p(path);
  if (p.has_parent_path()) create_output_dir(p.parent_path().string(), option);
  std::error_code ec;
  const bool existed = std::filesystem::exists(p, ec);
  errno = 0;
  {
    std::ofstream probe(p, std::ios::app);  // app: an existing file is not truncated
    if (!probe) cannot_write(path, option);
  }
  if (!existed) std::filesystem::remove(p, ec);
}

std::ofstream open_output_file(const std::string& path, const std::string& option) {
  const std::filesystem::path p(path);
  if (p.has_parent_path()) create_output_dir(p.parent_path().string(), option);
  errno = 0;
  std::ofstream out(p);
  if (!out) cannot_write(path, option);
  return out;
}

}  // namespace physik
