#include "app/charts.hpp"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "core/probes.hpp"
#include "core/writers.hpp"

#ifndef C2D_GNUPLOT
#define C2D_GNUPLOT "gnuplot"
#endif

namespace c2d::app {

std::string run_gnuplot(const std::string& script_path) {
  const std::string exe = std::filesystem::exists(C2D_GNUPLOT) ? C2D_GNUPLOT : "gnuplot";
  const std::string cmd = exe + " '" + script_path + "' > '" + script_path + ".log' 2>&1";
  const int rc = std::system(cmd.c_str());
  if (rc != 0) return "gnuplot failed (exit " + std::to_string(rc) + "), see " + script_path + ".log";
  std::filesystem::remove(script_path + ".log");
  return "";
}

std::string plot_png_and_svg(const std::string& dir, const std::string& stem,
                             const std::string& commands) {
  std::ostringstream gp;
  for (const char* term : {"png", "svg"}) {
    gp << (std::string(term) == "png" ? "set terminal pngcairo size 1200,800 font 'Sans,11'\n"
                                      : "set terminal svg size 1200,800 font 'Sans,11'\n")
       << "set output '" << dir << "/" << stem << "." << term << "'\n"
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
  cmd << std::setprecision(10) << "set title 'Contact pressure (" << c.method
      << ", recovered from nodal forces)'\nset xlabel '" << (axis ? "y" : "x")
      << "'\nset ylabel 'pressure'\nset grid\nset key top left\n";
  const auto p0 = scene.reference.find("p_max"), b = scene.reference.find("contact_length");
  const bool hertz = scene.reference_kind.rfind("hertz", 0) == 0 &&
                     p0 != scene.reference.end() && b != scene.reference.end();
  // The analytic profile is centred on the origin; show the data within 1.6 half-widths.
  if (hertz)
    cmd << "set xrange [" << std::max(pts.front().first, -1.6 * b->second) << ":"
        << std::min(pts.back().first, 1.6 * b->second) << "]\nset samples 400\n";
  cmd << "plot '" << data_path << "' using 1:2 with linespoints pt 7 ps 0.6 title 'contact2d'";
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
      "plot '" + data_path + "' using 1:2:3 with filledcurves closed fc palette z lw 0.3, \\\n"
      "     '" + outline_path + "' using 1:2 with lines lc rgb '#555555' dt 2\n";
  const std::string err = plot_png_and_svg(dir, "deformed", commands);
  std::filesystem::remove(data_path);
  std::filesystem::remove(outline_path);
  return err;
}

}  // namespace c2d::app
