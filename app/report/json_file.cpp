#include "app/report/json_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <filesystem>

#include "core/errors.hpp"

namespace fs = std::filesystem;

namespace c2d::app {

namespace {

/// What a path that is not a regular file is, for "expected a regular file, found ...".
std::string file_kind(fs::file_type type) {
  switch (type) {
    case fs::file_type::directory:
      return "a folder";
    case fs::file_type::fifo:
      return "a FIFO";
    case fs::file_type::character:
      return "a character device";
    case fs::file_type::block:
      return "a block device";
    case fs::file_type::socket:
      return "a socket";
    default:
      return "something else";
  }
}

std::string file_kind(mode_t mode) {
  if (S_ISDIR(mode)) return file_kind(fs::file_type::directory);
  if (S_ISFIFO(mode)) return file_kind(fs::file_type::fifo);
  if (S_ISCHR(mode)) return file_kind(fs::file_type::character);
  if (S_ISBLK(mode)) return file_kind(fs::file_type::block);
  if (S_ISSOCK(mode)) return file_kind(fs::file_type::socket);
  return file_kind(fs::file_type::unknown);
}

std::string too_large(std::size_t max_bytes, const std::string& found) {
  return "expected a file of at most " + std::to_string(max_bytes) + " bytes, found " + found;
}

/// Reads the open regular file `fd` (at most max_bytes + 1 bytes, so that growth is seen).
std::string read_descriptor(int fd, std::size_t max_bytes, std::string& error) {
  std::string text;
  char buffer[1 << 16];
  while (text.size() <= max_bytes) {
    const ssize_t n = ::read(fd, buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      error = std::string("cannot read: ") + std::strerror(errno);
      return "";
    }
    if (n == 0) return text;
    text.append(buffer, static_cast<std::size_t>(n));
  }
  error = too_large(max_bytes, "more");
  return "";
}

/// The first byte at which arrays and objects nest deeper than `max_depth` (brackets inside
/// strings do not count), npos when none: the depth nlohmann's parser would reach there.
std::size_t too_deep_at(std::string_view text, int max_depth) {
  int depth = 0;
  bool in_string = false, escaped = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (escaped)
        escaped = false;
      else if (c == '\\')
        escaped = true;
      else if (c == '"')
        in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > max_depth) return i;
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
  return std::string_view::npos;
}

/// nlohmann's message without its "[json.exception...] " tag, printable ASCII only.
std::string parse_message(const std::string& what) {
  const std::size_t tag_end = what.find("] ");
  std::string text = tag_end == std::string::npos ? what : what.substr(tag_end + 2);
  if (text.size() > 200) text = text.substr(0, 197) + "...";
  for (char& c : text)
    if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7f) c = '?';
  return text;
}

}  // namespace

std::string read_regular_file(const std::string& path, std::size_t max_bytes, std::string& error) {
  error.clear();
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);  // follows links: the file they name
  if (status.type() == fs::file_type::not_found) {
    error = "cannot open: no such file";
    return "";
  }
  if (ec) {
    error = "cannot open: " + ec.message();
    return "";
  }
  if (status.type() != fs::file_type::regular) {
    error = "expected a regular file, found " + file_kind(status.type());
    return "";
  }
  // O_NONBLOCK: should the path have become a FIFO since, opening it does not wait for a writer.
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
  if (fd < 0) {
    error = std::string("cannot open: ") + std::strerror(errno);
    return "";
  }
  std::string text;
  struct stat st {};
  if (::fstat(fd, &st) != 0)
    error = std::string("cannot read: ") + std::strerror(errno);
  else if (!S_ISREG(st.st_mode))
    error = "expected a regular file, found " + file_kind(st.st_mode);
  else if (static_cast<std::uintmax_t>(st.st_size) > max_bytes)
    error = too_large(max_bytes, std::to_string(st.st_size) + " bytes");
  else
    text = read_descriptor(fd, max_bytes, error);
  ::close(fd);
  return error.empty() ? text : std::string();
}

JsonFileRead parse_json_text(std::string_view text, const JsonFileLimits& limits) {
  JsonFileRead out;
  const std::size_t deep = too_deep_at(text, limits.max_depth);
  if (deep != std::string_view::npos) {
    out.error = "expected at most " + std::to_string(limits.max_depth) +
                " levels of nested arrays and objects, found more at byte " + std::to_string(deep);
    return out;
  }
  try {
    out.value = nlohmann::json::parse(text.begin(), text.end());
  } catch (const nlohmann::json::exception& e) {
    out.value = nullptr;
    out.error = "expected JSON, found a " + parse_message(e.what());
  }
  return out;
}

JsonFileRead try_read_json_file(const std::string& path, const JsonFileLimits& limits) {
  JsonFileRead out;
  const std::string text = read_regular_file(path, limits.max_bytes, out.error);
  if (!out.ok()) return out;
  return parse_json_text(text, limits);
}

nlohmann::json read_json_file(const std::string& path, const JsonFileLimits& limits) {
  JsonFileRead r = try_read_json_file(path, limits);
  if (!r.ok()) throw InputError(path + ": " + r.error);
  return std::move(r.value);
}

std::string shown_json(const nlohmann::json& j) {
  if (j.is_null()) return "null";
  std::string text = j.dump(-1, ' ', true, nlohmann::json::error_handler_t::replace);
  if (text.size() > 60) text = text.substr(0, 57) + "...";
  return std::string(j.type_name()) + " " + text;
}

}  // namespace c2d::app
