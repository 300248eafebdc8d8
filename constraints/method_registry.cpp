#include "constraints/method_registry.hpp"

#include "constraints/methods/adaptive_penalty_strategy.hpp"
#include "constraints/methods/auglag_strategy.hpp"
#include "constraints/methods/ipopt_strategy.hpp"
#include "constraints/methods/lagrange_strategy.hpp"
#include "constraints/methods/penalty_strategy.hpp"
#include "constraints/methods/ssn_strategy.hpp"
#include "constraints/registry.hpp"

namespace c2d::constraints {

namespace {

template <class Strategy>
MethodInfo entry(std::string name, std::string summary) {
  static_assert(std::is_base_of_v<RegularisedStrategy, Strategy> ||
                std::is_base_of_v<ExactStrategy, Strategy>);
  return {std::move(name), std::move(summary), std::is_base_of_v<ExactStrategy, Strategy>,
          [](const StrategyOptions& o) -> std::unique_ptr<ConstraintStrategy> {
            return std::make_unique<Strategy>(o);
          }};
}

}  // namespace

const std::vector<MethodInfo>& method_registry() {
  static const std::vector<MethodInfo> registry = {
      entry<PenaltyStrategy>("penalty", "a spring of stiffness k per closed row (k from the input or factor × the local stiffness)"),
      entry<AdaptivePenaltyStrategy>("adaptive_penalty", "penalty whose k grows on rows that penetrate beyond the tolerance, up to a cap"),
      entry<LagrangeStrategy>("lagrange", "Lagrange multipliers with a primal active-set loop (tension releases, penetration closes)"),
      entry<AugLagStrategy>("auglag", "augmented Lagrangian: penalised solves with Uzawa multiplier updates until the penetration is within tolerance"),
      entry<IpoptStrategy>("ipopt", "the quadratic programme with gap inequalities solved by Ipopt's interior point, as its dual on the contact surface (K factorised once; the set it finds then solved exactly), or whole where that does not apply"),
      entry<SsnStrategy>("ssn", "semi-smooth Newton on the complementarity function (primal-dual active sets)"),
  };
  return registry;
}

const MethodInfo* find_method(std::string_view name) { return find_entry(method_registry(), name); }

const std::vector<std::string>& method_names() {
  static const std::vector<std::string> names = entry_names(method_registry());
  return names;
}

std::string method_list(std::string_view separator) {
  std::string out;
  for (const auto& m : method_registry()) out += (out.empty() ? "" : std::string(separator)) + m.name;
  return out;
}

bool is_exact_method(std::string_view name) {
  const MethodInfo* m = find_method(name);
  return m && m->exact;
}

std::string method_table_markdown() {
  std::string out = "| method | enforcement | what it does |\n|---|---|---|\n";
  for (const auto& m : method_registry())
    out += "| `" + m.name + "` | " + (m.exact ? "exact" : "regularised") + " | " + m.summary + " |\n";
  return out;
}

}  // namespace c2d::constraints
