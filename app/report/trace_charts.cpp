#include "app/report/trace_charts.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "app/report/csv_table.hpp"
#include "app/report/gnuplot.hpp"
#include "app/report/json_file.hpp"
#include "app/report/pressure_profile.hpp"
#include "app/report/units.hpp"
#include "core/errors.hpp"
#include "core/writers.hpp"

namespace c2d::app {

namespace {

/// The units of the run in DIR (its summary.json's `units`; none when it has none).
Units run_units(const std::string& dir) {
  const JsonFileRead read = try_read_json_file(dir + "/summary.json");
  const nlohmann::json& s = read.value;
  if (!s.is_object() || !s.contains("units") || !s["units"].is_string()) return {};
  return parse_units(s["units"].get<std::string>());
}

/// 'slave node position x (reference) [mm]' for the axis the surface spreads along.
std::string position_label(int axis, const Units& u) {
  return gp_text(axis_label(std::string("slave node position ") + (axis ? "y" : "x") +
                                " (reference)", u.length));
}

/// Activation and contact force charts from contact_steps.csv.
std::string contact_charts(const std::string& dir, const CsvTable& t, const Units& u,
                           TraceCharts& out) {
  const int c_step = t.column("step"), c_lf = t.column("load_factor"), c_x = t.column("x"),
            c_y = t.column("y"), c_force = t.column("force"), c_p = t.column("pressure"),
            c_active = t.column("active");
  // Position along the slave surface: the reference coordinate along which it spreads most.
  const int axis = spread_axis(t.points("x", "y"));
  bool any_pressure = false;
  for (size_t r = 0; r < t.rows.size(); ++r) any_pressure = any_pressure || t.number(r, c_p) != 0.0;
  const int c_pos = axis ? c_y : c_x, c_colour = any_pressure ? c_p : c_force;
  std::ostringstream act;
  act << std::setprecision(12);
  std::map<int, std::pair<double, double>> per_step;  // step -> (load factor, force)
  std::map<int, int> active_per_step;
  for (size_t r = 0; r < t.rows.size(); ++r) {
    const int step = static_cast<int>(t.number(r, c_step));
    const bool active = t.number(r, c_active) > 0;
    act << t.number(r, c_pos) << ' ' << t.number(r, c_lf) << ' ' << t.number(r, c_colour) << ' '
        << (active ? 1 : 0) << '\n';
    auto& s = per_step[step];
    s.first = t.number(r, c_lf);
    s.second += t.number(r, c_force);
    active_per_step[step] += active;
  }
  const std::string act_path = dir + "/activation.dat";
  std::ostringstream cmd;
  cmd << "set title 'Contact activation per load step ("
      << t.rows.size() / std::max<size_t>(1, per_step.size()) << " slave nodes)'\nset xlabel "
      << position_label(axis, u)
      << "\nset ylabel 'load factor'\nset grid\nset key outside bottom center horizontal\n"
      // Viridis reversed: the dark end, high pressure, stands out on the white page.
      << "set yrange [0:1.05]\nset cbrange [0:*]\n"
      << gp_palette() << "set palette negative\n"
      << "set cblabel "
      << gp_text(any_pressure ? axis_label("contact pressure", u.stress)
                              : axis_label("contact force", u.force))
      << "\n"
      << "plot " << gp_file(act_path) << " using 1:($4 > 0 ? 1/0 : $2) with points pt 6 ps 0.6 "
      << "lc rgb 'gray60' title 'open', \\\n     '' using 1:($4 > 0 ? $2 : 1/0):3 with points "
      << "pt 5 ps 1.4 lc palette title 'in contact (colour: "
      << (any_pressure ? "pressure" : "force") << ")'\n";
  std::string err = plot_with_data(dir, "activation", cmd.str(), {{act_path, act.str()}});
  if (!err.empty()) return err;
  out.written.emplace_back("activation", "slave node position x load factor, coloured by " +
                                             std::string(any_pressure ? "pressure" : "force"));

  std::ostringstream force;
  force << std::setprecision(12) << "0 0 0\n";
  for (const auto& [step, s] : per_step)
    force << s.first << ' ' << s.second << ' ' << active_per_step[step] << '\n';
  const std::string force_path = dir + "/contact_force.dat";
  std::ostringstream fc;
  fc << "set title 'Total contact force against load factor'\nset xlabel 'load factor'\n"
     << "set ylabel " << gp_text(axis_label("total contact force", u.force))
     << "\nset y2label 'active slave nodes'\nset ytics nomirror\n"
     << "set y2tics\nset grid\nset key top left\nset xrange [0:1]\nset yrange [0:*]\n"
     << "set y2range [0:*]\nplot " << gp_file(force_path)
     << " using 1:2 with linespoints pt 7 lw 2 title 'contact force', '' using 1:3 axes x1y2 "
     << "with steps dt 2 lw 1.5 title 'active nodes'\n";
  err = plot_with_data(dir, "contact_force", fc.str(), {{force_path, force.str()}});
  if (err.empty())
    out.written.emplace_back("contact_force", "total contact force and active nodes per step");
  return err;
}

/// Friction: the stick and slip zones per load step (slave node position × load factor,
/// coloured by state) and the stick and slip counts per step, from contact_steps.csv's state.
std::string friction_charts(const std::string& dir, const CsvTable& t, const Units& u,
                            TraceCharts& out) {
  const int c_step = t.column("step"), c_lf = t.column("load_factor"), c_x = t.column("x"),
            c_y = t.column("y"), c_state = t.column("state"), c_q = t.column("shear");
  const int axis = spread_axis(t.points("x", "y"));
  const int c_pos = axis ? c_y : c_x;
  std::ostringstream zones;
  zones << std::setprecision(12);
  std::map<int, std::array<double, 3>> per_step;  // step -> (load factor, stick, slip)
  for (size_t r = 0; r < t.rows.size(); ++r) {
    const std::string& state = t.rows[r][c_state];
    if (state != "open" && state != "stick" && state != "slip")
      throw InputError(t.path + ":" + std::to_string(r + 2) +
                       ": state: expected open, stick or slip, found '" + state + "'");
    const int code = state == "stick" ? 1 : state == "slip" ? 2 : 0;
    zones << t.number(r, c_pos) << ' ' << t.number(r, c_lf) << ' ' << code << ' '
          << std::abs(t.number(r, c_q)) << '\n';
    auto& s = per_step[static_cast<int>(t.number(r, c_step))];
    s[0] = t.number(r, c_lf);
    s[1] += code == 1;
    s[2] += code == 2;
  }
  const std::string zones_path = dir + "/stick_slip.dat";
  std::ostringstream cmd;
  cmd << "set title 'Stick and slip per load step'\nset xlabel " << position_label(axis, u)
      << "\nset ylabel 'load factor'\nset grid\n"
      << "set key outside bottom center horizontal\nset yrange [0:1.05]\n"
      << "plot " << gp_file(zones_path) << " using 1:($3 == 0 ? $2 : 1/0) with points pt 6 "
      << "ps 0.6 lc rgb 'gray60' title 'open', \\\n     '' using 1:($3 == 1 ? $2 : 1/0) with "
      << "points pt 5 ps 1.2 lc rgb '#21918c' title 'stick', \\\n     '' using 1:($3 == 2 ? "
      << "$2 : 1/0) with points pt 5 ps 1.2 lc rgb '#e66101' title 'slip'\n";
  std::string err = plot_with_data(dir, "stick_slip", cmd.str(), {{zones_path, zones.str()}});
  if (!err.empty()) return err;
  out.written.emplace_back("stick_slip", "slave node position x load factor: open, stick, slip");
  std::ostringstream counts;
  counts << std::setprecision(12) << "0 0 0\n";
  for (const auto& [step, s] : per_step) counts << s[0] << ' ' << s[1] << ' ' << s[2] << '\n';
  const std::string counts_path = dir + "/stick_slip_counts.dat";
  std::ostringstream cc;
  cc << "set title 'Sticking and slipping slave nodes against load factor'\n"
     << "set xlabel 'load factor'\nset ylabel 'slave nodes'\nset grid\nset key top left\n"
     << "set xrange [0:1]\nset yrange [0:*]\nplot " << gp_file(counts_path)
     << " using 1:2 with linespoints pt 5 lw 2 lc rgb '#21918c' title 'stick', '' using 1:3 "
     << "with linespoints pt 7 lw 2 lc rgb '#e66101' title 'slip'\n";
  err = plot_with_data(dir, "stick_slip_counts", cc.str(), {{counts_path, counts.str()}});
  if (err.empty())
    out.written.emplace_back("stick_slip_counts", "sticking and slipping nodes per step");
  return err;
}

/// Newton residual history: one line per load step attempt, in the order of the trace.
std::string residual_chart(const std::string& dir, const CsvTable& t, TraceCharts& out) {
  const int c_step = t.column("step"), c_attempt = t.column("attempt"),
            c_res = t.column("residual"), c_lf = t.column("load_factor");
  std::ostringstream data;
  data << std::setprecision(12);
  std::vector<std::string> titles;
  int last_step = -1, last_attempt = -1, x = 0;
  for (size_t r = 0; r < t.rows.size(); ++r) {
    const int step = static_cast<int>(t.number(r, c_step));
    const int attempt = static_cast<int>(t.number(r, c_attempt));
    if (step != last_step || attempt != last_attempt) {
      if (!titles.empty()) data << "\n\n";
      std::ostringstream title;
      title << "λ = " << rounded_text(t.number(r, c_lf)) << (attempt > 0 ? " (retry)" : "");
      titles.push_back(title.str());
      last_step = step, last_attempt = attempt, x = 0;
    }
    const double res = t.number(r, c_res);
    data << x++ << ' ' << (res > 0 ? res : 1e-300) << '\n';
  }
  if (titles.empty()) return "";
  const std::string path = dir + "/residuals.dat";
  std::ostringstream cmd;
  cmd << "set title 'Newton residual history per load step (‖R‖∞, outer iterations joined)'\n"
      << "set xlabel 'residual evaluation within the step'\nset ylabel 'residual'\n"
      << "set logscale y\nset format y '10^{%L}'\nset grid\n"
      << (titles.size() > 12 ? "set key off\n" : "set key outside right\n") << "plot ";
  for (size_t i = 0; i < titles.size(); ++i)
    cmd << (i ? ", \\\n     " : "") << gp_file(path) << " index " << i
        << " using 1:2 with linespoints pt 7 ps 0.6 title " << gp_text(titles[i]);
  cmd << "\n";
  const std::string err = plot_with_data(dir, "residuals", cmd.str(), {{path, data.str()}});
  if (err.empty())
    out.written.emplace_back("residuals", std::to_string(titles.size()) +
                                              " load step attempts, residual per Newton iteration");
  return err;
}

}  // namespace

TraceCharts draw_trace_charts(const std::string& dir) {
  if (!std::filesystem::is_directory(dir))
    throw InputError(dir + ": expected the output folder of a run, found " +
                     (std::filesystem::exists(dir) ? "a file (trace reads the folder `contact2d "
                                                     "run SCENE --out DIR` wrote)"
                                                   : "no such folder"));
  const std::string trace_path = dir + "/trace.csv";
  if (!std::filesystem::exists(trace_path))
    throw InputError(trace_path + ": not found; `contact2d run SCENE --out " + dir + "` writes it");
  const CsvTable trace = read_csv(trace_path);
  TraceCharts out;
  const Units units = run_units(dir);
  const std::string steps_path = dir + "/contact_steps.csv";
  if (std::filesystem::exists(steps_path)) {
    const CsvTable steps = read_csv(steps_path);
    if (!steps.rows.empty()) out.error = contact_charts(dir, steps, units, out);
    const bool friction = std::find(steps.columns.begin(), steps.columns.end(), "state") !=
                          steps.columns.end();
    if (!steps.rows.empty() && friction && out.error.empty())
      out.error = friction_charts(dir, steps, units, out);
  }
  if (out.error.empty()) out.error = residual_chart(dir, trace, out);
  return out;
}

}  // namespace c2d::app
