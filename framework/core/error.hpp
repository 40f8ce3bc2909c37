#pragma once
// Errors a user can act on: every message names where (file, line or key), what is wrong
// and what is valid. The application turns them into a message and a non-zero exit.
#include <stdexcept>
#include <string>

namespace rockdem {

class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& what) : std::runtime_error(what) {}
};

// A run that went unstable (NaN, runaway velocity). Thrown after the last good state is kept.
class InstabilityError : public std::runtime_error {
 public:
  explicit InstabilityError(const std::string& what) : std::runtime_error(what) {}
};

}  // namespace rockdem
