// `contact2d plot DIR`: which of a run's result files and fields to draw, drawn by
// field_plot.hpp's charts.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "app/report/field_plot.hpp"

namespace c2d::app {

/// `contact2d plot DIR`: which result file and fields to draw.
struct PlotRequest {
  std::string dir;
  std::vector<std::string> fields;  ///< names from plot_fields(), or "all"
  PlotOptions options;              ///< its field is set per picture
  int step = 0;                     ///< > 0: DIR/step_NNNN.vtu; 0: the last step written
  int cycle = -1;                   ///< >= 0: DIR/cycle_NN.vtu of an adaptive run
};

struct PlotWritten {
  std::vector<std::pair<std::string, std::string>> written;  ///< stem, what it shows
  std::string error;                                         ///< gnuplot's failure
};

/// Draws every requested field from the chosen VTU and, when DIR holds an adaptive run's
/// cycle_NN.vtu files, up to four of their meshes side by side (adapt_meshes.png). Throws
/// InputError for a missing folder or file, or an unknown field.
PlotWritten plot_run(const PlotRequest& request);

}  // namespace c2d::app
