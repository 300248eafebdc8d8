// A unit square plate (plane stress) pulled by a uniform traction σ on its right edge, held by
// rollers on its left edge and at one corner: uniaxial stress, so the right edge moves by
// u_x = σ L / E exactly, and linear triangles reproduce that linear field to round-off.
// Built and run by the install test against the installed package; exits non-zero on failure.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <stdexcept>
#include <string>

#include "core/model.hpp"
#include "core/scene.hpp"
#include "core/solver_status.hpp"
#include "nonlinear/load_stepper.hpp"

namespace {

constexpr double kYoung = 210000.0;  // E
constexpr double kLength = 1.0;      // L
constexpr double kStress = 100.0;    // σ
// Round-off only: the exact field is linear, which T3 elements reproduce.
constexpr double kRelativeTolerance = 1e-8;

// The scene, with E, L and σ filled in from the constants above.
std::string plate_scene() {
  char text[1024];
  const int length = std::snprintf(text, sizeof text, R"(
title = "unit square plate under uniaxial tension"
[analysis]
kind = "plane_stress"
element = "T3"

[[material]]
name = "steel"
E = %.17g
nu = 0.3

[[body]]
name = "plate"
material = "steel"
shape = { type = "rectangle", min = [0.0, 0.0], max = [%.17g, %.17g] }
mesh = { size = 0.25 }

[[support]]
on = { body = "plate", edge = "left" }
fix = ["ux"]

[[support]]
on = { body = "plate", nearest = [0.0, 0.0] }
fix = ["uy"]

[[load]]
on = { body = "plate", edge = "right" }
traction = [%.17g, 0.0]
)",
                                   kYoung, kLength, kLength, kStress);
  if (length < 0 || length >= static_cast<int>(sizeof text))
    throw std::logic_error("plate_scene: the scene text does not fit its buffer");
  return text;
}

}  // namespace

int main() {
  using namespace c2d;
  try {
    const core::Scene scene = core::parse_scene(plate_scene(), "plate_tension");
    const core::Model model = core::build_model(scene);
    const core::Results r = nonlinear::solve_linear_static(model, scene.analysis);
    if (r.status != SolveStatus::kConverged) {
      std::fprintf(stderr, "plate_tension: status %s: %s\n", to_string(r.status),
                   r.message.c_str());
      return 1;
    }
    const double expected = kStress * kLength / kYoung;
    double worst = 0.0;
    int right_nodes = 0;
    for (int n = 0; n < model.mesh.num_nodes(); ++n) {
      if (std::abs(model.mesh.nodes[n].x() - kLength) > 1e-12) continue;
      ++right_nodes;
      worst = std::max(worst, std::abs(r.displacement[2 * n] - expected));
    }
    std::printf(
        "plate_tension: %d nodes on x = L, u_x expected %.10g (sigma L / E), "
        "largest error %.3g (tolerance %.1g relative)\n",
        right_nodes, expected, worst, kRelativeTolerance);
    if (right_nodes < 2 || !(worst <= kRelativeTolerance * expected)) {
      std::fprintf(stderr, "plate_tension: FAILED\n");
      return 1;
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "plate_tension: %s\n", e.what());
    return 1;
  }
}
