// The post-processor's pictures (the seed's figures 4.2-4.19): filled contours of a result
// field on the (deformed) mesh, the ZZ local-parameter map, and meshes of adaptive cycles side
// by side. Reads the run's own VTU files; draws through gnuplot (PNG and SVG).
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "app/report/vtu_reader.hpp"
#include "core/types.hpp"

namespace c2d::app {

/// The fields `plot` knows, with their labels: sx sy sxy vm p1 p2 ux uy error.
const std::vector<std::string>& plot_fields();
/// "sx|sy|...|error": plot_fields() for messages about --field.
std::string plot_field_list();

struct PlotOptions {
  std::string field = "vm";
  std::optional<std::array<double, 4>> zoom;  ///< x0, y0, x1, y1
  double deformed = 0.0;  ///< displacement scale; < 0: automatic (displacement_scale)
  bool edges = false;                         ///< draw element edges
  int levels = 12;                            ///< colour bands
  std::string units;    ///< the scene's `units`: the axes and the colour bar carry them
  std::string title;    ///< replaces the field's label as the title ("": the label)
  std::string note;     ///< said last in the title, after the values and the deformation
  /// Polylines drawn over the field in black (rigid obstacles).
  std::vector<std::vector<Vec2>> overlay;
};

/// What a picture shows, for the terminal: value range and, for `error`, elements above 1.
struct PlotSummary {
  double min = 0, max = 0;
  int elements = 0, above_one = 0;  ///< error map: elements drawn, elements with ξ_e > 1
  std::string error;                ///< gnuplot's failure, "" on success
};

/// Filled contours of one field (isobands of the nodal values, linear on each triangle; a T6
/// element is drawn as its four sub-triangles), or for `error` the elements coloured by
/// ξ_e <= 1 / > 1 as the seed did. Writes DIR/STEM.png and .svg.
PlotSummary plot_field(const VtuData& vtu, const PlotOptions& options, const std::string& dir,
                       const std::string& stem);

/// Element edges of several meshes side by side (titles given), in the zoom window if any.
std::string plot_mesh_comparison(const std::vector<std::pair<std::string, VtuData>>& meshes,
                                 const std::optional<std::array<double, 4>>& zoom,
                                 const std::string& dir, const std::string& stem);

/// A contour plot's colour bar: the data's range widened to whole ticks of a 1, 2, 2.5 or 5
/// times 10^k step (at most 10 intervals), each tick interval cut into 1, 2 or 5 bands, the
/// count nearest `levels`: the ticks read as round numbers, not as the data's extremes.
struct ColourScale {
  double lo = 0, hi = 1, tick = 1, band = 1;
  int bands = 1;
};
ColourScale colour_scale(double lo, double hi, int levels);

/// The smallest of 1, 2, 2.5 and 5 times a power of ten not below `raw` (> 0).
double nice_step(double raw);

/// How much a picture magnifies the displacements: the largest of 1, 2 and 5 times a power of
/// ten that draws `umax` within 8 % of the model's `size` (0 when nothing moves), and never
/// less than 1: displacements already that large are shown as they are. Finite strain
/// (geometric nonlinearity) is always drawn at true scale, 1: the large deflection is the
/// result, and a magnified configuration is none the solver computed.
double displacement_scale(double umax, double size, bool finite_strain);

/// "true scale" or "displacements x 200": what a title says of a picture's deformation.
std::string deformation_text(double scale);

/// Isobands of a linear triangle: the polygons where lo <= v <= hi (empty when none).
std::vector<Vec2> clip_band(const std::array<Vec2, 3>& x, const std::array<double, 3>& v, double lo,
                            double hi);

}  // namespace c2d::app
