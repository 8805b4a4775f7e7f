#pragma once
// Errors that reach the user: one clear sentence naming the file and the problem.
#include <stdexcept>
#include <string>

namespace mpmvs {

class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

// Throws Error(path + ": " + what).
[[noreturn]] inline void ThrowFileError(const std::string& path, const std::string& what) {
  throw Error(path + ": " + what);
}

}  // namespace mpmvs
