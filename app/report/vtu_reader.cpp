#include "app/report/vtu_reader.hpp"

#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <sstream>

#include "app/report/json_file.hpp"
#include "core/errors.hpp"

namespace c2d::app {

namespace {

/// The value of the attribute `name` in an element's opening tag ("" when it has none). No
/// std::regex: libstdc++'s recurses once per character matched, and a long value overflowed it.
std::string attribute(const std::string& tag, const std::string& name) {
  const std::string key = name + "=\"";
  for (size_t at = tag.find(key); at != std::string::npos; at = tag.find(key, at + 1)) {
    if (at > 0 && !std::isspace(static_cast<unsigned char>(tag[at - 1]))) continue;
    const size_t begin = at + key.size(), end = tag.find('"', begin);
    return end == std::string::npos ? std::string() : tag.substr(begin, end - begin);
  }
  return "";
}

/// The attribute `name` of `tag` as a whole decimal integer from `lo` to `hi`; throws InputError
/// naming `where` and the attribute otherwise.
long long count_attribute(const std::string& where, const std::string& tag, const std::string& name,
                          long long lo, long long hi) {
  const std::string text = attribute(tag, name);
  long long n = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), n);
  if (text.empty() || ec != std::errc() || end != text.data() + text.size() || n < lo || n > hi)
    throw InputError(where + ": " + name + ": expected an integer from " + std::to_string(lo) +
                     " to " + std::to_string(hi) + ", found " + quoted_found(text));
  return n;
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

/// Where a DataArray sits in the <Piece>, which says how many tuples it holds.
enum class Section { kNone, kPoints, kCells, kPointData, kCellData };

/// The section of the array at `pos`: the last section tag opened before it.
struct SectionMap {
  size_t points, cells, point_data, cell_data;
  SectionMap(const std::string& text, size_t piece)
      : points(text.find("<Points", piece)),
        cells(text.find("<Cells", piece)),
        point_data(text.find("<PointData", piece)),
        cell_data(text.find("<CellData", piece)) {}
  Section at(size_t pos) const {
    Section s = Section::kNone;
    size_t from = 0;
    for (const auto& [start, section] :
         {std::pair{points, Section::kPoints}, std::pair{cells, Section::kCells},
          std::pair{point_data, Section::kPointData}, std::pair{cell_data, Section::kCellData}})
      if (start != std::string::npos && start < pos && start >= from) from = start, s = section;
    return s;
  }
};

/// One DataArray's values (ascii or appended) and its components.
struct ArrayRead {
  std::string name;
  std::vector<double> values;
  int components = 1;
};

ArrayRead read_array(const std::string& path, const std::string& text, const Appended& appended,
                     size_t pos, size_t tag_end) {
  const std::string tag = text.substr(pos, tag_end - pos);
  ArrayRead a;
  a.name = attribute(tag, "Name");
  const std::string where = path + ": DataArray " + quoted_found(a.name);
  if (!attribute(tag, "NumberOfComponents").empty())
    a.components = static_cast<int>(count_attribute(where, tag, "NumberOfComponents", 1, 9));
  const std::string format = attribute(tag, "format");
  if (format == "appended") {
    const auto offset =
        count_attribute(where, tag, "offset", 0, static_cast<long long>(text.size()));
    a.values = appended.read(path, a.name, attribute(tag, "type"), static_cast<size_t>(offset));
  } else if (format == "ascii") {
    const auto end = text.find("</DataArray>", tag_end);
    if (end == std::string::npos) throw InputError(where + ": the <DataArray> is not closed");
    std::istringstream body(text.substr(tag_end + 1, end - tag_end - 1));
    for (double x; body >> x;) a.values.push_back(x);
  } else {
    throw InputError(where + ": expected format=\"ascii\" or \"appended\", found " +
                     quoted_found(format));
  }
  return a;
}

/// Refuses an array whose values are not `tuples` x its components (`what`: "points", "cells").
void check_count(const std::string& path, const ArrayRead& a, long long tuples,
                 const std::string& what) {
  const auto expected = static_cast<unsigned long long>(tuples) * a.components;
  if (a.values.size() != expected)
    throw InputError(path + ": DataArray " + quoted_found(a.name) + ": expected " +
                     std::to_string(expected) + " values (" + std::to_string(tuples) + " " + what +
                     " x " + std::to_string(a.components) + " components), found " +
                     std::to_string(a.values.size()));
}

/// A value found in an array, for a message ("7", "1e+300", "nan").
std::string shown_number(double x) {
  std::ostringstream os;
  os << x;
  return os.str();
}

/// `x` as an integer from 0 to `hi`; throws naming the array and the entry otherwise.
int index_value(const std::string& path, const std::string& array, size_t entry, double x,
                long long hi) {
  if (!(x >= 0 && x <= static_cast<double>(hi) && x == std::floor(x)))
    throw InputError(path + ": DataArray '" + array + "': entry " + std::to_string(entry) +
                     ": expected an integer from 0 to " + std::to_string(hi) + ", found " +
                     shown_number(x));
  return static_cast<int>(x);
}

/// The cells from the <Cells> arrays: one triangle type throughout, offsets that step by its node
/// count, node ids within the points.
void read_cells(const std::string& path, std::map<std::string, ArrayRead>& cells, long long points,
                long long num_cells, VtuData& v) {
  const ArrayRead& types = cells["types"];
  check_count(path, types, num_cells, "cells");
  const int type = index_value(path, "types", 0, types.values[0], 255);
  if (type != 5 && type != 22)
    throw InputError(path + ": expected triangles (VTK type 5 or 22), found type " +
                     std::to_string(type));
  for (size_t c = 1; c < types.values.size(); ++c)
    if (types.values[c] != type)
      throw InputError(path + ": DataArray 'types': entry " + std::to_string(c) + ": expected " +
                       std::to_string(type) + " (one cell type), found " +
                       shown_number(types.values[c]));
  v.order = type == 5 ? 1 : 2;
  const int nn = type == 5 ? 3 : 6;
  const ArrayRead& conn = cells["connectivity"];
  check_count(path, conn, nn * num_cells, "node ids");
  if (cells.count("offsets")) {
    const ArrayRead& offsets = cells["offsets"];
    check_count(path, offsets, num_cells, "cells");
    for (size_t c = 0; c < offsets.values.size(); ++c)
      if (offsets.values[c] != static_cast<double>(nn * (c + 1)))
        throw InputError(path + ": DataArray 'offsets': entry " + std::to_string(c) +
                         ": expected " + std::to_string(nn * (c + 1)) + " (" + std::to_string(nn) +
                         " node ids per cell, within the connectivity), found " +
                         shown_number(offsets.values[c]));
  }
  v.cells.resize(static_cast<size_t>(num_cells));
  for (size_t c = 0; c < v.cells.size(); ++c)
    for (int i = 0; i < nn; ++i)
      v.cells[c][i] =
          index_value(path, "connectivity", nn * c + i, conn.values[nn * c + i], points - 1);
}

}  // namespace

