#include "app/report/field_plot.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

#include "app/report/gnuplot.hpp"
#include "app/report/units.hpp"
#include "core/errors.hpp"
#include "core/writers.hpp"

namespace c2d::app {

namespace {

/// The sub-triangles drawn for a cell: the triangle itself (T3) or its four (T6).
std::vector<std::array<int, 3>> sub_triangles(const VtuData& v, int c) {
  const auto& n = v.cells[c];
  if (v.order == 1) return {{n[0], n[1], n[2]}};
  return {{n[0], n[3], n[5]}, {n[3], n[1], n[4]}, {n[5], n[4], n[2]}, {n[3], n[4], n[5]}};
}

bool overlaps(const std::array<Vec2, 3>& x, const std::optional<std::array<double, 4>>& zoom) {
  if (!zoom) return true;
  const auto& z = *zoom;
  const double x0 = std::min({x[0].x(), x[1].x(), x[2].x()}),
               x1 = std::max({x[0].x(), x[1].x(), x[2].x()});
  const double y0 = std::min({x[0].y(), x[1].y(), x[2].y()}),
               y1 = std::max({x[0].y(), x[1].y(), x[2].y()});
  return x1 >= z[0] && x0 <= z[2] && y1 >= z[1] && y0 <= z[3];
}

bool inside(const Vec2& p, const std::optional<std::array<double, 4>>& zoom) {
  if (!zoom) return true;
  const auto& z = *zoom;
  return p.x() >= z[0] && p.x() <= z[2] && p.y() >= z[1] && p.y() <= z[3];
}

struct FieldDef {
  std::string name, label, array;
  int component;  ///< -1: a scalar array
  bool cell;
};

const std::vector<FieldDef>& field_defs() {
  static const std::vector<FieldDef> defs = {
      {"sx", "sigma_x (smoothed)", "stress_smoothed", 0, false},
      {"sy", "sigma_y (smoothed)", "stress_smoothed", 1, false},
      {"sxy", "tau_xy (smoothed)", "stress_smoothed", 2, false},
      {"vm", "von Mises (smoothed)", "von_mises_smoothed", -1, false},
      {"p1", "major principal stress (smoothed)", "s1_smoothed", -1, false},
      {"p2", "minor principal stress (smoothed)", "s2_smoothed", -1, false},
      {"ux", "displacement u_x", "displacement", 0, false},
      {"uy", "displacement u_y", "displacement", 1, false},
      {"error", "ZZ local parameter ξ_e", "zz_local_parameter", -1, true},
  };
  return defs;
}

/// The unit of a field's values: a length for displacements, else a stress ("" for the error
/// map, or when the scene names none).
std::string field_unit(const PlotOptions& o, const FieldDef& def) {
  if (def.cell) return "";
  const Units u = parse_units(o.units);
  return def.array == "displacement" ? u.length : u.stress;
}

/// Axis and colour-bar labels with the scene's units (none without units).
std::string axis_commands(const PlotOptions& o, const FieldDef& def) {
  if (o.units.empty()) return "";
  const Units u = parse_units(o.units);
  std::string out = "set xlabel " + gp_text(axis_label("x", u.length)) + "\nset ylabel " +
                    gp_text(axis_label("y", u.length)) + "\n";
  // (gnuplot places the colour bar's label over tick labels of three digits or more.)
  if (!def.cell)
    out += "set cblabel " + gp_text(axis_label(def.name, field_unit(o, def))) + " offset 2,0\n";
  return out;
}

std::string window_commands(const std::optional<std::array<double, 4>>& zoom) {
  std::ostringstream os;
  os << std::setprecision(10) << "set size ratio -1\n";
  if (zoom)
    os << "set xrange [" << (*zoom)[0] << ":" << (*zoom)[2] << "]\nset yrange [" << (*zoom)[1]
       << ":" << (*zoom)[3] << "]\n";
  return os.str();
}

/// Corner-to-corner element edges (through the mid-side node for T6) as gnuplot line blocks.
void write_edges(std::ostream& os, const VtuData& v, const std::vector<Vec2>& x,
                 const std::optional<std::array<double, 4>>& zoom) {
  for (size_t c = 0; c < v.cells.size(); ++c) {
    const auto& n = v.cells[c];
    if (!overlaps({x[n[0]], x[n[1]], x[n[2]]}, zoom)) continue;
    const std::vector<int> loop = v.order == 1
                                      ? std::vector<int>{n[0], n[1], n[2], n[0]}
                                      : std::vector<int>{n[0], n[3], n[1], n[4], n[2], n[5], n[0]};
    for (int i : loop) os << x[i].x() << ' ' << x[i].y() << '\n';
    os << '\n';
  }
}

}  // namespace

std::string plot_field_list() {
  std::string list;
  for (const auto& n : plot_fields()) list += (list.empty() ? "" : "|") + n;
  return list;
}

const std::vector<std::string>& plot_fields() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (const auto& d : field_defs()) n.push_back(d.name);
    return n;
  }();
  return names;
}

