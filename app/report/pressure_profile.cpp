#include "app/report/pressure_profile.hpp"

#include <algorithm>
#include <filesystem>

#include "app/report/csv_table.hpp"

namespace c2d::app {

int spread_axis(const std::vector<Vec2>& points) {
  Vec2 lo = Vec2::Constant(1e300), hi = Vec2::Constant(-1e300);
  for (const auto& p : points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  return hi.y() - lo.y() > hi.x() - lo.x() ? 1 : 0;
}

std::vector<std::pair<double, double>> pressure_profile(const constraints::ContactReport& contact,
                                                        int* axis) {
  std::vector<Vec2> positions;
  for (const auto& n : contact.nodes) positions.push_back(n.x);
  const int along = spread_axis(positions);
  if (axis) *axis = along;
  std::vector<std::pair<double, double>> pts;
  for (const auto& n : contact.nodes) pts.emplace_back(n.x[along], n.pressure);
  std::sort(pts.begin(), pts.end());
  return pts;
}

std::vector<std::pair<double, double>> read_pressure_profile(const std::string& dir) {
  std::vector<std::pair<double, double>> pts;
  if (!std::filesystem::exists(dir + "/contact.csv")) return pts;
  const CsvTable t = read_csv(dir + "/contact.csv");
  const int cp = t.column("pressure");
  const std::vector<Vec2> positions = t.points("x", "y");
  const int axis = spread_axis(positions);
  for (size_t r = 0; r < t.rows.size(); ++r) pts.emplace_back(positions[r][axis], t.number(r, cp));
  std::sort(pts.begin(), pts.end());
  return pts;
}

}  // namespace c2d::app
