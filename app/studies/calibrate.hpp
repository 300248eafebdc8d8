// `contact2d calibrate`: scene parameters fitted to measured probe values by least squares
// (Ceres), one in-process solve per evaluation.
#pragma once

#include <string>
#include <vector>

#include "app/studies/study.hpp"

namespace c2d::app {

struct CalibrateOptions : StudyOptions {
  std::string data;               ///< CSV: probe,value[,weight]
  std::vector<std::string> fits;  ///< key[=lo:hi[:log|lin]]; E, nu, thickness = material.*
  int max_iterations = 30;
};

/// Fits the parameters so the scene's probes match the data (residuals relative to the measured
/// values, times the weights), in log space for parameters marked log (the default for positive
/// ones), within bounds. Writes calibrate.json and calibrate.md with the fitted values, their
/// standard deviations from Ceres's covariance (scaled by the residual variance when there are
/// more data than parameters), the residuals and the solver's summary. Returns the exit code.
int run_calibrate(const CalibrateOptions& o);

}  // namespace c2d::app