std::vector<Vec2> clip_band(const std::array<Vec2, 3>& x, const std::array<double, 3>& v, double lo,
                            double hi) {
  // Sutherland-Hodgman in value space: keep v >= lo, then v <= hi (v is linear, so each clip
  // keeps one convex polygon and the new vertices interpolate v exactly).
  std::vector<std::pair<Vec2, double>> poly = {{x[0], v[0]}, {x[1], v[1]}, {x[2], v[2]}};
  auto clip = [&poly](double level, bool keep_above) {
    std::vector<std::pair<Vec2, double>> out;
    const size_t n = poly.size();
    for (size_t i = 0; i < n; ++i) {
      const auto& a = poly[i];
      const auto& b = poly[(i + 1) % n];
      const bool in_a = keep_above ? a.second >= level : a.second <= level;
      const bool in_b = keep_above ? b.second >= level : b.second <= level;
      if (in_a) out.push_back(a);
      if (in_a != in_b) {
        const double t = (level - a.second) / (b.second - a.second);
        out.push_back({a.first + t * (b.first - a.first), level});
      }
    }
    poly = std::move(out);
  };
  clip(lo, true);
  if (poly.size() >= 3) clip(hi, false);
  std::vector<Vec2> result;
  if (poly.size() >= 3)
    for (const auto& p : poly) result.push_back(p.first);
  return result;
}

double nice_step(double raw) {
  const double decade = std::pow(10.0, std::floor(std::log10(raw)));
  for (const double m : {1.0, 2.0, 2.5, 5.0})
    if (m * decade >= raw * (1 - 1e-9)) return m * decade;
  return 10 * decade;
}

ColourScale colour_scale(double lo, double hi, int levels) {
  ColourScale c;
  // Ticks at multiples of the step; the first step with at most 10 intervals over the range.
  for (double tick = nice_step((hi - lo) / 10);; tick = nice_step(tick * 1.01)) {
    c.lo = tick * std::floor(lo / tick + 1e-9), c.hi = tick * std::ceil(hi / tick - 1e-9);
    c.tick = tick;
    if (std::lround((c.hi - c.lo) / tick) <= 10) break;
  }
  const int intervals = std::max(1, static_cast<int>(std::lround((c.hi - c.lo) / c.tick)));
  // 1, 2 or 5 bands per tick interval (bands of round width too), the count nearest `levels`.
  int per_tick = 1;
  for (const int d : {2, 5})
    if (std::abs(intervals * d - levels) < std::abs(intervals * per_tick - levels)) per_tick = d;
  c.band = c.tick / per_tick;
  c.bands = intervals * per_tick;
  return c;
}

double displacement_scale(double umax, double size, bool finite_strain) {
  if (finite_strain) return 1.0;
  if (!(umax > 0)) return 0.0;
  const double raw = 0.08 * size / umax;
  if (raw <= 1) return 1.0;
  const double decade = std::pow(10.0, std::floor(std::log10(raw)));
  for (const double m : {5.0, 2.0, 1.0})
    if (m * decade <= raw * (1 + 1e-9)) return m * decade;
  return decade;
}

std::string deformation_text(double scale) {
  return scale == 1.0 ? "true scale" : "displacements ×" + rounded_text(scale);
}

