#include "app/report/vtu_reader.hpp"

#include <cstdint>
#include <cstdlib>
#include <cstring>
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

/// The raw appended block of a VTU file (contact2d writes UInt64 headers; VTK's default is
/// UInt32), from which appended arrays are decoded.
struct Appended {
  const std::string* text = nullptr;
  size_t base = std::string::npos;  ///< first byte after '_'
  size_t header = 8;

  template <typename T>
  static void decode(const char* p, size_t n, std::vector<double>& out) {
    for (size_t i = 0; i < n; ++i) {
      T v;
      std::memcpy(&v, p + i * sizeof(T), sizeof(T));
      out.push_back(static_cast<double>(v));
    }
  }

  std::vector<double> read(const std::string& path, const std::string& name,
                           const std::string& type, size_t offset) const {
    const std::string where = path + ": DataArray '" + name + "'";
    if (base == std::string::npos)
      throw InputError(where + ": expected an <AppendedData encoding=\"raw\"> block, found none");
    std::uint64_t bytes = 0;
    if (offset > text->size() || text->size() - offset < base + header)
      throw InputError(where + ": offset " + std::to_string(offset) + " lies beyond the file");
    std::memcpy(&bytes, text->data() + base + offset, header);  // little-endian host
    if (header == 4) bytes &= 0xffffffffULL;
    const size_t start = base + offset + header;
    if (bytes > text->size() - start)
      throw InputError(where + ": expected " + std::to_string(bytes) + " bytes, found " +
                       std::to_string(text->size() - start));
    const char* p = text->data() + start;
    std::vector<double> values;
    if (type == "Float64") decode<double>(p, bytes / 8, values);
    else if (type == "Float32") decode<float>(p, bytes / 4, values);
    else if (type == "Int64") decode<std::int64_t>(p, bytes / 8, values);
    else if (type == "Int32") decode<std::int32_t>(p, bytes / 4, values);
    else if (type == "UInt8") decode<std::uint8_t>(p, bytes, values);
    else
      throw InputError(where + ": expected type Float64, Float32, Int64, Int32 or UInt8, found '" +
                       type + "'");
    return values;
  }
};

/// The raw appended block, if the file has one; refuses other encodings and byte orders.
Appended find_appended(const std::string& path, const std::string& text, size_t appended_at) {
  Appended a;
  a.text = &text;
  const std::string file_tag = text.substr(0, text.find('>', text.find("<VTKFile")));
  const std::string header_type = attribute(file_tag, "header_type");
  if (header_type == "UInt32" || header_type.empty()) a.header = 4;
  if (appended_at == std::string::npos) return a;
  if (attribute(file_tag, "byte_order") != "LittleEndian")
    throw InputError(path + ": expected byte_order=\"LittleEndian\", found '" +
                     attribute(file_tag, "byte_order") + "'");
  const std::string tag = text.substr(appended_at, text.find('>', appended_at) - appended_at);
  if (attribute(tag, "encoding") != "raw")
    throw InputError(path + ": AppendedData: expected encoding=\"raw\", found '" +
                     attribute(tag, "encoding") + "'");
  const size_t underscore = text.find('_', appended_at);
  if (underscore != std::string::npos) a.base = underscore + 1;
  return a;
}

}  // namespace

VtuData read_vtu(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
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
  const size_t appended_at = text.find("<AppendedData");
  const Appended appended = find_appended(path, text, appended_at);
  const auto cell_data_at = text.find("<CellData");
  std::map<std::string, std::vector<double>> arrays;
  for (size_t pos = text.find("<DataArray"); pos < appended_at && pos != std::string::npos;
       pos = text.find("<DataArray", pos + 1)) {
    const auto tag_end = text.find('>', pos);
    if (tag_end == std::string::npos) throw InputError(path + ": a <DataArray> is not closed");
    const std::string tag = text.substr(pos, tag_end - pos);
    const std::string name = attribute(tag, "Name"), format = attribute(tag, "format");
    std::vector<double> values;
    if (format == "appended") {
      values = appended.read(path, name, attribute(tag, "type"),
                             std::strtoull(attribute(tag, "offset").c_str(), nullptr, 10));
    } else if (format == "ascii") {
      const auto end = text.find("</DataArray>", tag_end);
      if (end == std::string::npos) throw InputError(path + ": a <DataArray> is not closed");
      std::istringstream body(text.substr(tag_end + 1, end - tag_end - 1));
      for (double x; body >> x;) values.push_back(x);
    } else {
      throw InputError(path + ": DataArray '" + name +
                       "': expected format=\"ascii\" or \"appended\", found '" + format + "'");
    }
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
