#include "app/charts.hpp"

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
  std::ostringstream gp;
  std::ostringstream scale_text;
  scale_text << std::setprecision(3) << scale;
  for (const char* term : {"png", "svg"}) {
    if (std::string(term) == "png")
      gp << "set terminal pngcairo size 1200,800 font 'Sans,11'\n";
    else
      gp << "set terminal svg size 1200,800 font 'Sans,11'\n";
    gp << "set output '" << dir << "/deformed." << term << "'\n"
       << "set size ratio -1\nset title 'Deformed mesh (displacements x " << scale_text.str()
       << "), coloured by von Mises (smoothed)'\n"
       << "set palette rgb 33,13,10\nset cbrange [*:*]\nunset key\n"
       << "plot '" << data_path << "' using 1:2:3 with filledcurves closed fc palette z lw 0.3, \\\n"
       << "     '" << outline_path << "' using 1:2 with lines lc rgb '#555555' dt 2\n"
       << "unset output\n";
  }
  const std::string script = dir + "/deformed.gp";
  core::write_file_atomic(script, gp.str());
  std::string err = run_gnuplot(script);
  std::filesystem::remove(data_path);
  std::filesystem::remove(outline_path);
  if (err.empty()) std::filesystem::remove(script);
  return err;
}

}  // namespace c2d::app
