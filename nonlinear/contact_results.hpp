// A contact state as analysis results: the report's quantities as result globals and point
// fields, for the VTU output, the probes and summary.json.
#pragma once

#include "constraints/contact_set.hpp"
#include "core/results.hpp"

namespace c2d::nonlinear {

/// The contact quantities of a report as result globals (contact_pressure_max, contact_length,
/// contact_force, contact_penetration; with friction the tangential force and the stick and slip
/// counts; per plate its motion and force) and point fields (contact_gap, contact_pressure,
/// contact_force; with friction contact_shear, contact_slip, contact_state).
void store_contact_results(const constraints::ContactReport& report, int num_nodes,
                           core::Results& results);

}  // namespace c2d::nonlinear
