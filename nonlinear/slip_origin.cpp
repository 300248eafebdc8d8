#include "nonlinear/slip_origin.hpp"

namespace c2d::nonlinear {

void SlipOrigin::apply(const std::vector<constraints::GapRow>& rows,
                       const constraints::StepHistory& history, const std::vector<char>& closed,
                       const VecX& tangent, constraints::ConstrainedProblem& qp,
                       constraints::RowMemory& memory) {
  const int m = qp.num_gaps();
  const int slots = static_cast<int>(slip_.size());
  memory.tangent_force0 = VecX::Zero(m);
  if (history.tangent_force.size() == slots)
    for (int i = 0; i < m; ++i) memory.tangent_force0[i] = history.tangent_force[rows[i].slot];
  for (int i = 0; i < m; ++i) {
    const int k = rows[i].slot;
    if (static_cast<int>(history.states.size()) > k && history.states[k]) continue;
    if (slip_[k] == kNone && static_cast<int>(closed.size()) > k && closed[k]) {
      slip_[k] = qp.slip0[i];
      force_[k] = tangent.size() > k ? tangent[k] : 0.0;
    }
    if (slip_[k] == kNone) continue;
    qp.slip0[i] -= slip_[k];
    memory.tangent_force0[i] = force_[k];
  }
}

}  // namespace c2d::nonlinear
