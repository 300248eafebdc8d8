// Lookups shared by the registries (methods, discretizations): entries with a `name` member.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace c2d::constraints {

/// The entry of `registry` named `name`, or nullptr.
template <class Entry>
const Entry* find_entry(const std::vector<Entry>& registry, std::string_view name) {
  for (const auto& e : registry)
    if (e.name == name) return &e;
  return nullptr;
}

/// The entries' names, in the registry's order.
template <class Entry>
std::vector<std::string> entry_names(const std::vector<Entry>& registry) {
  std::vector<std::string> out;
  for (const auto& e : registry) out.push_back(e.name);
  return out;
}

}  // namespace c2d::constraints
