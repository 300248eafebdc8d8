#include "core/writers.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <bit>
#include <cerrno>
#include <charconv>
#include <cstdint>
#include <cstring>
#include <functional>
#include <iomanip>
#include <sstream>
#include <stdexcept>
#include <string_view>

#include "core/probes.hpp"

namespace c2d::core {

WriteError::WriteError(const std::string& path, int error_number, const std::string& message)
    : std::runtime_error(message.empty() ? path + ": cannot write: " + std::strerror(error_number)
                                         : message),
      path_(path),
      reason_(std::strerror(error_number)),
      error_number_(error_number) {}

void write_file_atomic(const std::string& path, const std::string& content) {
  const std::string tmp = path + ".tmp." + std::to_string(::getpid());
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (fd < 0) throw WriteError(path, errno);
  // errno is taken where the call failed: close() and unlink() below may change it.
  auto fail = [&](int error_number) {
    ::unlink(tmp.c_str());  // a full disk gets its space back
    throw WriteError(path, error_number);
  };
  for (size_t done = 0; done < content.size();) {
    const ssize_t n = ::write(fd, content.data() + done, content.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int e = n < 0 ? errno : EIO;
      ::close(fd);
      fail(e);
    }
    done += static_cast<size_t>(n);
  }
  if (::close(fd) != 0) fail(errno);  // NFS and quotas report some failures only here
  if (::rename(tmp.c_str(), path.c_str()) != 0) fail(errno);
}

namespace {

/// Text built by appending, numbers through std::to_chars (12 significant digits, as
/// setprecision(12) printed them): about twice as fast as an ostringstream for the millions of
/// numbers of a large VTU.
class Text {
 public:
  Text& operator<<(double v) {
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general, 12);
    s_.append(buf, static_cast<size_t>(r.ptr - buf));
    return *this;
  }
  Text& operator<<(int v) {
    char buf[16];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    s_.append(buf, static_cast<size_t>(r.ptr - buf));
    return *this;
  }
  Text& operator<<(char c) {
    s_.push_back(c);
    return *this;
  }
  Text& operator<<(const char* t) {
    s_.append(t);
    return *this;
  }
  Text& operator<<(const std::string& t) {
    s_.append(t);
    return *this;
  }
  void append(const char* bytes, size_t n) { s_.append(bytes, n); }
  void reserve(size_t n) { s_.reserve(n); }
  std::string str() && { return std::move(s_); }

 private:
  std::string s_;
};

/// One VTK DataArray: doubles (Float64), or integers of the type named.
struct DataArray {
  DataArray(std::string n, int c, std::string t = "Float64")
      : name(std::move(n)), components(c), type(std::move(t)) {}
  std::string name;
  int components = 1;
  std::string type;
  std::vector<double> real;
  std::vector<std::int32_t> integer;  ///< Int32 arrays
  std::vector<std::uint8_t> byte;     ///< UInt8 arrays

