// A checked view of a TOML node: every accessor knows its key path and source position, so a
// mistake becomes one line "file:line:col: key.path: expected ..., found ...".
#pragma once

#include <initializer_list>
#include <optional>
#include <string>
#include <vector>

#include <toml++/toml.h>

#include "core/errors.hpp"
#include "core/types.hpp"

namespace c2d::core {

class TomlView {
 public:
  TomlView(const toml::node* node, std::string path, const std::string* file,
           const toml::node* parent = nullptr)
      : node_(node), parent_(parent), path_(std::move(path)), file_(file) {}

  bool exists() const { return node_ != nullptr; }
  const toml::node* node() const { return node_; }
  const std::string& path() const { return path_; }
  /// "file:line:col: path" of this node (or of its parent table when the key is missing).
  std::string where() const;
  [[noreturn]] void fail(const std::string& expected) const;
  [[noreturn]] void fail_message(const std::string& message) const;
  /// Describes what the node holds, for "found ..." (e.g. `string "abc"`, `nothing`).
  std::string found() const;

  TomlView operator[](const std::string& key) const;
  bool has(const std::string& key) const { return (*this)[key].exists(); }
  bool is_table() const { return node_ && node_->is_table(); }
  bool is_array() const { return node_ && node_->is_array(); }
  /// Rejects keys not in `allowed`, naming the nearest allowed one.
  void check_keys(std::initializer_list<const char*> allowed) const;
  void check_keys(const std::vector<std::string>& allowed) const;
  void require_table() const;

  double number() const;                        ///< any integer or float
  double number_or(double fallback) const;      ///< fallback when missing
  double positive() const;                      ///< > 0
  int integer() const;
  bool boolean_or(bool fallback) const;
  std::string string() const;
  std::string string_or(const std::string& fallback) const;
  /// One of `choices` (exact); names them on failure.
  std::string choice(const std::vector<std::string>& choices) const;
  std::string choice_or(const std::vector<std::string>& choices, const std::string& fallback) const;
  Vec2 vec2() const;                            ///< [x, y]
  std::vector<Vec2> points() const;             ///< [[x, y], ...]
  /// Entries of an array of tables (missing: empty); each view is named path[i].
  std::vector<TomlView> tables() const;
  /// Entries of an array (missing: empty).
  std::vector<TomlView> items() const;

 private:
  const toml::node* node_;
  const toml::node* parent_;
  std::string path_;
  const std::string* file_;
};

/// Levenshtein-nearest candidate, or empty when nothing is close.
std::string nearest_name(const std::string& key, const std::vector<std::string>& candidates);
/// " (did you mean 'NEAREST'?)" when a candidate is near `key`, else "": the suffix of every
/// unknown-name message.
std::string did_you_mean(const std::string& key, const std::vector<std::string>& candidates);

}  // namespace c2d::core
