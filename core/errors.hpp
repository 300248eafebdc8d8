// Exceptions for user mistakes. Numerical failures are never exceptions: they are statuses.
#pragma once

#include <stdexcept>
#include <string>

namespace c2d {

/// Bad input: a scene, mesh, legacy data file or command-line value. The message is one line that
/// names the place (file:line:column and/or key path), what was expected and what was found.
class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& message) : std::runtime_error(message) {}
};

/// A feature that the input asks for but this build does not provide yet.
class NotSupportedError : public InputError {
 public:
  explicit NotSupportedError(const std::string& message) : InputError(message) {}
};

}  // namespace c2d
