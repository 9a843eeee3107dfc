#pragma once
// The one exception type for bad input. Messages name the file, and the line or field,
// so that a user can find the mistake; the command line prints them and exits non-zero.

#include <stdexcept>
#include <string>

namespace omnidso {

class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

// "FILE: MESSAGE", "FILE:LINE: MESSAGE" or "FILE: field 'NAME': MESSAGE".
inline Error fileError(const std::string& file, const std::string& message) {
  return Error(file + ": " + message);
}
inline Error fileError(const std::string& file, int line, const std::string& message) {
  return Error(file + ":" + std::to_string(line) + ": " + message);
}
inline Error fieldError(const std::string& file, const std::string& field,
                        const std::string& message) {
  return Error(file + ": field '" + field + "': " + message);
}

}  // namespace omnidso
