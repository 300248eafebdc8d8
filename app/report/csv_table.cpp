#include "app/report/csv_table.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "core/errors.hpp"

namespace c2d::app {

namespace {

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> cells;
  std::string cell;
  std::istringstream in(line);
  while (std::getline(in, cell, ',')) cells.push_back(cell);
  if (!line.empty() && line.back() == ',') cells.emplace_back();
  return cells;
}

}  // namespace

int CsvTable::column(const std::string& name) const {
  const auto it = std::find(columns.begin(), columns.end(), name);
  if (it == columns.end())
    throw InputError(path + ":1: expected a column '" + name + "', found none in the header");
  return static_cast<int>(it - columns.begin());
}

double CsvTable::number(size_t row, int column) const {
  const std::string& cell = rows[row][column];
  if (cell.empty()) return std::nan("");
  char* end = nullptr;
  const double v = std::strtod(cell.c_str(), &end);
  if (end == cell.c_str() || *end != '\0')
    throw InputError(path + ":" + std::to_string(row + 2) + ": column " +
                     quoted_found(columns[column]) + ": expected a number, found " +
                     quoted_found(cell));
  return v;
}

std::vector<Vec2> CsvTable::points(const std::string& x, const std::string& y) const {
  const int cx = column(x), cy = column(y);
  std::vector<Vec2> out;
  for (size_t r = 0; r < rows.size(); ++r) out.emplace_back(number(r, cx), number(r, cy));
  return out;
}

CsvTable read_csv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": expected a readable file, found none");
  CsvTable t;
  t.path = path;
  std::string line;
  if (!std::getline(in, line) || line.empty())
    throw InputError(path + ":1: expected a header row, found an empty file");
  t.columns = split(line);
  int number = 1;
  while (std::getline(in, line)) {
    ++number;
    if (line.empty()) continue;
    auto cells = split(line);
    if (cells.size() != t.columns.size())
      throw InputError(path + ":" + std::to_string(number) + ": expected " +
                       std::to_string(t.columns.size()) + " cells, found " +
                       std::to_string(cells.size()));
    t.rows.push_back(std::move(cells));
  }
  return t;
}

}  // namespace c2d::app
