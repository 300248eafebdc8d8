// `contact2d trace OUTDIR`: charts of a finished load-stepped run from its trace.csv and
// contact_steps.csv.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "core/types.hpp"

namespace c2d::app {

/// A CSV table with a header row; numbers only (text cells such as a status are kept as text).
struct CsvTable {
  std::string path;
  std::vector<std::string> columns;
  std::vector<std::vector<std::string>> rows;

  /// Column index by name; throws InputError naming the file and the missing column.
  int column(const std::string& name) const;
  /// Number in a cell; throws InputError naming file, line and column when it is not one.
  double number(size_t row, int column) const;
  /// Every row's (x, y) from two named columns.
  std::vector<Vec2> points(const std::string& x, const std::string& y) const;
};

/// Reads a CSV file; throws InputError (file, line) on a missing file or a ragged row.
CsvTable read_csv(const std::string& path);

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
