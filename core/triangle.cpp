#include "core/triangle.hpp"

#include <array>

namespace c2d::core {

std::span<const QuadraturePoint> rule_degree1() {
  static constexpr std::array<QuadraturePoint, 1> r{{{1.0 / 3.0, 1.0 / 3.0, 0.5}}};
  return r;
}

std::span<const QuadraturePoint> rule_degree2() {
  static constexpr std::array<QuadraturePoint, 3> r{{{1.0 / 6.0, 1.0 / 6.0, 1.0 / 6.0},
                                                     {2.0 / 3.0, 1.0 / 6.0, 1.0 / 6.0},
                                                     {1.0 / 6.0, 2.0 / 3.0, 1.0 / 6.0}}};
  return r;
}

std::span<const QuadraturePoint> rule_degree4() {
  constexpr double a = 0.445948490915965, wa = 0.223381589678011 / 2.0;
  constexpr double b = 0.091576213509771, wb = 0.109951743655322 / 2.0;
  static constexpr std::array<QuadraturePoint, 6> r{{{a, a, wa},
                                                     {1.0 - 2.0 * a, a, wa},
                                                     {a, 1.0 - 2.0 * a, wa},
                                                     {b, b, wb},
                                                     {1.0 - 2.0 * b, b, wb},
                                                     {b, 1.0 - 2.0 * b, wb}}};
  return r;
}

}  // namespace c2d::core
