// `contact2d trace OUTDIR`: charts of a finished load-stepped run from its trace.csv and
// contact_steps.csv.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace c2d::app {

/// What `trace` wrote: chart stems and a one-line description each.
struct TraceCharts {
  std::vector<std::pair<std::string, std::string>> written;
  std::string error;  ///< gnuplot's failure, empty on success
};

/// Draws from DIR/trace.csv (required) and DIR/contact_steps.csv (when present):
///   activation.png/svg     slave position × load factor, active nodes coloured by pressure
///   contact_force.png/svg  total contact force and active node count against load factor
///   residuals.png/svg      Newton residual history of every load step (log scale)
/// Throws InputError when trace.csv is missing or malformed.
TraceCharts draw_trace_charts(const std::string& dir);

}  // namespace c2d::app
