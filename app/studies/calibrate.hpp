// Least-squares fitting with Ceres: `contact2d calibrate` (scene parameters against measured
// probe values) and the Hertz profile fit that `compare` applies to every method's pressures.
#pragma once

#include <string>
#include <vector>

#include "app/studies/studies.hpp"

namespace c2d::app {

struct CalibrateOptions : StudyOptions {
  std::string data;                ///< CSV: probe,value[,weight]
  std::vector<std::string> fits;   ///< key[=lo:hi[:log|lin]]; E, nu, thickness = material.*
  int max_iterations = 30;
};

/// Fits the parameters so the scene's probes match the data (residuals relative to the measured
/// values, times the weights), in log space for parameters marked log (the default for positive
/// ones), within bounds. Writes calibrate.json and calibrate.md with the fitted values, their
/// standard deviations from Ceres's covariance (scaled by the residual variance when there are
/// more data than parameters), the residuals and the solver's summary. Returns the exit code.
int run_calibrate(const CalibrateOptions& o);

struct HertzFit {
  bool ok = false;
  double p0 = 0.0, b = 0.0, x0 = 0.0;
  double sigma_p0 = 0.0, sigma_b = 0.0;  ///< from the covariance (0 when unavailable)
  int iterations = 0;
  std::string message;
};

/// Fits p0 √(1 − ((x − x0)/b)²) (zero outside |x − x0| < b) to nodal pressures by nonlinear
/// least squares, so the contact width does not depend on where the nodes fall. x0 is fixed at 0
/// when the nodes lie on one side of it (a symmetric half model). Starts from the largest
/// pressure and the extent of the positive ones.
HertzFit fit_hertz_profile(const std::vector<std::pair<double, double>>& x_p);

}  // namespace c2d::app
