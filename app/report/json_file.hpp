// Reading a JSON file that a user could have edited (a study's study.json, a case's summary.json)
// without trusting it: only a regular file is opened (a FIFO would block the reader for ever, a
// device could stream without end), its size is bounded, and its nesting is bounded before
// nlohmann parses it (dumping, copying and comparing a parsed value recurse once per level: a
// study.json of 60,000 '[' overflowed the stack of `contact2d merge`).
#pragma once

#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

namespace c2d::app {

/// The bounds a JSON input file must keep.
struct JsonFileLimits {
  std::size_t max_bytes = 64u << 20;  ///< 64 MiB: a summary.json is a few kB, a study.json less
  int max_depth = 64;                 ///< nested arrays and objects (a summary.json uses 5)
};

/// What reading a JSON file gave: its value, or why it has none.
struct JsonFileRead {
  nlohmann::json value;  ///< null when `error` is set
  std::string error;     ///< empty when read; else one clause: what was expected, what found
  bool ok() const { return error.empty(); }
};

/// The bytes of PATH when it is a regular file of at most `max_bytes`; otherwise "" and `error`
/// says why (not found, not a regular file, too large, unreadable). Never opens anything but a
/// regular file: the type is checked before opening, and again on the open descriptor.
std::string read_regular_file(const std::string& path, std::size_t max_bytes, std::string& error);

/// `text` parsed as JSON when its nesting stays within `limits.max_depth` (checked on the bytes
/// before parsing); else `error` names the byte offset and what was found.
JsonFileRead parse_json_text(std::string_view text, const JsonFileLimits& limits = {});

/// PATH read (read_regular_file) and parsed (parse_json_text); never throws for what the file
/// holds.
JsonFileRead try_read_json_file(const std::string& path, const JsonFileLimits& limits = {});

/// The same, throwing InputError "PATH: <error>" when it cannot be read or parsed.
nlohmann::json read_json_file(const std::string& path, const JsonFileLimits& limits = {});

/// A found JSON value for a message: its type and the start of its text ("number 3",
/// "string \"x\"", "null"), at most about 60 characters.
std::string shown_json(const nlohmann::json& j);

}  // namespace c2d::app
