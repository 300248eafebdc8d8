#include "app/report/units.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

namespace c2d::app {

Units parse_units(const std::string& text) {
  Units u;
  std::string token;
  std::istringstream in(text);
  while (std::getline(in, token, ',')) {
    std::istringstream t(token);
    std::string word;
    if (!(t >> word)) continue;
    const auto ends_with = [&](const std::string& tail) {
      return word.size() >= tail.size() &&
             word.compare(word.size() - tail.size(), tail.size(), tail) == 0;
    };
    if (ends_with("Pa") || word == "psi" || word == "ksi" || word.find("/m") != std::string::npos)
      u.stress = word;
    else if (word == "m" || word == "mm" || word == "cm" || word == "km" || word == "um" ||
             word == "in" || word == "ft")
      u.length = word;
    else if (ends_with("N") || word == "lbf" || word == "kip" || word == "t" || word == "kgf")
      u.force = word;
  }
  return u;
}

std::string rounded_text(double v, int digits) {
  char text[32];
  std::snprintf(text, sizeof text, "%.*g", digits, v);
  // Below a million a rounded whole number reads in full: 2000, not 2e+03.
  const double rounded = std::strtod(text, nullptr);
  if (std::abs(rounded) >= 1 && std::abs(rounded) < 1e6 && rounded == std::round(rounded))
    std::snprintf(text, sizeof text, "%.0f", rounded);
  return text;
}

}  // namespace c2d::app
