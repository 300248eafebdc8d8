// The rows that attach a rigid plate ([[plate]], core/rigid_plate.hpp) to the structure. The
// plate's DOFs q = (U_x, U_y, θ) move its reference point P; an attached node i sits at
// r_i = X_i − X_P in the reference configuration.
//   attach = "all":    u_i − U − (R(θ) − I) r_i = 0          (two rows: x and y)
//   attach = "normal": n(θ)·(r_i + u_i − U) − n₀·r_i = 0      (one row; n(θ) = R(θ) n₀)
// Exact in θ in load-stepped runs: the edge follows the rigid motion, not its linearisation, and
// the rows carry their second derivatives (the geometric stiffness −μ ∂²c). In linear runs both
// are linearised about θ = 0: u_i − U − θ J r_i = 0 and n₀·(u_i − U) + θ (J n₀)·r_i = 0, with J
// the quarter turn.
#pragma once

#include <vector>

#include "constraints/equality.hpp"
#include "core/model.hpp"

namespace c2d::constraints {

/// Appends plate `p`'s rows at the full displacement u (`small_strain`: the linear rows).
void rigid_plate_rows(const core::Model& model, int p, const VecX& u, bool small_strain,
                      std::vector<EqualityRow>& out);

}  // namespace c2d::constraints
