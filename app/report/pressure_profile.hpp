// Contact pressure along a slave surface: from a solve's contact report, or read back from a
// finished run's contact.csv.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "constraints/contact_set.hpp"
#include "core/types.hpp"

namespace c2d::app {

/// The coordinate (0: x, 1: y) along which the points spread most: the abscissa for values
/// along a slave surface.
int spread_axis(const std::vector<Vec2>& points);

/// Every slave node's (reference coordinate along spread_axis, recovered pressure), sorted;
/// `axis`, when given, receives that axis.
std::vector<std::pair<double, double>> pressure_profile(const constraints::ContactReport& contact,
                                                        int* axis = nullptr);

/// The same from DIR/contact.csv of a finished run; empty when the run wrote none. Throws
/// InputError for a malformed file.
std::vector<std::pair<double, double>> read_pressure_profile(const std::string& dir);

}  // namespace c2d::app
