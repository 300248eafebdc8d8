// compare's charts: accuracy against solve time per method, the finest level's pressure
// profiles with Hertz's, the largest penetration per method and level (gnuplot, PNG and SVG).
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iterator>
#include <sstream>

#include "app/report/gnuplot.hpp"
#include "app/report/pressure_profile.hpp"
#include "app/report/units.hpp"
#include "app/studies/compare_report.hpp"

namespace c2d::app {

namespace {

std::string chart_commands_accuracy(const CompareStudy& s, std::string& data_text) {
  std::ostringstream data, plot;
  int block = 0;
  plot << "set title "
       << gp_text("Accuracy against solve time (" + metric_name(s) +
                  "; one point per refinement level)")
       << "\nset xlabel 'solve time (s)'\nset ylabel " << gp_text(metric_name(s))
       << "\nset logscale xy\nset grid\nset key outside right\nplot ";
  for (const auto& m : s.methods) {
    std::ostringstream block_data;
    int points = 0;
    for (const auto& r : s.rows) {
      const double e = accuracy(s, r);
      if (r.method != m || !std::isfinite(e) || !(e > 0) || !(r.t_solve > 0)) continue;
      block_data << r.t_solve << ' ' << e << ' ' << r.level << '\n';
      ++points;
    }
    if (!points) continue;
    data << block_data.str() << "\n\n";
    plot << (block ? ", \\\n     " : "") << gp_file(s.out + "/accuracy.dat") << " index " << block
         << " using 1:2 with linespoints pt 7 lw 2 title " << gp_text(m);
    ++block;
  }
  if (!block) return "";
  data_text = data.str();
  return plot.str() + "\n";
}

/// compare's charts, in the order they are drawn.
const ReportChart kCompareCharts[] = {{"accuracy_time", "accuracy against time", ""},
                                      {"pressure_profiles", "pressure profiles", ""},
                                      {"penetration", "penetration", ""}};

/// Adds `chart`, not written for `why` ("" when it was), to `charts`; returns `error`.
std::string add_chart(std::vector<ReportChart>& charts, ReportChart chart, const std::string& why,
                      const std::string& error = "") {
  chart.not_written = error.empty() ? why : error;
  charts.push_back(chart);
  return error;
}

/// accuracy_time.png/svg; "" or the chart's failure.
std::string chart_accuracy_time(const CompareStudy& s, std::vector<ReportChart>& charts) {
  if (s.metric.empty())
    return add_chart(charts, kCompareCharts[0], "the scene has no reference to measure against");
  std::string data;
  const std::string cmd = chart_commands_accuracy(s, data);
  if (cmd.empty())
    return add_chart(charts, kCompareCharts[0], "no converged run has an error and a time above 0");
  return add_chart(charts, kCompareCharts[0], "",
                   plot_with_data(s.out, "accuracy_time", cmd, {{s.out + "/accuracy.dat", data}}));
}

/// pressure_profiles.png/svg: every method's pressures on the finest level, with Hertz's.
std::string chart_pressure_profiles(const CompareStudy& s, int finest,
                                    std::vector<ReportChart>& charts) {
  std::ostringstream plot;
  plot << "set title 'Contact pressure, level " << finest << " (finest), every method'\nset xlabel "
       << gp_text(axis_label("x or y, the coordinate the contact spreads along",
                             parse_units(s.units).length))
       << "\nset ylabel " << gp_text(axis_label("pressure", parse_units(s.units).stress))
       << "\nset grid\nset key top right\n";
  if (s.hertz) {
    // The data's span within 1.6 half-widths of the centre (a half model shows one side).
    double lo = 1e300, hi = -1e300;
    for (const auto& r : s.rows)
      if (r.level == finest)
        for (const auto& xp : r.profile) lo = std::min(lo, xp.first), hi = std::max(hi, xp.first);
    write_hertz_window(plot, *s.hertz, lo, hi);
    plot << "set key top left\n";
  }
  plot << "plot ";
  int n = 0;
  std::vector<PlotData> files;
  for (const auto& r : s.rows) {
    if (r.level != finest || r.profile.empty()) continue;
    std::ostringstream d;
    d << std::setprecision(12);
    for (const auto& [x, p] : r.profile) d << x << ' ' << p << '\n';
    const std::string path = s.out + "/profile_" + r.method + ".dat";
    files.push_back({path, d.str()});
    plot << (n ? ", \\\n     " : "") << gp_file(path) << " using 1:2 with linespoints pt " << 4 + n
         << " ps 0.7 title " << gp_text(r.method);
    ++n;
  }
  if (s.hertz) {
    plot << (n ? ", \\\n     " : "");
    write_hertz_curve(plot, *s.hertz);
    plot << " with lines lw 2 lc rgb 'black' dt 2 title 'Hertz'";
  }
  plot << "\n";
  if (!n) return add_chart(charts, kCompareCharts[1], "no run converged on the finest level");
  return add_chart(charts, kCompareCharts[1], "",
                   plot_with_data(s.out, "pressure_profiles", plot.str(), files));
}

/// penetration.png/svg: the largest penetration per method and level.
std::string chart_penetration(const CompareStudy& s, std::vector<ReportChart>& charts) {
  std::ostringstream d, plot;
  int n = 0;
  plot << "set title 'Largest penetration per method (exact methods at round-off; 0 drawn at "
          "1e-20)'\n"
       << "set xlabel 'refinement level'\nset ylabel "
       << gp_text(axis_label("max penetration", parse_units(s.units).length))
       << "\nset logscale y\n"
       << "set format y '10^{%L}'\nset grid\nset key outside right\nset xtics 1\n"
       // Half a level either side: the first and last levels' points clear of the border.
       << "set xrange [-0.5:" << s.levels - 0.5 << "]\nplot ";
  for (const auto& m : s.methods) {
    std::ostringstream block;
    int points = 0;
    for (const auto& r : s.rows)
      if (r.method == m && r.converged() && std::isfinite(r.penetration))
        block << r.level << ' ' << std::max(r.penetration, 1e-20) << '\n', ++points;
    if (!points) continue;
    d << block.str() << "\n\n";
    plot << (n ? ", \\\n     " : "") << gp_file(s.out + "/penetration.dat") << " index " << n
         << " using 1:2 with linespoints pt 7 lw 2 title " << gp_text(m);
    ++n;
  }
  plot << "\n";
  if (!n) return add_chart(charts, kCompareCharts[2], "no run converged");
  return add_chart(
      charts, kCompareCharts[2], "",
      plot_with_data(s.out, "penetration", plot.str(), {{s.out + "/penetration.dat", d.str()}}));
}

}  // namespace

std::string draw_compare_charts(const CompareStudy& s, std::vector<ReportChart>& charts) {
  std::string error;
  for (size_t k = 0; k < std::size(kCompareCharts); ++k) {
    if (!error.empty())
      add_chart(charts, kCompareCharts[k], "not drawn after the failure of an earlier chart");
    else
      error = k == 0   ? chart_accuracy_time(s, charts)
              : k == 1 ? chart_pressure_profiles(s, s.levels - 1, charts)
                       : chart_penetration(s, charts);
  }
  return error;
}

}  // namespace c2d::app