namespace {

/// One field of a VTU: its definition and values, per point (per cell for the error map).
struct FieldValues {
  const FieldDef* def = nullptr;
  const std::vector<double>* values = nullptr;
  int components = 1;
  double operator()(int i) const {
    return (*values)[static_cast<size_t>(components) * i + std::max(def->component, 0)];
  }
};

/// The field named by `field`; throws InputError for an unknown field or a missing or
/// mis-sized array.
FieldValues field_values(const VtuData& vtu, const std::string& field) {
  const auto def = std::find_if(field_defs().begin(), field_defs().end(),
                                [&](const FieldDef& d) { return d.name == field; });
  if (def == field_defs().end())
    throw InputError("--field: expected " + plot_field_list() + ", found '" + field + "'");
  const auto& source = def->cell ? vtu.cell_data : vtu.point_data;
  const auto arr = source.find(def->array);
  if (arr == source.end())
    throw InputError(vtu.path + ": field " + field + " needs the array '" + def->array +
                     "', which the file does not have");
  const int comps = vtu.components.at(def->array);
  const int count =
      def->cell ? static_cast<int>(vtu.cells.size()) : static_cast<int>(vtu.points.size());
  if (comps < 1 || arr->second.size() != static_cast<size_t>(comps) * count)
    throw InputError(vtu.path + ": array '" + def->array + "': expected " +
                     std::to_string(static_cast<size_t>(std::max(comps, 1)) * count) +
                     " values for " + std::to_string(count) + (def->cell ? " cells" : " points") +
                     ", found " + std::to_string(arr->second.size()));
  if (def->component >= comps)
    throw InputError(vtu.path + ": array '" + def->array + "': field " + field +
                     " needs component " + std::to_string(def->component + 1) + ", found " +
                     std::to_string(comps) + " component(s)");
  return {&*def, &arr->second, comps};
}

/// Positions drawn: the reference ones, or deformed by the displacement times `scale` (< 0:
/// displacement_scale over the model's diagonal; set to the scale used).
std::vector<Vec2> drawn_positions(const VtuData& vtu, double& scale) {
  std::vector<Vec2> x = vtu.points;
  const auto disp = vtu.point_data.find("displacement");
  if (scale == 0.0 || disp == vtu.point_data.end()) return x;
  const auto comps = vtu.components.find("displacement");
  const size_t n = comps == vtu.components.end() ? 0 : static_cast<size_t>(comps->second);
  if (n < 2 || disp->second.size() != n * x.size())
    throw InputError(vtu.path + ": array 'displacement': expected 2 or 3 components for each of " +
                     std::to_string(x.size()) + " points, found " +
                     std::to_string(disp->second.size()) + " values of " + std::to_string(n) +
                     " component(s)");
  const auto u = [&](size_t i, size_t c) { return disp->second[n * i + c]; };
  if (scale < 0) {
    double umax = 0.0, lo_x = 1e300, hi_x = -1e300, lo_y = 1e300, hi_y = -1e300;
    for (size_t i = 0; i < vtu.points.size(); ++i) {
      umax = std::max({umax, std::abs(u(i, 0)), std::abs(u(i, 1))});
      lo_x = std::min(lo_x, x[i].x()), hi_x = std::max(hi_x, x[i].x());
      lo_y = std::min(lo_y, x[i].y()), hi_y = std::max(hi_y, x[i].y());
    }
    scale = displacement_scale(umax, std::hypot(hi_x - lo_x, hi_y - lo_y), false);
  }
  for (size_t i = 0; i < x.size(); ++i) x[i] += scale * Vec2(u(i, 0), u(i, 1));
  return x;
}

/// A picture's title around the values it shows: "HEAD: <values>TAIL".
struct Title {
  std::string head, tail;
};

/// The seed's map: elements with ξ_e <= 1 (the error there meets the target) and > 1.
void draw_error_map(const VtuData& vtu, const std::vector<Vec2>& x, const FieldValues& value,
                    const PlotOptions& o, const Title& title, std::ostream& data, std::ostream& cmd,
                    PlotSummary& sum) {
  sum.min = 1e300, sum.max = -1e300;
  for (size_t c = 0; c < vtu.cells.size(); ++c) {
    const auto& n = vtu.cells[c];
    if (!overlaps({x[n[0]], x[n[1]], x[n[2]]}, o.zoom)) continue;
    const double xi = value(static_cast<int>(c));
    ++sum.elements;
    sum.above_one += xi > 1.0;
    sum.min = std::min(sum.min, xi), sum.max = std::max(sum.max, xi);
    for (const auto& t : sub_triangles(vtu, static_cast<int>(c))) {
      for (int k = 0; k <= 3; ++k)
        data << x[t[k % 3]].x() << ' ' << x[t[k % 3]].y() << ' ' << (xi > 1 ? 1.5 : 0.5) << '\n';
      data << '\n';
    }
  }
  cmd << "set title "
      << gp_text(title.head + ": " + std::to_string(sum.above_one) + " of " +
                 std::to_string(sum.elements) + " elements above 1 (max " + rounded_text(sum.max) +
                 ")" + title.tail)
      << "\nset cbrange [0:2]\n"
      // Two classes, not a scale: light blue and red tell apart for every colour vision.
      << "set palette defined (0 '#9ecae1', 1 '#9ecae1', 1 '#de2d26', 2 '#de2d26')\n"
      << "set cbtics ('ξ_e ≤ 1' 0.5, 'ξ_e > 1' 1.5)\n";
}

/// Filled contours: colour range over the nodes in view, isobands between uniform levels.
void draw_isobands(const VtuData& vtu, const std::vector<Vec2>& x, const FieldValues& value,
                   const PlotOptions& o, const Title& title, std::ostream& data, std::ostream& cmd,
                   PlotSummary& sum) {
  double lo = 1e300, hi = -1e300;
  for (size_t c = 0; c < vtu.cells.size(); ++c)
    for (const auto& t : sub_triangles(vtu, static_cast<int>(c)))
      for (int i : t)
        if (inside(x[i], o.zoom)) lo = std::min(lo, value(i)), hi = std::max(hi, value(i));
  if (lo > hi) {  // no node inside the window: the range of everything drawn
    for (int i = 0; i < static_cast<int>(x.size()); ++i)
      lo = std::min(lo, value(i)), hi = std::max(hi, value(i));
  }
  sum.min = lo, sum.max = hi;
  if (hi - lo <= 1e-12 * std::max(std::abs(hi), std::abs(lo))) {
    lo -= 0.5 * std::max(std::abs(lo), 1e-30);
    hi += 0.5 * std::max(std::abs(hi), 1e-30);
  }
  const ColourScale scale = colour_scale(lo, hi, std::max(2, o.levels));
  const int levels = scale.bands;
  lo = scale.lo;
  const double step = scale.band;
  auto band_of = [&](double v) {
    // Values outside the range (nodes beyond the window) fall into the end bands.
    return std::clamp(static_cast<int>(std::floor((v - lo) / step)), 0, levels - 1);
  };
  auto write_polygon = [&](const std::vector<Vec2>& poly, int k) {
    for (size_t i = 0; i <= poly.size(); ++i)
      data << poly[i % poly.size()].x() << ' ' << poly[i % poly.size()].y() << ' '
           << lo + (k + 0.5) * step << '\n';
    data << '\n';
  };
  for (size_t c = 0; c < vtu.cells.size(); ++c) {
    // A cell within one band is one polygon, its outline (a quadratic cell's six nodes), not a
    // polygon per sub-triangle: a fine mesh's chart draws and files a quarter of the shapes.
    const auto& n = vtu.cells[c];
    if (vtu.order == 2 && n.size() == 6) {
      std::array<Vec2, 3> corners = {x[n[0]], x[n[1]], x[n[2]]};
      int k = band_of(value(n[0]));
      bool one_band = overlaps(corners, o.zoom);
      for (int i = 1; i < 6 && one_band; ++i) one_band = band_of(value(n[i])) == k;
      if (one_band) {
        write_polygon({x[n[0]], x[n[3]], x[n[1]], x[n[4]], x[n[2]], x[n[5]]}, k);
        continue;
      }
    }
    for (const auto& t : sub_triangles(vtu, static_cast<int>(c))) {
      const std::array<Vec2, 3> p = {x[t[0]], x[t[1]], x[t[2]]};
      if (!overlaps(p, o.zoom)) continue;
      const std::array<double, 3> v = {value(t[0]), value(t[1]), value(t[2])};
      const int k0 = band_of(std::min({v[0], v[1], v[2]}));
      const int k1 = band_of(std::max({v[0], v[1], v[2]}));
      for (int k = k0; k <= k1; ++k) {
        const double b0 = k == 0 ? -1e300 : lo + k * step,
                     b1 = k == levels - 1 ? 1e300 : lo + (k + 1) * step;
        const auto poly = clip_band(p, v, b0, b1);
        if (!poly.empty()) write_polygon(poly, k);
      }
    }
  }
  const std::string unit = field_unit(o, *value.def);
  cmd << "set title "
      << gp_text(title.head + ": " + rounded_text(sum.min) + " to " + quantity_text(sum.max, unit) +
                 title.tail)
      << "\nset cbrange [" << scale.lo << ":" << scale.hi << "]\n"
      << gp_palette(levels) << "set cbtics " << scale.lo << ", " << scale.tick
      << "\nset format cb '%g'\n";
}

}  // namespace

