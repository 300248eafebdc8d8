// The CSV tables of a run: contact.csv, trace.csv and contact_steps.csv.
#pragma once

#include <string>
#include <vector>

#include "constraints/contact_set.hpp"
#include "nonlinear/load_stepper.hpp"

namespace c2d::app {

/// One row per slave node: node, x, y, gap, force, pressure, active, penalty.
std::string contact_csv(const constraints::ContactReport& contact);
/// The [[constraint]] rows: constraint name and type, multiplier (the row's force), residual.
std::string constraints_csv(const constraints::ContactReport& contact);

/// trace.csv of a linear analysis: one row per contact backend iteration (DESIGN §4 columns;
/// one load step).
std::string trace_csv(const constraints::ContactReport& contact);

/// trace.csv of a load-stepped analysis: one row per Newton iteration of every load step
/// attempt (DESIGN §4 columns).
std::string newton_trace_csv(const std::vector<nonlinear::StepRecord>& steps);

/// contact_steps.csv: per converged load step and slave node: step, load_factor, node, x, y
/// (reference position), gap, force, pressure, active.
std::string contact_steps_csv(const std::vector<nonlinear::StepRecord>& steps);

/// contact_steps.csv of a linear analysis: its one step at load factor 1, when it converged.
std::string contact_steps_csv(const constraints::ContactReport& contact, bool converged);

}  // namespace c2d::app