  size_t bytes() const {
    return real.size() * sizeof(double) + integer.size() * sizeof(std::int32_t) + byte.size();
  }
  const char* data() const {
    if (!real.empty()) return reinterpret_cast<const char*>(real.data());
    if (!integer.empty()) return reinterpret_cast<const char*>(integer.data());
    return reinterpret_cast<const char*>(byte.data());
  }
};

DataArray reals(const std::string& name, int components, int count,
                const std::function<double(int, int)>& value) {
  DataArray a(name, components);
  a.real.resize(static_cast<size_t>(count) * components);
  for (int i = 0; i < count; ++i)
    for (int c = 0; c < components; ++c) a.real[static_cast<size_t>(i) * components + c] = value(i, c);
  return a;
}

/// The array's opening tag; ASCII arrays then hold their values, appended ones point into the
/// appended block at `offset`.
void open_array(Text& os, const DataArray& a, VtuEncoding encoding, size_t offset) {
  os << "        <DataArray type=\"" << a.type << "\" Name=\"" << a.name << "\"";
  if (a.components > 1) os << " NumberOfComponents=\"" << a.components << "\"";
  if (encoding == VtuEncoding::kAscii) {
    os << " format=\"ascii\">\n";
    return;
  }
  os << " format=\"appended\" offset=\"" << std::to_string(offset) << "\"/>\n";
}

void ascii_values(Text& os, const DataArray& a) {
  const size_t n = a.real.size() + a.integer.size() + a.byte.size();
  for (size_t i = 0; i < n; ++i) {
    os << (i % a.components == 0 ? "          " : " ");
    if (!a.real.empty()) os << a.real[i];
    else if (!a.integer.empty()) os << static_cast<int>(a.integer[i]);
    else os << static_cast<int>(a.byte[i]);
    if ((i + 1) % a.components == 0) os << '\n';
  }
  os << "        </DataArray>\n";
}

/// The grid's arrays in document order: points, cells, point data, cell data.
struct GridArrays {
  DataArray points;
  std::vector<DataArray> cells, point_data, cell_data;
};

GridArrays grid_arrays(const Model& model, const Results& r) {
  const Mesh& mesh = model.mesh;
  const int nn = mesh.nodes_per_element(), nodes = mesh.num_nodes(), elements = mesh.num_elements();
  GridArrays g{reals("Points", 3, nodes, [&](int i, int c) { return c < 2 ? mesh.nodes[i][c] : 0.0; }),
               {}, {}, {}};
  DataArray conn("connectivity", 1, "Int32"), offsets("offsets", 1, "Int32"), types("types", 1, "UInt8");
  for (const auto& el : mesh.elements) conn.integer.insert(conn.integer.end(), el.begin(), el.begin() + nn);
  for (int e = 0; e < elements; ++e) offsets.integer.push_back((e + 1) * nn);
  types.byte.assign(elements, nn == 3 ? 5 : 22);
  g.cells = {std::move(conn), std::move(offsets), std::move(types)};
  auto& pd = g.point_data;
  pd.push_back(reals("displacement", 3, nodes, [&](int i, int c) { return c < 2 ? r.displacement[2 * i + c] : 0.0; }));
  pd.push_back(reals("reaction", 3, nodes, [&](int i, int c) { return c < 2 ? r.reaction[2 * i + c] : 0.0; }));
  pd.push_back(reals("stress_smoothed", 3, nodes, [&](int i, int c) { return r.nodal_stress(c, i); }));
  for (const auto& [q, name] : {std::pair{"vm", "von_mises_smoothed"}, std::pair{"s1", "s1_smoothed"},
                                std::pair{"s2", "s2_smoothed"}}) {
    const char* quantity = q;  // (a structured binding: clang 14 cannot capture it)
    pd.push_back(reals(name, 1, nodes, [&](int i, int) { return nodal_quantity(model, r, quantity, i); }));
  }
  for (const auto& entry : r.point_fields) {  // (a structured binding: clang 14 cannot capture it)
    const VecX& field = entry.second;
    pd.push_back(reals(entry.first, 1, nodes, [&](int i, int) { return field[i]; }));
  }
  auto element_mean = [&](int e) -> Voigt { return r.element_stresses.at_points[e].rowwise().mean(); };
  auto& cd = g.cell_data;
  cd.push_back(reals("stress_element", 3, elements, [&](int e, int c) { return element_mean(e)[c]; }));
  cd.push_back(reals("von_mises_element", 1, elements, [&](int e, int) {
    const Voigt s = element_mean(e);
    return von_mises(s, model.materials[mesh.element_material[e]].sigma_zz(s));
  }));
  cd.push_back(reals("zz_local_parameter", 1, elements, [&](int e, int) {
    return r.error.local_parameter.empty() ? 0.0 : r.error.local_parameter[e];
  }));
  cd.push_back(reals("body_id", 1, elements, [&](int e, int) { return mesh.element_body[e]; }));
  cd.push_back(reals("material_id", 1, elements, [&](int e, int) { return mesh.element_material[e]; }));
  return g;
}

}  // namespace

