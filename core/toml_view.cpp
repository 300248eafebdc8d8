#include "core/toml_view.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace c2d::core {

namespace {

std::string position(const toml::node* n, const std::string* file) {
  std::ostringstream os;
  os << (file ? *file : std::string("<scene>"));
  if (n && n->source().begin.line > 0) {
    os << ':' << n->source().begin.line << ':' << n->source().begin.column;
  } else if (n) {
    os << " (--set)";
  }
  return os.str();
}

}  // namespace

std::string TomlView::where() const {
  return position(node_ ? node_ : parent_, file_) + ": " + (path_.empty() ? "<root>" : path_);
}

void TomlView::fail(const std::string& expected) const {
  throw InputError(where() + ": expected " + expected + ", found " + found());
}

void TomlView::fail_message(const std::string& message) const {
  throw InputError(where() + ": " + message);
}

std::string TomlView::found() const {
  if (!node_) return "nothing (key missing)";
  std::ostringstream os;
  switch (node_->type()) {
    case toml::node_type::string: os << "string \"" << *node_->value<std::string>() << '"'; break;
    case toml::node_type::integer: os << "integer " << *node_->value<int64_t>(); break;
    case toml::node_type::floating_point: os << "number " << *node_->value<double>(); break;
    case toml::node_type::boolean: os << "boolean " << (*node_->value<bool>() ? "true" : "false"); break;
    case toml::node_type::table: os << "a table"; break;
    case toml::node_type::array: os << "an array of " << node_->as_array()->size(); break;
    default: os << "a date/time"; break;
  }
  return os.str();
}

TomlView TomlView::operator[](const std::string& key) const {
  const std::string child_path = path_.empty() ? key : path_ + "." + key;
  const toml::node* child = nullptr;
  if (node_ && node_->is_table()) child = node_->as_table()->get(key);
  return TomlView(child, child_path, file_, node_ ? node_ : parent_);
}

void TomlView::require_table() const {
  if (!is_table()) fail("a table");
}

void TomlView::check_keys(std::initializer_list<const char*> allowed) const {
  check_keys(std::vector<std::string>(allowed.begin(), allowed.end()));
}

void TomlView::check_keys(const std::vector<std::string>& names) const {
  if (!is_table()) return;
  for (const auto& [key, value] : *node_->as_table()) {
    const std::string k(key.str());
    if (std::find(names.begin(), names.end(), k) != names.end()) continue;
    std::string list;
    for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
    TomlView bad(&value, path_.empty() ? k : path_ + "." + k, file_, node_);
    throw InputError(bad.where() + ": unknown key '" + k + "'" + did_you_mean(k, names) +
                     "; expected one of: " + list);
  }
}

double TomlView::number() const {
  if (!node_) fail("a number");
  if (auto v = node_->value_exact<double>()) {
    if (!std::isfinite(*v)) fail("a finite number");  // TOML allows nan and inf
    return *v;
  }
  if (auto v = node_->value_exact<int64_t>()) return static_cast<double>(*v);
  fail("a number");
}

double TomlView::number_or(double fallback) const { return node_ ? number() : fallback; }

double TomlView::positive() const {
  const double v = number();
  if (!(v > 0.0) || !std::isfinite(v)) fail("a positive number");
  return v;
}

int TomlView::integer() const {
  if (!node_) fail("an integer");
  if (auto v = node_->value_exact<int64_t>()) {
    if (*v < std::numeric_limits<int>::min() || *v > std::numeric_limits<int>::max())
      fail("an integer within ±" + std::to_string(std::numeric_limits<int>::max()));
    return static_cast<int>(*v);
  }
  fail("an integer");
}

bool TomlView::boolean_or(bool fallback) const {
  if (!node_) return fallback;
  if (auto v = node_->value_exact<bool>()) return *v;
  fail("true or false");
}

std::string TomlView::string() const {
  if (!node_) fail("a string");
  if (auto v = node_->value_exact<std::string>()) return *v;
  fail("a string");
}

std::string TomlView::string_or(const std::string& fallback) const {
  return node_ ? string() : fallback;
}

std::string TomlView::choice(const std::vector<std::string>& choices) const {
  std::string list;
  for (const std::string& c : choices) list += std::string(list.empty() ? "" : " | ") + '"' + c + '"';
  if (!node_ || !node_->is_string()) fail("one of " + list);
  const std::string v = string();
  for (const std::string& c : choices)
    if (v == c) return v;
  fail("one of " + list);
}

std::string TomlView::choice_or(const std::vector<std::string>& choices,
                                const std::string& fallback) const {
  return node_ ? choice(choices) : fallback;
}

Vec2 TomlView::vec2() const {
  if (!node_ || !node_->is_array() || node_->as_array()->size() != 2) fail("a pair [x, y]");
  const auto items_ = items();
  Vec2 v(items_[0].number(), items_[1].number());
  if (!v.allFinite()) fail("a pair of finite numbers [x, y]");
  return v;
}

std::vector<Vec2> TomlView::points() const {
  if (!node_ || !node_->is_array()) fail("a list of points [[x, y], ...]");
  std::vector<Vec2> pts;
  for (const auto& item : items()) pts.push_back(item.vec2());
  return pts;
}

std::vector<TomlView> TomlView::tables() const {
  std::vector<TomlView> out;
  if (!node_) return out;
  if (node_->is_table()) {  // a single [table] where [[array]] was meant: accept it
    out.emplace_back(node_, path_ + "[0]", file_, parent_);
    return out;
  }
  if (!node_->is_array()) fail("an array of tables ([[" + path_ + "]])");
  const auto& arr = *node_->as_array();
  for (size_t i = 0; i < arr.size(); ++i) {
    TomlView v(&arr[i], path_ + "[" + std::to_string(i) + "]", file_, node_);
    v.require_table();
    out.push_back(v);
  }
  return out;
}

std::vector<TomlView> TomlView::items() const {
  std::vector<TomlView> out;
  if (!node_) return out;
  if (!node_->is_array()) fail("an array");
  const auto& arr = *node_->as_array();
  for (size_t i = 0; i < arr.size(); ++i)
    out.emplace_back(&arr[i], path_ + "[" + std::to_string(i) + "]", file_, node_);
  return out;
}

std::string did_you_mean(const std::string& key, const std::vector<std::string>& candidates) {
  const std::string near = nearest_name(key, candidates);
  return near.empty() ? std::string() : " (did you mean '" + near + "'?)";
}

std::string nearest_name(const std::string& key, const std::vector<std::string>& candidates) {
  auto distance = [](const std::string& a, const std::string& b) {
    std::vector<size_t> prev(b.size() + 1), cur(b.size() + 1);
    for (size_t j = 0; j <= b.size(); ++j) prev[j] = j;
    for (size_t i = 1; i <= a.size(); ++i) {
      cur[0] = i;
      for (size_t j = 1; j <= b.size(); ++j)
        cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1,
                           prev[j - 1] + (std::tolower(a[i - 1]) == std::tolower(b[j - 1]) ? 0 : 1)});
      std::swap(prev, cur);
    }
    return prev[b.size()];
  };
  std::string best;
  size_t best_d = std::max<size_t>(2, key.size() / 3) + 1;
  for (const auto& c : candidates) {
    const size_t d = distance(key, c);
    if (d < best_d) {
      best_d = d;
      best = c;
    }
  }
  return best;
}

}  // namespace c2d::core
