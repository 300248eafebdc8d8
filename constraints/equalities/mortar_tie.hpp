// `type = "tie"`: a slave surface glued to a master surface by mortar tying in the reference
// configuration, per slave corner node j and component d: Σ_k D_jk u_k,d = Σ_l M_jl u_l,d
// (D, M: Mortar::coupling). The coefficients are fixed (a tie glues material points), so the
// rows are linear in u in small and finite strain alike, and a uniform traction crosses
// non-matching meshes exactly.
#pragma once

#include "constraints/equality.hpp"
#include "core/scene.hpp"

namespace c2d::constraints {

class MortarTie final : public EqualityConstraint {
 public:
  static std::unique_ptr<EqualityConstraint> parse(const core::TomlView& v);
  std::vector<EqualityRow> rows(const core::Model& model, int owner,
                                const std::string& where) const override;

 private:
  core::SelectionSpec slave_, master_;
};

}  // namespace c2d::constraints
