#include "app/report/run_tables.hpp"

#include <algorithm>
#include <iomanip>
#include <sstream>

namespace c2d::app {

namespace {

// trace.csv columns (DESIGN §4), shared by the contact and the Newton traces.
constexpr const char* kTraceHeader =
    "step,load_factor,attempt,outer,iteration,residual,increment_norm,active,entering,leaving,"
    "max_penetration,max_pressure,penalty,status,stick,slip,factorizations\n";

constexpr const char* kContactStepsHeader = "step,load_factor,node,x,y,gap,force,pressure,active";
/// Friction columns (frictional scenes only): the tangential force on the slave along t (the
/// normal turned clockwise), its recovered traction, the step's slip, the slip summed over the
/// steps, and open / stick / slip.
constexpr const char* kFrictionColumns = ",tangential_force,shear,slip,accumulated_slip,state";

const char* state_name(constraints::FrictionState s) {
  switch (s) {
    case constraints::FrictionState::kStick: return "stick";
    case constraints::FrictionState::kSlip: return "slip";
    default: return "open";
  }
}

void write_friction(std::ostream& os, const constraints::ContactNodeResult& n) {
  os << ',' << n.tangent_force << ',' << n.shear << ',' << n.slip << ',' << n.accumulated_slip
     << ',' << state_name(n.state);
}

/// The rows of one converged state in contact_steps.csv.
void write_contact_state(std::ostream& os, int step, double load_factor,
                         const constraints::ContactReport& state) {
  for (const auto& n : state.nodes) {
    os << step << ',' << load_factor << ',' << n.node + 1 << ',' << n.x.x() << ',' << n.x.y() << ','
       << n.gap << ',' << n.force << ',' << n.pressure << ',' << (n.active ? 1 : 0);
    if (state.friction) write_friction(os, n);
    os << '\n';
  }
}

/// The rows of one load step without contact: one per Newton iteration.
void write_newton_rows(std::ostream& os, const nonlinear::StepRecord& s) {
  const auto& norms = s.newton.residual_norms;
  for (size_t k = 0; k < norms.size(); ++k) {
    const bool last = k + 1 == norms.size();
    os << s.step << ',' << s.load_factor << ',' << s.attempt << ",1," << k << ',' << norms[k]
       << ',';
    if (last) os << s.newton.last_step;
    os << ",0,0,0,0,0,0," << (last ? to_string(s.newton.status) : "iterating") << ",0,0,";
    if (last) os << s.factorizations;
    os << '\n';
  }
}

/// The rows of one load step with contact: the Newton iterations of each outer (active-set)
/// iteration, numbered through the attempt; the last row of an outer iteration carries its
/// penetration and pressure, the last row of the attempt its status.
void write_contact_rows(std::ostream& os, const nonlinear::StepRecord& s) {
  int base = 0;
  for (size_t o = 0; o < s.contact.size(); ++o) {
    const auto& it = s.contact[o];
    const auto& norms = it.newton.residual_norms;
    const size_t rows = std::max<size_t>(norms.size(), 1);
    for (size_t k = 0; k < rows; ++k) {
      const bool last = k + 1 == rows;
      os << s.step << ',' << s.load_factor << ',' << s.attempt << ',' << it.outer << ','
         << base + static_cast<int>(k) << ',' << (norms.empty() ? 0.0 : norms[k]) << ',';
      if (last) os << it.newton.last_step;
      os << ',' << it.active << ',' << it.entering << ',' << it.leaving << ',';
      if (last)
        os << it.max_penetration << ',' << it.max_pressure;
      else
        os << ',';
      os << ',' << it.penalty << ','
         << (!last ? "iterating"
                   : to_string(o + 1 == s.contact.size() ? s.newton.status : it.newton.status))
         << ',' << it.stick << ',' << it.slip << ',';
      if (last) os << it.factorizations;
      os << '\n';
    }
    base += it.newton.iterations;
  }
}

}  // namespace

std::string contact_csv(const constraints::ContactReport& c) {
  std::ostringstream os;
  os << std::setprecision(12) << "node,x,y,gap,force,pressure,active,penalty"
     << (c.friction ? kFrictionColumns : "") << '\n';
  for (const auto& n : c.nodes) {
    os << n.node + 1 << ',' << n.x.x() << ',' << n.x.y() << ',' << n.gap << ',' << n.force << ','
       << n.pressure << ',' << (n.active ? 1 : 0) << ',' << n.penalty;
    if (c.friction) write_friction(os, n);
    os << '\n';
  }
  return os.str();
}

std::string constraints_csv(const constraints::ContactReport& c) {
  std::ostringstream os;
  os << std::setprecision(12) << "row,constraint,type,multiplier,residual\n";
  for (size_t i = 0; i < c.equalities.size(); ++i) {
    const auto& e = c.equalities[i];
    os << i + 1 << ',' << c.equality_names[e.owner] << ',' << c.equality_types[e.owner] << ','
       << e.multiplier << ',' << e.residual << '\n';
  }
  return os.str();
}

std::string trace_csv(const constraints::ContactReport& c) {
  std::ostringstream os;
  os << std::setprecision(10) << kTraceHeader;
  for (size_t i = 0; i < c.history.size(); ++i) {
    const auto& h = c.history[i];
    const bool last = i + 1 == c.history.size();
    os << "1,1,0,1," << h.iteration << ',' << h.residual << ",," << h.active << ',' << h.entering
       << ',' << h.leaving << ',' << h.max_penetration << ',';
    if (last) os << c.p_max;
    os << ',' << h.penalty << ',' << (last ? to_string(c.status) : "iterating") << ',' << h.stick
       << ',' << h.slip << ",\n";
  }
  return os.str();
}

std::string newton_trace_csv(const std::vector<nonlinear::StepRecord>& steps) {
  std::ostringstream os;
  os << std::setprecision(10) << kTraceHeader;
  for (const auto& s : steps) {
    if (s.contact.empty())
      write_newton_rows(os, s);
    else
      write_contact_rows(os, s);
  }
  return os.str();
}

std::string contact_steps_csv(const std::vector<nonlinear::StepRecord>& steps) {
  std::ostringstream os;
  bool friction = false;
  for (const auto& s : steps) friction = friction || s.contact_state.friction;
  os << std::setprecision(12) << kContactStepsHeader << (friction ? kFrictionColumns : "") << '\n';
  for (const auto& s : steps)
    if (s.newton.status == SolveStatus::kConverged)
      write_contact_state(os, s.step, s.load_factor, s.contact_state);
  return os.str();
}

std::string contact_steps_csv(const constraints::ContactReport& contact, bool converged) {
  std::ostringstream os;
  os << std::setprecision(12) << kContactStepsHeader << (contact.friction ? kFrictionColumns : "")
     << '\n';
  if (converged) write_contact_state(os, 1, 1.0, contact);
  return os.str();
}

}  // namespace c2d::app