std::string vtu_document(const Model& model, const Results& r, VtuEncoding encoding) {
  const GridArrays g = grid_arrays(model, r);
  std::vector<const DataArray*> order{&g.points};
  for (const auto* list : {&g.cells, &g.point_data, &g.cell_data})
    for (const auto& a : *list) order.push_back(&a);
  const bool ascii = encoding == VtuEncoding::kAscii;
  size_t payload = 0;
  for (const auto* a : order) payload += a->bytes() + sizeof(std::uint64_t);
  Text os;
  os.reserve(ascii ? payload * 3 : payload + 4096);
  os << "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\""
     << (std::endian::native == std::endian::little ? "LittleEndian" : "BigEndian")
     << "\" header_type=\"UInt64\">\n  <UnstructuredGrid>\n"
     << "    <Piece NumberOfPoints=\"" << model.mesh.num_nodes() << "\" NumberOfCells=\""
     << model.mesh.num_elements() << "\">\n";
  size_t offset = 0;
  auto emit = [&](const DataArray& a) {
    open_array(os, a, encoding, offset);
    if (ascii) ascii_values(os, a);
    offset += a.bytes() + sizeof(std::uint64_t);
  };
  os << "      <Points>\n";
  emit(g.points);
  os << "      </Points>\n      <Cells>\n";
  for (const auto& a : g.cells) emit(a);
  os << "      </Cells>\n      <PointData Vectors=\"displacement\">\n";
  for (const auto& a : g.point_data) emit(a);
  os << "      </PointData>\n      <CellData>\n";
  for (const auto& a : g.cell_data) emit(a);
  os << "      </CellData>\n    </Piece>\n  </UnstructuredGrid>\n";
  if (!ascii) {
    // Raw appended data: after '_', each array as its byte count (UInt64) and its bytes.
    os << "  <AppendedData encoding=\"raw\">\n   _";
    for (const auto* a : order) {
      const std::uint64_t n = a->bytes();
      os.append(reinterpret_cast<const char*>(&n), sizeof n);
      os.append(a->data(), a->bytes());
    }
    os << "\n  </AppendedData>\n";
  }
  os << "</VTKFile>\n";
  return std::move(os).str();
}

std::string pvd_document(const std::vector<std::pair<double, std::string>>& steps) {
  std::ostringstream os;
  os << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n  <Collection>\n";
  for (const auto& [t, file] : steps) {
    // 15 significant digits: a stream's default 6 made the load factor 1/30 "0.0333333", off
    // steps.csv and merging steps closer than 1e-6; 17 would print a sum of ten 0.1 steps as
    // 0.9999999999999999.
    char time[32];
    const auto r = std::to_chars(time, time + sizeof time, t, std::chars_format::general, 15);
    os << "    <DataSet timestep=\"" << std::string_view(time, static_cast<size_t>(r.ptr - time))
       << "\" part=\"0\" file=\"" << file << "\"/>\n";
  }
  os << "  </Collection>\n</VTKFile>\n";
  return os.str();
}

std::string nodes_csv(const Model& model, const Results& r) {
  Text os;
  os.reserve(static_cast<size_t>(model.mesh.num_nodes()) * 200);
  os << "node,x,y,ux,uy,sx,sy,sxy,vm,rx,ry\n";
  for (int n = 0; n < model.mesh.num_nodes(); ++n) {
    os << n + 1 << ',' << model.mesh.nodes[n].x() << ',' << model.mesh.nodes[n].y() << ','
       << r.displacement[2 * n] << ',' << r.displacement[2 * n + 1] << ','
       << r.nodal_stress(0, n) << ',' << r.nodal_stress(1, n) << ',' << r.nodal_stress(2, n)
       << ',' << nodal_quantity(model, r, "vm", n) << ',' << r.reaction[2 * n] << ','
       << r.reaction[2 * n + 1] << '\n';
  }
  return std::move(os).str();
}

}  // namespace c2d::core