VtuData read_vtu(const std::string& path) {
  std::string error;
  const std::string text = read_regular_file(path, std::size_t{1} << 34, error);
  if (!error.empty())
    throw InputError(path + ": " + error + " (expected a VTU file written by contact2d run)");
  VtuData v;
  v.path = path;
  const auto piece = text.find("<Piece");
  if (piece == std::string::npos)
    throw InputError(path + ": expected a VTK UnstructuredGrid <Piece>, found none");
  const std::string piece_tag = text.substr(piece, text.find('>', piece) - piece);
  const long long num_points = count_attribute(path, piece_tag, "NumberOfPoints", 1, 100000000);
  const long long num_cells = count_attribute(path, piece_tag, "NumberOfCells", 1, 100000000);
  const size_t appended_at = text.find("<AppendedData");
  const Appended appended = find_appended(path, text, appended_at);
  const SectionMap sections(text, piece);
  std::map<std::string, ArrayRead> points, cells;
  for (size_t pos = text.find("<DataArray"); pos < appended_at && pos != std::string::npos;
       pos = text.find("<DataArray", pos + 1)) {
    const auto tag_end = text.find('>', pos);
    if (tag_end == std::string::npos) throw InputError(path + ": a <DataArray> is not closed");
    ArrayRead a = read_array(path, text, appended, pos, tag_end);
    switch (sections.at(pos)) {
      case Section::kPoints:
        points[a.name] = std::move(a);
        break;
      case Section::kCells:
        cells[a.name] = std::move(a);
        break;
      case Section::kPointData:
      case Section::kCellData: {
        const bool cell = sections.at(pos) == Section::kCellData;
        check_count(path, a, cell ? num_cells : num_points, cell ? "cells" : "points");
        // One components entry per name: a second array of the name (point data beside cell
        // data of other components) would leave the first one's values with its count.
        if (v.components.count(a.name))
          throw InputError(path + ": DataArray " + quoted_found(a.name) +
                           ": expected one array of that name in the point and cell data, "
                           "found a second");
        v.components[a.name] = a.components;
        (cell ? v.cell_data : v.point_data)[a.name] = std::move(a.values);
        break;
      }
      case Section::kNone:
        break;  // outside the grid (FieldData): not read
    }
  }
  for (const auto& [need, from] : {std::pair{"Points", &points}, std::pair{"connectivity", &cells},
                                   std::pair{"types", &cells}})
    if (!from->count(need))
      throw InputError(path + ": expected a DataArray named '" + need + "', found none");
  const ArrayRead& pts = points["Points"];
  if (pts.components != 3)
    throw InputError(path + ": DataArray 'Points': expected 3 components, found " +
                     std::to_string(pts.components));
  check_count(path, pts, num_points, "points");
  for (long long i = 0; i < num_points; ++i)
    v.points.emplace_back(pts.values[3 * i], pts.values[3 * i + 1]);
  read_cells(path, cells, num_points, num_cells, v);
  return v;
}

}  // namespace c2d::app
