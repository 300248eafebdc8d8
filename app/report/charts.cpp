#include "app/report/charts.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <filesystem>
#include <iomanip>
#include <optional>
#include <sstream>

#include <Eigen/Geometry>

#include "app/report/field_plot.hpp"
#include "app/report/gnuplot.hpp"
#include "app/report/hertz.hpp"
#include "app/report/pressure_profile.hpp"
#include "app/report/units.hpp"
#include "core/probes.hpp"
#include "core/writers.hpp"

namespace c2d::app {

std::string chart_contact_pressure(const std::string& dir, const constraints::ContactReport& c,
                                   const core::Scene& scene) {
  // Abscissa: the reference coordinate along which the slave nodes spread most.
  const Units units = parse_units(scene.units);
  std::vector<Vec2> positions;
  for (const auto& n : c.nodes) positions.push_back(n.x);
  const int axis = spread_axis(positions);
  // Position, pressure and (with friction) shear per slave node, sorted along the surface once
  // (two sorts of pairs could pair nodes at the same position crosswise).
  std::vector<std::array<double, 3>> pts;
  for (const auto& n : c.nodes) pts.push_back({n.x[axis], n.pressure, n.shear});
  std::sort(pts.begin(), pts.end());
  std::ostringstream data;
  data << std::setprecision(12);
  for (const auto& [x, p, q] : pts) data << x << ' ' << p << ' ' << q << '\n';
  const std::string data_path = dir + "/pressure.dat";
  std::ostringstream cmd;
  cmd << std::setprecision(10) << "set title "
      << gp_text((c.friction ? "Contact pressure and shear (" : "Contact pressure (") + c.method +
                 ", recovered from nodal forces)")
      << "\nset xlabel " << gp_text(axis_label(axis ? "y" : "x", units.length))
      << "\nset ylabel "
      << gp_text(axis_label(c.friction ? "pressure, shear" : "pressure", units.stress))
      << "\nset grid\nset key top left\n";
  std::optional<HertzReference> hertz = hertz_reference(scene);
  // A Cattaneo–Mindlin reference: Hertz's pressure and the shear of a partial slip.
  const auto cattaneo = cattaneo_reference(scene);
  if (cattaneo) hertz = cattaneo->hertz;
  // The analytic profile is centred on the origin; show the data within 1.6 half-widths.
  if (hertz) write_hertz_window(cmd, *hertz, pts.front()[0], pts.back()[0]);
  cmd << "plot " << gp_file(data_path)
      << " using 1:2 with linespoints pt 7 ps 0.6 title 'pressure'";
  if (c.friction)
    cmd << ", \\\n     '' using 1:3 with linespoints pt 5 ps 0.6 title 'shear (on the slave, along t)'";
  if (hertz) {
    cmd << ", \\\n     ";
    write_hertz_curve(cmd, *hertz);
    cmd << " with lines lw 2 dt 2 title 'Hertz'";
  }
  if (cattaneo && c.friction) {
    const double mu = cattaneo->mu, p0 = hertz->p0, b = hertz->b, cs = cattaneo->c,
                 sign = c.tangent_force < 0 ? -1.0 : 1.0;
    cmd << ", \\\n     " << sign << "*((abs(x) < " << b << " ? " << mu * p0 << "*sqrt(1-(x/" << b
        << ")**2) : 0) - (abs(x) < " << cs << " ? " << mu * p0 * cs / b << "*sqrt(1-(x/" << cs
        << ")**2) : 0)) with lines lw 2 dt 3 title 'Cattaneo-Mindlin'";
  }
  cmd << "\n";
  return plot_with_data(dir, "pressure", cmd.str(), {{data_path, data.str()}});
}

// A model much wider than tall drawn at equal scale left the plot a strip, too low for its
// colour bar's ticks (slender_floor, spring_chain: labels over each other).
std::string slender_window(const Eigen::AlignedBox2d& box) {
  if (box.isEmpty()) return "";
  const Vec2 size = box.sizes();
  constexpr double kLowest = 1.0 / 3.0;  // height / width of the plotted window, at least
  if (!(size.x() > 0) || size.y() >= kLowest * size.x()) return "";
  const double pad = 0.02 * size.x(), half = 0.5 * kLowest * (size.x() + 2 * pad);
  const double cy = box.center().y();
  std::ostringstream os;
  os << std::setprecision(10) << "set xrange [" << box.min().x() - pad << ":"
     << box.max().x() + pad << "]\nset yrange [" << cy - half << ":" << cy + half << "]\n";
  return os.str();
}

std::string chart_deformed_mesh(const std::string& dir, const core::Model& model,
                                const core::Results& r, const std::string& units,
                                bool finite_strain) {
  const core::Mesh& mesh = model.mesh;
  const double umax = r.displacement.size() ? r.displacement.cwiseAbs().maxCoeff() : 0.0;
  const double scale = displacement_scale(umax, model.model_size, finite_strain);
  // One filled triangle per element (corner nodes) coloured by element-average von Mises.
  std::ostringstream data;
  data << std::setprecision(9);
  Eigen::AlignedBox2d box;  // of the drawn points, deformed and undeformed
  for (int e = 0; e < mesh.num_elements(); ++e) {
    double vm = 0;
    for (int i = 0; i < 3; ++i) vm += core::nodal_quantity(model, r, "vm", mesh.elements[e][i]) / 3;
    for (int k = 0; k <= 3; ++k) {
      const int n = mesh.elements[e][k % 3];
      const c2d::Vec2 p = mesh.nodes[n] + scale * r.displacement.segment<2>(2 * n);
      box.extend(p);
      box.extend(mesh.nodes[n]);
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
  const Units u = parse_units(units);
  const std::string commands =
      "set size ratio -1\n" + slender_window(box) + "set title " +
      gp_text("Deformed mesh (" + deformation_text(scale) +
              (finite_strain ? ", finite strain" : "") + "), coloured by von Mises (smoothed)") +
      "\n" + gp_palette() + "set cbrange [*:*]\nset format cb '%g'\nunset key\nset xlabel " +
      gp_text(axis_label("x", u.length)) + "\nset ylabel " + gp_text(axis_label("y", u.length)) +
      "\nset cblabel " + gp_text(axis_label("von Mises", u.stress)) + " offset 2,0\nplot " +
      gp_file(data_path) + " using 1:2:3 with filledcurves closed fc palette z lw 0.3, \\\n     " +
      gp_file(outline_path) + " using 1:2 with lines lc rgb '#555555' dt 2\n";
  return plot_with_data(dir, "deformed", commands,
                        {{data_path, data.str()}, {outline_path, outline.str()}});
}

namespace {

/// An obstacle as a polyline around `center` (a line: a segment of ±4 half across it).
std::vector<Vec2> obstacle_line(const constraints::Obstacle& o, const Vec2& center, double half) {
  if (o.type == constraints::Obstacle::Type::kLine) {
    const Vec2 t(-o.normal.y(), o.normal.x());
    const Vec2 q = center - (center - o.point).dot(o.normal) * o.normal;
    return {q - 4 * half * t, q + 4 * half * t};
  }
  std::vector<Vec2> circle;
  for (int k = 0; k <= 720; ++k) {
    const double a = 2 * std::numbers::pi * k / 720;
    circle.push_back(o.center + o.radius * Vec2(std::cos(a), std::sin(a)));
  }
  return circle;
}

}  // namespace

std::string chart_contact_zone(const std::string& dir, const std::string& vtu_path,
                               const constraints::ContactReport& c,
                               const std::vector<constraints::Obstacle>& obstacles,
                               const std::vector<Vec2>& mesh_nodes, const core::Results& r,
                               const std::string& units) {
  Vec2 lo = Vec2::Constant(1e300), hi = Vec2::Constant(-1e300), sum = Vec2::Zero();
  int active = 0;
  for (const auto& n : c.nodes) {
    if (!n.active) continue;
    const Vec2 x = n.x + (r.displacement.size() > 2 * n.node + 1
                              ? Vec2(r.displacement.segment<2>(2 * n.node)) : Vec2::Zero());
    lo = lo.cwiseMin(x), hi = hi.cwiseMax(x), sum += x, ++active;
  }
  if (active == 0) return "";
  Vec2 center = sum / active;
  const double half = 1.5 * std::max({c.length, (hi - lo).maxCoeff(), 1e-12});
  // The window stays over the bodies where they are wider than it (a half model's symmetry
  // plane, the free side of a contact), with a tenth of it to spare for an obstacle's line.
  Vec2 body_lo = Vec2::Constant(1e300), body_hi = Vec2::Constant(-1e300);
  for (int k = 0; 2 * k + 1 < r.displacement.size() && k < static_cast<int>(mesh_nodes.size()); ++k) {
    const Vec2 x = mesh_nodes[k] + Vec2(r.displacement.segment<2>(2 * k));
    body_lo = body_lo.cwiseMin(x), body_hi = body_hi.cwiseMax(x);
  }
  for (int a = 0; a < 2; ++a) {
    const double lo_edge = body_lo[a] - 0.2 * half, hi_edge = body_hi[a] + 0.2 * half;
    if (hi_edge - lo_edge <= 2 * half) continue;
    center[a] = std::clamp(center[a], lo_edge + half, hi_edge - half);
  }
  PlotOptions o;
  o.field = "vm";
  o.zoom = std::array<double, 4>{center.x() - half, center.y() - half, center.x() + half,
                                 center.y() + half};
  o.deformed = 1.0;
  o.units = units;
  o.title = "Contact zone, von Mises (smoothed)";
  if (!obstacles.empty()) o.note = "rigid obstacles in black";
  for (const auto& ob : obstacles) o.overlay.push_back(obstacle_line(ob, center, half));
  try {
    return plot_field(read_vtu(vtu_path), o, dir, "contact_zone").error;
  } catch (const std::exception& e) {
    return std::string("contact zone: ") + e.what();
  }
}

}  // namespace c2d::app
