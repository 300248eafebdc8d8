// Reads back the VTU files `contact2d run` writes (their ASCII layout, not VTU in general).
#pragma once

#include <array>
#include <map>
#include <string>
#include <vector>

#include "core/types.hpp"

namespace c2d::app {

/// What `contact2d run` wrote into one VTU file.
struct VtuData {
  std::string path;
  int order = 1;  ///< 1: T3 cells (VTK type 5), 2: T6 (type 22)
  std::vector<Vec2> points;
  std::vector<std::array<int, 6>> cells;
  /// Arrays by name, flattened (point data: components per point; cell data: per cell).
  std::map<std::string, std::vector<double>> point_data, cell_data;
  std::map<std::string, int> components;
};

/// Reads DIR/step_0001.vtu and the like. Throws InputError naming the file and what is missing.
VtuData read_vtu(const std::string& path);

}  // namespace c2d::app
