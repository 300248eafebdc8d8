// `type = "linear"`: one row Σ aᵢ u_{nᵢ,dᵢ} = value over single nodes.
#pragma once

#include "constraints/equality.hpp"
#include "core/scene.hpp"

namespace c2d::constraints {

class LinearRows final : public EqualityConstraint {
 public:
  static std::unique_ptr<EqualityConstraint> parse(const core::TomlView& v);
  std::vector<EqualityRow> rows(const core::Model& model, int owner,
                                const std::string& where) const override;

 private:
  struct Term {
    core::SelectionSpec on;
    int dof = 0;
    double coefficient = 1.0;
  };
  std::vector<Term> terms_;
  double value_ = 0.0;
};

}  // namespace c2d::constraints
