#include "app/report/vtu_reader.hpp"

#include <fstream>
#include <regex>
#include <sstream>

#include "core/errors.hpp"

namespace c2d::app {

namespace {

std::string attribute(const std::string& tag, const std::string& name) {
  const std::regex re(name + "=\"([^\"]*)\"");
  std::smatch m;
  return std::regex_search(tag, m, re) ? m[1].str() : std::string();
}

}  // namespace

VtuData read_vtu(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot read (expected a VTU file written by contact2d run)");
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string text = ss.str();
  VtuData v;
  v.path = path;
  const auto piece = text.find("<Piece");
  if (piece == std::string::npos)
    throw InputError(path + ": expected a VTK UnstructuredGrid <Piece>, found none");
  const std::string piece_tag = text.substr(piece, text.find('>', piece) - piece);
  const int num_points = std::atoi(attribute(piece_tag, "NumberOfPoints").c_str());
  const int num_cells = std::atoi(attribute(piece_tag, "NumberOfCells").c_str());
  const auto cell_data_at = text.find("<CellData");
  std::map<std::string, std::vector<double>> arrays;
  for (size_t pos = text.find("<DataArray"); pos != std::string::npos;
       pos = text.find("<DataArray", pos + 1)) {
    const auto tag_end = text.find('>', pos);
    const auto end = text.find("</DataArray>", tag_end);
    if (tag_end == std::string::npos || end == std::string::npos)
      throw InputError(path + ": a <DataArray> is not closed");
    const std::string tag = text.substr(pos, tag_end - pos);
    const std::string name = attribute(tag, "Name");
    if (attribute(tag, "format") != "ascii")
      throw InputError(path + ": DataArray '" + name + "': expected format=\"ascii\", found '" +
                       attribute(tag, "format") + "'");
    std::istringstream body(text.substr(tag_end + 1, end - tag_end - 1));
    std::vector<double> values;
    for (double x; body >> x;) values.push_back(x);
    const std::string comps = attribute(tag, "NumberOfComponents");
    v.components[name] = comps.empty() ? 1 : std::atoi(comps.c_str());
    const bool cell = cell_data_at != std::string::npos && pos > cell_data_at;
    (cell ? v.cell_data : v.point_data)[name] = values;
    arrays[name] = std::move(values);
  }
  for (const char* need : {"Points", "connectivity", "types"})
    if (!arrays.count(need))
      throw InputError(path + ": expected a DataArray named '" + need + "', found none");
  const auto& pts = arrays["Points"];
  if (static_cast<int>(pts.size()) != 3 * num_points)
    throw InputError(path + ": Points: expected " + std::to_string(3 * num_points) +
                     " values, found " + std::to_string(pts.size()));
  for (int i = 0; i < num_points; ++i) v.points.emplace_back(pts[3 * i], pts[3 * i + 1]);
  const auto& types = arrays["types"];
  if (static_cast<int>(types.size()) != num_cells || num_cells == 0)
    throw InputError(path + ": types: expected " + std::to_string(num_cells) + " cells, found " +
                     std::to_string(types.size()));
  const int type = static_cast<int>(types[0]);
  if (type != 5 && type != 22)
    throw InputError(path + ": expected triangles (VTK type 5 or 22), found type " +
                     std::to_string(type));
  v.order = type == 5 ? 1 : 2;
  const int nn = type == 5 ? 3 : 6;
  const auto& conn = arrays["connectivity"];
  if (static_cast<int>(conn.size()) != nn * num_cells)
    throw InputError(path + ": connectivity: expected " + std::to_string(nn * num_cells) +
                     " node ids, found " + std::to_string(conn.size()));
  v.cells.resize(num_cells);
  for (int c = 0; c < num_cells; ++c)
    for (int i = 0; i < nn; ++i) {
      const int id = static_cast<int>(conn[nn * c + i]);
      if (id < 0 || id >= num_points)
        throw InputError(path + ": connectivity: node " + std::to_string(id) + " of cell " +
                         std::to_string(c) + " is out of range");
      v.cells[c][i] = id;
    }
  return v;
}

}  // namespace c2d::app
