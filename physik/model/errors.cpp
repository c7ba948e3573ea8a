#include "physik/model/errors.h"

namespace physik {

std::string input_error_message(const std::string& file, const std::string& element,
                                const std::string& field, const std::string& reason) {
  std::string msg = file.empty() ? std::string("<input>") : file;
  if (!element.empty()) msg += ": " + element;
  if (!field.empty()) msg += ": field '" + field + "'";
  msg += ": " + reason;
  return msg;
}

void throw_input_error(const std::string& file, const std::string& element,
                       const std::string& field, const std::string& reason) {
  throw InputError(input_error_message(file, element, field, reason));
}

}  // namespace physik
