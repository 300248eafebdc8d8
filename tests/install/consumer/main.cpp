// A unit square plate (plane stress) pulled by a uniform traction σ on its right edge, held by
// rollers on its left edge and at one corner: uniaxial stress, so the right edge moves by
// u_x = σ L / E exactly, and linear triangles reproduce that linear field to round-off.
// Solved twice: through the layers (build_model, solve_linear_static) and through the entry
// point a whole run takes (app::run_scene, as `contact2d run` and the Python module do), which
// writes the run's folder (argv[1]) with its summary.json.
// Built and run by the install test against the installed package; exits non-zero on failure.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "app/run/run_scene.hpp"
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

/// Whether the right edge of `model` moved by σ L / E under `r`, printed with `how`.
bool right_edge_exact(const c2d::core::Model& model, const c2d::core::Results& r,
                      const char* how) {
  if (r.status != c2d::SolveStatus::kConverged) {
    std::fprintf(stderr, "plate_tension (%s): status %s: %s\n", how, to_string(r.status),
                 r.message.c_str());
    return false;
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
      "plate_tension (%s): %d nodes on x = L, u_x expected %.10g (sigma L / E), "
      "largest error %.3g (tolerance %.1g relative)\n",
      how, right_nodes, expected, worst, kRelativeTolerance);
  return right_nodes >= 2 && worst <= kRelativeTolerance * expected;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace c2d;
  if (argc != 2) {
    std::fprintf(stderr, "usage: plate_tension OUTPUT_FOLDER\n");
    return 2;
  }
  try {
    const core::Scene scene = core::parse_scene(plate_scene(), "plate_tension");
    const core::Model model = core::build_model(scene);
    const core::Results r = nonlinear::solve_linear_static(model, scene.analysis);
    app::RunOptions options;
    options.out = argv[1];
    const app::RunResult run = app::run_scene(scene, options);
    const bool summary = run.summary.value("status", "") == "converged" &&
                         std::filesystem::exists(std::filesystem::path(argv[1]) / "summary.json");
    if (!summary) std::fprintf(stderr, "plate_tension: run_scene wrote no converged summary\n");
    if (!right_edge_exact(model, r, "layers") ||
        !right_edge_exact(run.run->model, run.run->results, "run_scene") || !summary) {
      std::fprintf(stderr, "plate_tension: FAILED\n");
      return 1;
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "plate_tension: %s\n", e.what());
    return 1;
  }
}
