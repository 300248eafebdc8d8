#include "app/report/hertz.hpp"

#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>

namespace c2d::app {

std::optional<HertzReference> hertz_reference(const core::Scene& scene) {
  const auto p0 = scene.reference.find("p_max"), b = scene.reference.find("contact_length");
  if (scene.reference_kind.rfind("hertz", 0) != 0 || p0 == scene.reference.end() ||
      b == scene.reference.end())
    return std::nullopt;
  return HertzReference{p0->second, b->second};
}

namespace {

/// Relative L2 error of a sampled profile (linear between its points) against `exact` over
/// [−window b, window b] ∩ the points' span: 4000 trapezoid samples. NaN without a span.
template <class Exact>
double profile_l2_error(std::vector<std::pair<double, double>> pts, double b, Exact exact,
                        double window = 1.5) {
  std::sort(pts.begin(), pts.end());
  const double lo = std::max(pts.front().first, -window * b),
               hi = std::min(pts.back().first, window * b);
  if (!(hi > lo)) return std::nan("");
  constexpr int kSamples = 4000;
  double err2 = 0.0, ref2 = 0.0;
  size_t k = 0;
  for (int i = 0; i <= kSamples; ++i) {
    const double x = lo + (hi - lo) * i / kSamples;
    while (k + 2 < pts.size() && pts[k + 1].first < x) ++k;
    const auto& a = pts[k];
    const auto& c = pts[k + 1];
    const double t =
        c.first > a.first ? std::clamp((x - a.first) / (c.first - a.first), 0.0, 1.0) : 0.0;
    const double vh = a.second + t * (c.second - a.second), va = exact(x);
    const double w = (i == 0 || i == kSamples) ? 0.5 : 1.0;
    err2 += w * (vh - va) * (vh - va);
    ref2 += w * va * va;
  }
  return ref2 > 0 ? std::sqrt(err2 / ref2) : std::nan("");
}

/// hertz_profile_error over |x| ≤ window × b.
double hertz_error_within(const std::vector<std::pair<double, double>>& x_p, double p0, double b,
                          double window) {
  if (x_p.size() < 2 || !(b > 0) || !(p0 > 0)) return std::nan("");
  return profile_l2_error(
      x_p, b,
      [&](double x) { return std::abs(x) < b ? p0 * std::sqrt(1.0 - (x / b) * (x / b)) : 0.0; },
      window);
}

}  // namespace

std::optional<CattaneoReference> cattaneo_reference(const core::Scene& scene) {
  const auto& ref = scene.reference;
  if (scene.reference_kind != "cattaneo_mindlin" || !ref.count("p_max") ||
      !ref.count("contact_length") || !ref.count("stick_length") || !ref.count("coefficient"))
    return std::nullopt;
  return CattaneoReference{{ref.at("p_max"), ref.at("contact_length") / 2},
                           ref.at("coefficient"),
                           ref.at("stick_length") / 2};
}

double hertz_profile_error(const std::vector<std::pair<double, double>>& x_p, double p0, double b) {
  return hertz_error_within(x_p, p0, b, 1.5);
}

double hertz_inner_profile_error(const std::vector<std::pair<double, double>>& x_p, double p0,
                                 double b) {
  return hertz_error_within(x_p, p0, b, kInnerWindow);
}

double cattaneo_mindlin_error(const std::vector<std::pair<double, double>>& x_q, double mu,
                              double p0, double b, double c) {
  if (x_q.size() < 2 || !(b > 0) || !(p0 > 0) || !(mu > 0) || !(c >= 0) || c > b)
    return std::nan("");
  return profile_l2_error(x_q, b, [&](double x) {
    double q = std::abs(x) < b ? mu * p0 * std::sqrt(1.0 - (x / b) * (x / b)) : 0.0;
    if (std::abs(x) < c) q -= mu * p0 * (c / b) * std::sqrt(1.0 - (x / c) * (x / c));
    return q;
  });
}

namespace {

struct HertzResidual {
  HertzResidual(double x, double p) : x_(x), p_(p) {}
  template <typename T>
  bool operator()(const T* const p0, const T* const b, const T* const x0, T* r) const {
    const T s = (T(x_) - x0[0]) / b[0];
    const T arg = T(1.0) - s * s;
    const T model = arg > T(1e-14) ? p0[0] * sqrt(arg) : T(0.0) * p0[0];
    r[0] = T(p_) - model;
    return true;
  }
  double x_, p_;
};

}  // namespace

HertzFit fit_hertz_profile(const std::vector<std::pair<double, double>>& x_p) {
  HertzFit fit;
  double pmax = 0.0, xmin = 1e300, xmax = -1e300, lo = 1e300, hi = -1e300;
  for (const auto& [x, p] : x_p) {
    xmin = std::min(xmin, x), xmax = std::max(xmax, x);
    if (p > pmax) pmax = p;
    if (p > 0) lo = std::min(lo, x), hi = std::max(hi, x);
  }
  if (!(pmax > 0) || x_p.size() < 3) {
    fit.message = "no positive pressure to fit";
    return fit;
  }
  const double span = xmax - xmin;
  const bool half = xmin >= -1e-9 * span || xmax <= 1e-9 * span;  // nodes on one side of 0
  double p0 = pmax, x0 = half ? 0.0 : 0.5 * (lo + hi);
  double b = half ? std::max(std::abs(lo), std::abs(hi)) : 0.5 * (hi - lo);
  b = std::max(b * 1.05, 1e-9 * span);
  ceres::Problem problem;
  for (const auto& [x, p] : x_p)
    problem.AddResidualBlock(
        new ceres::AutoDiffCostFunction<HertzResidual, 1, 1, 1, 1>(new HertzResidual(x, p)),
        nullptr, &p0, &b, &x0);
  problem.SetParameterLowerBound(&b, 0, 1e-6 * span);
  problem.SetParameterLowerBound(&p0, 0, 0.0);
  if (half) problem.SetParameterBlockConstant(&x0);
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.logging_type = ceres::SILENT;
  options.max_num_iterations = 100;
  options.function_tolerance = 1e-14;
  options.parameter_tolerance = 1e-12;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  fit.ok = summary.IsSolutionUsable() && std::isfinite(p0) && std::isfinite(b);
  fit.p0 = p0;
  fit.b = b;
  fit.x0 = x0;
  fit.iterations = static_cast<int>(summary.iterations.size());
  fit.message = summary.BriefReport();
  return fit;
}

void write_hertz_window(std::ostream& gp, const HertzReference& hertz, double lo, double hi) {
  gp << "set xrange [" << std::max(lo, -1.6 * hertz.b) << ":" << std::min(hi, 1.6 * hertz.b)
     << "]\nset samples 400\n";
}

void write_hertz_curve(std::ostream& gp, const HertzReference& hertz) {
  gp << "(abs(x) < " << hertz.b << " ? " << hertz.p0 << "*sqrt(1-(x/" << hertz.b << ")**2) : 0)";
}

}  // namespace c2d::app