PlotSummary plot_field(const VtuData& vtu, const PlotOptions& o, const std::string& dir,
                       const std::string& stem) {
  const FieldValues value = field_values(vtu, o.field);
  double scale = o.deformed;
  const std::vector<Vec2> x = drawn_positions(vtu, scale);
  PlotSummary sum;
  std::ostringstream data, cmd;
  data << std::setprecision(9);
  cmd << std::setprecision(6);
  Title title{o.title.empty() ? value.def->label : o.title, ""};
  if (scale != 0.0) title.tail += ", " + deformation_text(scale);
  if (!o.note.empty()) title.tail += "; " + o.note;
  if (value.def->cell)
    draw_error_map(vtu, x, value, o, title, data, cmd, sum);
  else
    draw_isobands(vtu, x, value, o, title, data, cmd, sum);
  const std::string data_path = dir + "/" + stem + ".dat",
                    edges_path = dir + "/" + stem + "_edges.dat";
  std::vector<PlotData> files{{data_path, data.str()}};
  // (set clip two: an overlay segment with both ends outside the window still crosses it.)
  cmd << window_commands(o.zoom) << axis_commands(o, *value.def)
      << "unset key\nset clip two\nset style fill solid 1.0 noborder\n"
      << "plot " << gp_file(data_path) << " using 1:2:3 with filledcurves closed fc palette z";
  if (!o.overlay.empty()) {
    const std::string overlay_path = dir + "/" + stem + "_overlay.dat";
    std::ostringstream lines;
    lines << std::setprecision(12);
    for (const auto& line : o.overlay) {
      for (const Vec2& p : line) lines << p.x() << ' ' << p.y() << '\n';
      lines << '\n';
    }
    files.push_back({overlay_path, lines.str()});
    cmd << ", \\\n     " << gp_file(overlay_path) << " using 1:2 with lines lc rgb 'black' lw 2.5";
  }
  if (o.edges) {
    std::ostringstream edges;
    edges << std::setprecision(9);
    write_edges(edges, vtu, x, o.zoom);
    files.push_back({edges_path, edges.str()});
    cmd << ", \\\n     " << gp_file(edges_path) << " using 1:2 with lines lc rgb '#303030' lw 0.4";
  }
  cmd << "\n";
  sum.error = plot_with_data(dir, stem, cmd.str(), files);
  return sum;
}

std::string plot_mesh_comparison(const std::vector<std::pair<std::string, VtuData>>& meshes,
                                 const std::optional<std::array<double, 4>>& zoom,
                                 const std::string& dir, const std::string& stem) {
  std::ostringstream cmd;
  std::vector<PlotData> files;
  const int n = static_cast<int>(meshes.size());
  cmd << "set multiplot layout " << (n <= 2 ? 1 : 2) << "," << (n <= 2 ? n : 2)
      << " title 'Adaptive cycles: element edges" << (zoom ? " (zoom)" : "") << "'\n"
      << window_commands(zoom) << "unset key\n";
  for (int i = 0; i < n; ++i) {
    const std::string path = dir + "/" + stem + "_" + std::to_string(i) + ".dat";
    std::ostringstream edges;
    edges << std::setprecision(9);
    write_edges(edges, meshes[i].second, meshes[i].second.points, zoom);
    files.push_back({path, edges.str()});
    cmd << "set title " << gp_text(meshes[i].first) << "\nplot " << gp_file(path)
        << " using 1:2 with lines lc rgb '#1f4e79' lw 0.5\n";
  }
  cmd << "unset multiplot\n";
  return plot_with_data(dir, stem, cmd.str(), files);
}

}  // namespace c2d::app
