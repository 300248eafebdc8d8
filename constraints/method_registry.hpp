// The registry of constraint enforcement methods: the one list that the scene parser, the
// command line's help, compare's default list, docs/scene.md's method table (checked by a test)
// and the tests read. A new method is one class deriving from RegularisedStrategy or
// ExactStrategy (constraints/methods/) and one line in method_registry.cpp.
#pragma once

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "constraints/constraint_strategy.hpp"

namespace c2d::constraints {

struct MethodInfo {
  std::string name;         ///< the name scenes and --method use
  std::string summary;      ///< one line for --help and the docs' table
  bool exact = false;       ///< exact (multipliers) or regularised (a penalty per row)
  std::unique_ptr<ConstraintStrategy> (*create)(const StrategyOptions&) = nullptr;
};

/// Every registered method, in the order reports list them.
const std::vector<MethodInfo>& method_registry();
/// The registered method of that name, or nullptr.
const MethodInfo* find_method(std::string_view name);
/// The registered names, in the registry's order.
const std::vector<std::string>& method_names();
/// The names joined by `separator` ("penalty | adaptive_penalty | ...").
std::string method_list(std::string_view separator);
/// True for a registered method that enforces the constraints exactly.
bool is_exact_method(std::string_view name);
/// The method table of docs/scene.md: name, exact or regularised, summary (Markdown).
std::string method_table_markdown();

}  // namespace c2d::constraints
