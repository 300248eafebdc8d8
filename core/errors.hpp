// Exceptions for user mistakes. Numerical failures are never exceptions: they are statuses.
#pragma once

#include <cstdio>
#include <stdexcept>
#include <string>
#include <string_view>

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

/// Text found in an input file, for an error message: single-quoted, at most 60 characters
/// (then "..."), every control or non-ASCII byte written as \xNN, so that a binary file's bytes
/// never reach the terminal.
inline std::string quoted_found(std::string_view text) {
  constexpr size_t kMax = 60;
  std::string out = "'";
  for (size_t i = 0; i < text.size() && i < kMax; ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c >= 0x20 && c < 0x7f) {
      out += static_cast<char>(c);
    } else {
      char hex[5];
      std::snprintf(hex, sizeof hex, "\\x%02x", c);
      out += hex;
    }
  }
  if (text.size() > kMax) out += "...";
  return out + "'";
}

/// A number as a message shows it: `digits` significant digits, no trailing zeros ("1", "0.504",
/// "1e-09", "1e+30"), never printf's %f, whose six fixed decimals print 1 as "1.000000" and a
/// small value as "0.000000" (std::to_string(double) is %f).
inline std::string number_text(double v, int digits = 6) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}

}  // namespace c2d
