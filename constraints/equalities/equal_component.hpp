// `type = "equal"`: every selected node shares one displacement component.
#pragma once

#include "constraints/equality.hpp"
#include "core/scene.hpp"

namespace c2d::constraints {

class EqualComponent final : public EqualityConstraint {
 public:
  static std::unique_ptr<EqualityConstraint> parse(const core::TomlView& v);
  std::vector<EqualityRow> rows(const core::Model& model, int owner,
                                const std::string& where) const override;

 private:
  core::SelectionSpec on_;
  int dof_ = 0;
};

}  // namespace c2d::constraints
