// Charts through gnuplot (PNG and SVG). A missing gnuplot is reported, not fatal.
#pragma once

#include <string>

#include "core/model.hpp"
#include "core/results.hpp"

namespace c2d::app {

/// Runs a gnuplot script; returns an empty string on success, else why it failed.
std::string run_gnuplot(const std::string& script_path);

/// Deformed mesh (scaled) over the undeformed outline, coloured by smoothed von Mises.
/// Writes DIR/deformed.png and DIR/deformed.svg; returns "" or the failure reason.
std::string chart_deformed_mesh(const std::string& dir, const core::Model& model,
                                const core::Results& results);

}  // namespace c2d::app
