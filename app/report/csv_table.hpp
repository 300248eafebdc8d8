// The CSV files of a run (and measured data): a header row, then cells read as numbers on demand.
#pragma once

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

}  // namespace c2d::app
