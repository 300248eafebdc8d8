#include "core/writers.hpp"

#include <charconv>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>
#include <unistd.h>

#include "core/probes.hpp"

namespace c2d::core {

void write_file_atomic(const std::string& path, const std::string& content) {
  const std::string tmp = path + ".tmp." + std::to_string(::getpid());
  {
    std::ofstream out(tmp, std::ios::binary);
    if (!out) throw std::runtime_error(path + ": cannot write (" + tmp + ")");
    out << content;
    out.flush();
    if (!out) throw std::runtime_error(path + ": write failed");
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::filesystem::remove(tmp);
    throw std::runtime_error(path + ": cannot rename the temporary file: " + ec.message());
  }
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
  void reserve(size_t n) { s_.reserve(n); }
  std::string str() && { return std::move(s_); }

 private:
  std::string s_;
};

void data_array(Text& os, const std::string& name, int components,
                const std::function<double(int, int)>& value, int count) {
  os << "        <DataArray type=\"Float64\" Name=\"" << name << "\" NumberOfComponents=\""
     << components << "\" format=\"ascii\">\n";
  for (int i = 0; i < count; ++i) {
    os << "          ";
    for (int c = 0; c < components; ++c) os << value(i, c) << (c + 1 < components ? " " : "");
    os << '\n';
  }
  os << "        </DataArray>\n";
}

}  // namespace

std::string vtu_document(const Model& model, const Results& r) {
  const Mesh& mesh = model.mesh;
  const int nn = mesh.nodes_per_element();
  Text os;
  os.reserve(static_cast<size_t>(mesh.num_nodes()) * 220 + static_cast<size_t>(mesh.num_elements()) * 120);
  os << "<?xml version=\"1.0\"?>\n"
        "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
        "  <UnstructuredGrid>\n"
     << "    <Piece NumberOfPoints=\"" << mesh.num_nodes() << "\" NumberOfCells=\""
     << mesh.num_elements() << "\">\n";
  os << "      <Points>\n";
  data_array(os, "Points", 3, [&](int i, int c) { return c < 2 ? mesh.nodes[i][c] : 0.0; },
             mesh.num_nodes());
  os << "      </Points>\n      <Cells>\n"
        "        <DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">\n";
  for (const auto& el : mesh.elements) {
    os << "         ";
    for (int i = 0; i < nn; ++i) os << ' ' << el[i];
    os << '\n';
  }
  os << "        </DataArray>\n"
        "        <DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">\n         ";
  for (int e = 0; e < mesh.num_elements(); ++e) os << ' ' << (e + 1) * nn;
  os << "\n        </DataArray>\n"
        "        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n         ";
  for (int e = 0; e < mesh.num_elements(); ++e) os << ' ' << (nn == 3 ? 5 : 22);
  os << "\n        </DataArray>\n      </Cells>\n";

  os << "      <PointData Vectors=\"displacement\">\n";
  data_array(os, "displacement", 3,
             [&](int i, int c) { return c < 2 ? r.displacement[2 * i + c] : 0.0; },
             mesh.num_nodes());
  data_array(os, "reaction", 3, [&](int i, int c) { return c < 2 ? r.reaction[2 * i + c] : 0.0; },
             mesh.num_nodes());
  data_array(os, "stress_smoothed", 3, [&](int i, int c) { return r.nodal_stress(c, i); },
             mesh.num_nodes());
  data_array(os, "von_mises_smoothed", 1,
             [&](int i, int) { return nodal_quantity(model, r, "vm", i); }, mesh.num_nodes());
  data_array(os, "s1_smoothed", 1, [&](int i, int) { return nodal_quantity(model, r, "s1", i); },
             mesh.num_nodes());
  data_array(os, "s2_smoothed", 1, [&](int i, int) { return nodal_quantity(model, r, "s2", i); },
             mesh.num_nodes());
  for (const auto& entry : r.point_fields) {  // (a structured binding: clang 14 cannot capture it)
    const VecX& field = entry.second;
    data_array(os, entry.first, 1, [&](int i, int) { return field[i]; }, mesh.num_nodes());
  }
  os << "      </PointData>\n      <CellData>\n";
  auto element_mean = [&](int e) -> Voigt { return r.element_stresses.at_points[e].rowwise().mean(); };
  data_array(os, "stress_element", 3, [&](int e, int c) { return element_mean(e)[c]; },
             mesh.num_elements());
  data_array(os, "von_mises_element", 1,
             [&](int e, int) {
               const Voigt s = element_mean(e);
               return von_mises(s, model.materials[mesh.element_material[e]].sigma_zz(s));
             },
             mesh.num_elements());
  data_array(os, "zz_local_parameter", 1,
             [&](int e, int) {
               return r.error.local_parameter.empty() ? 0.0 : r.error.local_parameter[e];
             },
             mesh.num_elements());
  data_array(os, "body_id", 1, [&](int e, int) { return mesh.element_body[e]; },
             mesh.num_elements());
  data_array(os, "material_id", 1, [&](int e, int) { return mesh.element_material[e]; },
             mesh.num_elements());
  os << "      </CellData>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n";
  return std::move(os).str();
}

std::string pvd_document(const std::vector<std::pair<double, std::string>>& steps) {
  std::ostringstream os;
  os << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n  <Collection>\n";
  for (const auto& [t, file] : steps)
    os << "    <DataSet timestep=\"" << t << "\" part=\"0\" file=\"" << file << "\"/>\n";
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
