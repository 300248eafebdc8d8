#include "app/report/charts.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "app/process.hpp"
#include "core/errors.hpp"
#include "core/probes.hpp"
#include "core/writers.hpp"

#ifndef C2D_GNUPLOT
#define C2D_GNUPLOT "gnuplot"
#endif

namespace c2d::app {

namespace {

bool has_control_character(std::string_view text) {
  return std::any_of(text.begin(), text.end(),
                     [](char c) { return static_cast<unsigned char>(c) < 0x20 || c == 0x7f; });
}

/// Doubles every single quote: inside '...' gnuplot substitutes nothing (no backquotes, no
/// macros, no escapes), and '' stands for one quote.
std::string single_quoted(std::string_view text) {
  std::string out = "'";
  for (char c : text) out += c == '\'' ? std::string("''") : std::string(1, c);
  return out + "'";
}

}  // namespace

std::string gp_text(std::string_view text) {
  std::string clean(text);
  for (char& c : clean)
    if (has_control_character({&c, 1})) c = ' ';
  return single_quoted(clean);
}

std::string gp_file(const std::string& path) {
  if (has_control_character(path))
    throw InputError(path + ": expected a file path without control characters, found one");
  // Absolute, so that the name can never start with '<' or '|' (gnuplot runs those as commands).
  return single_quoted(std::filesystem::absolute(path).lexically_normal().string());
}

std::string run_gnuplot(const std::string& script_path) {
  const std::string exe = std::filesystem::exists(C2D_GNUPLOT) ? C2D_GNUPLOT : "gnuplot";
  const std::string script = std::filesystem::absolute(script_path).string();
  const std::string log = script + ".log";
  const ProcessOutcome run = run_process(exe, {script}, log);
  if (!run.started) return run.error;
  if (run.exit_code != 0)
    return "gnuplot failed (exit " + std::to_string(run.exit_code) + "), see " + log;
  std::filesystem::remove(log);
  return "";
}

std::string plot_png_and_svg(const std::string& dir, const std::string& stem,
                             const std::string& commands) {
  std::ostringstream gp;
  for (const char* term : {"png", "svg"}) {
    gp << (std::string(term) == "png" ? "set terminal pngcairo size 1200,800 font 'Sans,11'\n"
                                      : "set terminal svg size 1200,800 font 'Sans,11'\n")
       << "set output " << gp_file(dir + "/" + stem + "." + term) << "\n"
       << commands << "unset output\n";
  }
  const std::string script = dir + "/" + stem + ".gp";
  core::write_file_atomic(script, gp.str());
  const std::string err = run_gnuplot(script);
  if (err.empty()) std::filesystem::remove(script);
  return err;
}

int spread_axis(const std::vector<Vec2>& points) {
  Vec2 lo = Vec2::Constant(1e300), hi = Vec2::Constant(-1e300);
  for (const auto& p : points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  return hi.y() - lo.y() > hi.x() - lo.x() ? 1 : 0;
}

std::string chart_contact_pressure(const std::string& dir, const constraints::ContactReport& c,
                                   const core::Scene& scene) {
  // Abscissa: the reference coordinate along which the slave nodes spread most.
  std::vector<Vec2> positions;
  for (const auto& n : c.nodes) positions.push_back(n.x);
  const int axis = spread_axis(positions);
  std::vector<std::pair<double, double>> pts;
  for (const auto& n : c.nodes) pts.emplace_back(n.x[axis], n.pressure);
  std::sort(pts.begin(), pts.end());
  std::ostringstream data;
  data << std::setprecision(12);
  for (const auto& [x, p] : pts) data << x << ' ' << p << '\n';
  const std::string data_path = dir + "/pressure.dat";
  core::write_file_atomic(data_path, data.str());
  std::ostringstream cmd;
  cmd << std::setprecision(10) << "set title "
      << gp_text("Contact pressure (" + c.method + ", recovered from nodal forces)")
      << "\nset xlabel '" << (axis ? "y" : "x")
      << "'\nset ylabel 'pressure'\nset grid\nset key top left\n";
  const auto p0 = scene.reference.find("p_max"), b = scene.reference.find("contact_length");
  const bool hertz = scene.reference_kind.rfind("hertz", 0) == 0 &&
                     p0 != scene.reference.end() && b != scene.reference.end();
  // The analytic profile is centred on the origin; show the data within 1.6 half-widths.
  if (hertz)
    cmd << "set xrange [" << std::max(pts.front().first, -1.6 * b->second) << ":"
        << std::min(pts.back().first, 1.6 * b->second) << "]\nset samples 400\n";
  cmd << "plot " << gp_file(data_path) << " using 1:2 with linespoints pt 7 ps 0.6 title 'contact2d'";
  if (hertz)
    cmd << ", \\\n     (abs(x) < " << b->second << " ? " << p0->second << "*sqrt(1-(x/"
        << b->second << ")**2) : 0) with lines lw 2 dt 2 title 'Hertz'";
  cmd << "\n";
  const std::string err = plot_png_and_svg(dir, "pressure", cmd.str());
  std::filesystem::remove(data_path);
  return err;
}

std::string chart_deformed_mesh(const std::string& dir, const core::Model& model,
                                const core::Results& r) {
  const core::Mesh& mesh = model.mesh;
  const double umax = r.displacement.size() ? r.displacement.cwiseAbs().maxCoeff() : 0.0;
  const double scale = umax > 0 ? 0.08 * model.model_size / umax : 0.0;
  // One filled triangle per element (corner nodes) coloured by element-average von Mises.
  std::ostringstream data;
  data << std::setprecision(9);
  for (int e = 0; e < mesh.num_elements(); ++e) {
    double vm = 0;
    for (int i = 0; i < 3; ++i) vm += core::nodal_quantity(model, r, "vm", mesh.elements[e][i]) / 3;
    for (int k = 0; k <= 3; ++k) {
      const int n = mesh.elements[e][k % 3];
      const c2d::Vec2 p = mesh.nodes[n] + scale * r.displacement.segment<2>(2 * n);
      data << p.x() << ' ' << p.y() << ' ' << vm << '\n';
    }
    data << "\n";
  }
  std::ostringstream outline;
  outline << std::setprecision(9);
  for (const auto& be : mesh.boundary_edges)
    outline << mesh.nodes[be.nodes[0]].x() << ' ' << mesh.nodes[be.nodes[0]].y() << '\n'
            << mesh.nodes[be.nodes[1]].x() << ' ' << mesh.nodes[be.nodes[1]].y() << "\n\n";
  const std::string data_path = dir + "/deformed.dat", outline_path = dir + "/outline.dat";
  core::write_file_atomic(data_path, data.str());
  core::write_file_atomic(outline_path, outline.str());
  std::ostringstream scale_text;
  scale_text << std::setprecision(3) << scale;
  const std::string commands =
      "set size ratio -1\nset title 'Deformed mesh (displacements x " + scale_text.str() +
      "), coloured by von Mises (smoothed)'\n"
      "set palette rgb 33,13,10\nset cbrange [*:*]\nunset key\n"
      "plot " + gp_file(data_path) + " using 1:2:3 with filledcurves closed fc palette z lw 0.3, \\\n"
      "     " + gp_file(outline_path) + " using 1:2 with lines lc rgb '#555555' dt 2\n";
  const std::string err = plot_png_and_svg(dir, "deformed", commands);
  std::filesystem::remove(data_path);
  std::filesystem::remove(outline_path);
  return err;
}

}  // namespace c2d::app
