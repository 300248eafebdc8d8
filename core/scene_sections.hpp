// The parsers of a scene's sections (internal to core's scene reader). Each takes the section's
// TOML view and fails with a located InputError; the checks that span sections (a selection's
// body exists, names are unique) are the caller's, except where a parser is given the earlier
// entries.
#pragma once

#include <vector>

#include "core/scene.hpp"
#include "core/toml_view.hpp"

namespace c2d::core {

RefineSpec parse_refine(const TomlView& v);
ShapeSpec parse_shape(const TomlView& v);
void parse_analysis(const TomlView& v, AnalysisSpec& a);
void parse_adapt(const TomlView& v, AdaptSpec& a);
ProbeSpec parse_probe(const TomlView& v);
/// A [[material]]; `earlier` for the unique-name check.
MaterialSpec parse_material(const TomlView& m, const std::vector<MaterialSpec>& earlier);
/// A [[body]] of `scene` (its materials, earlier bodies and mesh scale already read).
BodySpec parse_body(const TomlView& b, const Scene& scene);
SupportSpec parse_support(const TomlView& s);
/// A [[spring]] (the index names an unnamed one); `materials` bound its stiffness
/// (spring_stiffness_limit).
SpringSpec parse_spring(const TomlView& s, int index, const std::vector<MaterialSpec>& materials);
/// The stiffest spring a scene takes: 1e12 times the largest E·t of its materials (a stiffness
/// per unit length, as a spring's). A stiffer spring is a support in all but name, and the
/// factorisation cannot tell the body from an unsupported one.
double spring_stiffness_limit(const std::vector<MaterialSpec>& materials);
/// A [[load]] (the index names an unnamed one).
LoadSpec parse_load(const TomlView& l, int index);
/// An `amplitude` table: [[λ, a], ...] from λ = 0 to λ = 1, λ strictly increasing, finite a.
AmplitudeTable parse_amplitude(const TomlView& a);
/// [reference]: the kind of reference and its values (what a run is checked against).
void parse_reference(const TomlView& root, Scene& scene);

}  // namespace c2d::core
