// Named scalar outputs of a scene, evaluated on a solved model.
#pragma once

#include <map>
#include <string>

#include "core/model.hpp"
#include "core/results.hpp"
#include "core/scene.hpp"

namespace c2d::core {

/// A quantity from point values: displacement u, reaction, stress s and the material there
/// (von Mises needs sigma_zz, which depends on the plane state and nu).
double point_quantity(const std::string& quantity, const Vec2& u, const Vec2& reaction,
                      const Voigt& s, const Material& material);

/// Field value at a node: ux, uy, umag, sx, sy, sxy, vm, s1, s2 (smoothed stresses),
/// reaction_x, reaction_y.
double nodal_quantity(const Model& model, const Results& results, const std::string& quantity,
                      int node);

/// Evaluates every probe; throws InputError when a probe point lies outside the mesh.
std::map<std::string, double> evaluate_probes(const Scene& scene, const Model& model,
                                              const Results& results);

}  // namespace c2d::core
