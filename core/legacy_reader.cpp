#include "core/legacy_reader.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <tuple>
#include <utility>

#include "core/errors.hpp"

namespace c2d::core {

namespace {

class LineReader {
 public:
  explicit LineReader(const std::string& path) : path_(path), in_(path) {
    if (!in_) throw InputError(path + ": expected a readable data file, found none (no such file, or "
                               "no permission to read it)");
    std::ifstream count(path);
    for (std::string line; std::getline(count, line);) ++lines_;
  }
  /// Lines in the file: no count in it may exceed them (nothing is sized beyond the file).
  long long lines() const { return lines_; }
  // Next non-empty line, split into numbers.
  std::vector<double> next(const std::string& what) {
    std::string line;
    while (std::getline(in_, line)) {
      ++line_no_;
      if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
      std::istringstream is(line);
      std::vector<double> v;
      std::string tok;
      while (is >> tok) {
        try {
          size_t used = 0;
          v.push_back(std::stod(tok, &used));
          if (used != tok.size()) throw std::invalid_argument(tok);
        } catch (const std::exception&) {
          fail("expected " + what + ", found " + quoted_found(tok));
        }
      }
      return v;
    }
    fail("expected " + what + ", found the end of the file");
  }
  [[noreturn]] void fail(const std::string& message) const {
    throw InputError(path_ + ":" + std::to_string(line_no_) + ": " + message);
  }
  int line() const { return line_no_; }

 private:
  std::string path_;
  std::ifstream in_;
  int line_no_ = 0;
  long long lines_ = 0;
};

int as_index(LineReader& r, double v, int count, const char* what) {
  if (v != std::floor(v) || v < 1 || v > count)
    r.fail(std::string("expected a ") + what + " number in 1.." + std::to_string(count) +
           ", found " + number_text(v));
  return static_cast<int>(v) - 1;
}

/// The head line 'NN NE [ITER]': node and element counts (the iteration count is not used).
std::pair<int, int> read_counts(LineReader& r) {
  const auto head = r.next("NN NE ITER");
  if (head.size() < 2 || head.size() > 3)
    r.fail("expected 'NN NE ITER' (node count, element count, iteration count), found " +
           std::to_string(head.size()) + " numbers");
  // Range first: converting a double outside int's range is undefined behaviour.
  const auto integral = [](double v) { return v >= 1 && v <= 1e9 && v == std::floor(v); };
  if (!integral(head[0]) || !integral(head[1]))
    r.fail("expected positive integer node and element counts, found " +
           number_text(head[0]) + " and " + number_text(head[1]));
  const int nn = static_cast<int>(head[0]), ne = static_cast<int>(head[1]);
  if (nn < 3) r.fail("expected at least 3 nodes, found " + std::to_string(nn));
  // (Generous: a short file gets its own located message at the line that is missing.)
  if (static_cast<long long>(nn) + ne > 2 * r.lines() + 16)
    r.fail("expected node and element counts that the file's " + std::to_string(r.lines()) +
           " lines can hold, found " + std::to_string(nn) + " and " + std::to_string(ne));
  return {nn, ne};
}

/// One direction `c` of a node line: flag 1 prescribes `value` as a displacement, flag 0 with a
/// non-zero value applies it as a nodal force.
void add_node_condition(LineReader& r, const std::string& path, int id, int c, double flag,
                        double value, Scene& scene) {
  if (flag != 0 && flag != 1)
    r.fail("expected a support flag 0 or 1, found " + number_text(flag));
  SelectionSpec on;
  on.kind = SelectionSpec::Kind::kNodes;
  on.nodes = {id};
  on.at.where = path + ":" + std::to_string(r.line()) + ": node " + std::to_string(id + 1);
  if (flag == 1) {
    SupportSpec s;
    s.on = on;
    (c == 0 ? s.ux : s.uy) = value;
    s.at = on.at;
    scene.supports.push_back(s);
  } else if (value != 0.0) {
    LoadSpec l;
    l.kind = LoadSpec::Kind::kNodalForce;
    l.on = on;
    l.vector = c == 0 ? Vec2(value, 0) : Vec2(0, value);
    l.at = on.at;
    scene.loads.push_back(l);
  }
}

/// The node block: coordinates into `mesh`, supports and loads into `scene`. Returns which
/// nodes the block defined.
std::vector<bool> read_nodes(LineReader& r, const std::string& path, int nn, Mesh& mesh,
                             Scene& scene) {
  mesh.nodes.assign(nn, Vec2::Zero());
  std::vector<bool> seen(nn, false);
  for (int i = 0; i < nn; ++i) {
    const auto v = r.next("a node line 'id x y sx sy fx fy'");
    if (v.size() != 7)
      r.fail("expected 7 numbers on a node line (id x y sx sy fx fy), found " +
             std::to_string(v.size()));
    for (double x : v)
      if (!std::isfinite(x)) r.fail("expected finite numbers on a node line, found " + number_text(x));
    // Coordinates as the scene's shapes (gmsh-free here, but 1e300 would overflow the extent),
    // loads and prescribed values as the scene's: beyond 1e30, K u or f overflows.
    if (!(std::abs(v[1]) <= 1e15 && std::abs(v[2]) <= 1e15))
      r.fail("expected node coordinates of at most 1e15 in magnitude");
    for (int k = 3; k < 7; ++k)
      if (!(std::abs(v[k]) <= 1e30))
        r.fail("expected support values and loads of at most 1e30 in magnitude, found " +
               number_text(v[k]));
    const int id = as_index(r, v[0], nn, "node");
    if (seen[id]) r.fail("node " + std::to_string(id + 1) + " defined twice");
    seen[id] = true;
    mesh.nodes[id] = Vec2(v[1], v[2]);
    for (int c = 0; c < 2; ++c) add_node_condition(r, path, id, c, v[3 + c], v[5 + c], scene);
  }
  return seen;
}

/// The element block's shared state: element order (0 until the first solid element) and the
/// plane state's element type (-1 until then), and one material per distinct property set.
struct ElementBlock {
  int order = 0;
  int state = -1;
  std::map<std::tuple<int, double, double, double>, int> material_index;
};

/// One element line: its numbers, node count (3 or 6), type and properties p1 p2 p3.
struct ElementLine {
  std::vector<double> v;
  int nodes_per = 0;
  int type = 0;
  double p1 = 0, p2 = 0, p3 = 0;
};

/// Reads an element line 'id n1 n2 n3 [n4 n5 n6] type p1 p2 p3'.
ElementLine read_element_line(LineReader& r) {
  ElementLine e;
  e.v = r.next("an element line 'id n1 n2 n3 type p1 p2 p3'");
  const auto& v = e.v;
  if (v.size() == 8)
    e.nodes_per = 3;
  else if (v.size() == 11)
    e.nodes_per = 6;
  else
    r.fail("expected 8 (T3) or 11 (T6) numbers on an element line, found " +
           std::to_string(v.size()));
  const double type = v[1 + e.nodes_per];
  if (type != 0 && type != 1 && type != 2)
    r.fail("expected element type 0 (plane stress), 1 (gap) or 2 (plane strain), found " +
           number_text(type));
  e.type = static_cast<int>(type);
  e.p1 = v[2 + e.nodes_per], e.p2 = v[3 + e.nodes_per], e.p3 = v[4 + e.nodes_per];
  return e;
}

/// A gap element (type 1): nodes n1 n2, direction (p1, p2), stiffness p3.
void add_gap_element(LineReader& r, const ElementLine& e, int nn, ExplicitModel& model) {
  ExplicitModel::Gap gap;
  gap.node_a = as_index(r, e.v[1], nn, "node");
  gap.node_b = as_index(r, e.v[2], nn, "node");
  gap.direction = Vec2(e.p1, e.p2);
  gap.stiffness = e.p3;
  if (gap.node_a == gap.node_b) r.fail("gap element from a node to itself");
  if (!(gap.stiffness > 0) || !std::isfinite(gap.stiffness))
    r.fail("gap element with a stiffness k > 0, found " + number_text(gap.stiffness));
  if (!gap.direction.allFinite())
    r.fail("gap element with a finite direction (nx, ny), found (" + number_text(e.p1) + ", " +
           number_text(e.p2) + ")");
  if (!(gap.direction.norm() > 0)) r.fail("gap element with a non-zero direction (nx, ny), found (0, 0)");
  model.gaps.push_back(gap);
}

/// Refuses an element whose corner nodes are collinear (zero area: a singular stiffness).
void check_element_area(LineReader& r, const std::vector<Vec2>& x, const std::array<int, 6>& conn) {
  const Vec2 a = x[conn[1]] - x[conn[0]], b = x[conn[2]] - x[conn[0]];
  const double scale = std::max({a.squaredNorm(), b.squaredNorm(), (b - a).squaredNorm()});
  if (!(std::abs(a.x() * b.y() - a.y() * b.x()) > 1e-12 * scale))
    r.fail("an element of positive area, found collinear corner nodes " + std::to_string(conn[0] + 1) +
           ", " + std::to_string(conn[1] + 1) + ", " + std::to_string(conn[2] + 1));
}

/// A solid element (type 0 or 2): E = p1, thickness = p2, nu = p3.
void add_solid_element(LineReader& r, const ElementLine& e, int nn, ElementBlock& block,
                       ExplicitModel& model) {
  if (e.type != 0 && e.type != 2)
    r.fail("expected element type 0 (plane stress), 1 (gap) or 2 (plane strain), found " +
           std::to_string(e.type));
  if (block.order == 0) block.order = e.nodes_per == 3 ? 1 : 2;
  if ((block.order == 1) != (e.nodes_per == 3)) r.fail("mixed T3 and T6 elements");
  if (block.state >= 0 && block.state != e.type)
    r.fail("mixed plane stress and plane strain elements");
  block.state = e.type;
  // The bounds of a scene's [[material]] (beyond them the stiffness or displacements overflow).
  if (!(e.p1 >= 1e-30 && e.p1 <= 1e30) || !(e.p2 >= 1e-30 && e.p2 <= 1e30) ||
      !(e.p3 > -1 && e.p3 < 0.5))
    r.fail("expected E and thickness in [1e-30, 1e30] and -1 < nu < 0.5");
  std::array<int, 6> conn{-1, -1, -1, -1, -1, -1};
  for (int k = 0; k < e.nodes_per; ++k) {
    conn[k] = as_index(r, e.v[1 + k], nn, "node");
    for (int j = 0; j < k; ++j)
      if (conn[j] == conn[k]) r.fail("an element with distinct nodes, found node " + std::to_string(conn[k] + 1) + " twice");
  }
  check_element_area(r, model.mesh.nodes, conn);
  auto [it, inserted] = block.material_index.try_emplace({e.type, e.p1, e.p2, e.p3},
                                                         static_cast<int>(model.materials.size()));
  if (inserted) {
    MaterialSpec m;
    m.name = "material" + std::to_string(model.materials.size() + 1);
    m.young = e.p1;
    m.thickness = e.p2;
    m.poisson = e.p3;
    model.materials.push_back(m);
  }
  model.mesh.elements.push_back(conn);
  model.mesh.element_body.push_back(0);
  model.mesh.element_material.push_back(it->second);
}

/// The element block: T3 or T6 solids and gap elements, into `model`.
ElementBlock read_elements(LineReader& r, int nn, int ne, ExplicitModel& model) {
  ElementBlock block;
  for (int i = 0; i < ne; ++i) {
    const ElementLine e = read_element_line(r);
    if (e.type == 1)
      add_gap_element(r, e, nn, model);
    else
      add_solid_element(r, e, nn, block, model);
  }
  return block;
}

}  // namespace

Scene read_legacy_scene(const std::string& path) {
  LineReader r(path);
  const auto [nn, ne] = read_counts(r);

  Scene scene;
  scene.path = path;
  scene.title = "legacy data file " + path;
  auto model = std::make_shared<ExplicitModel>();
  Mesh& mesh = model->mesh;
  const std::vector<bool> seen = read_nodes(r, path, nn, mesh, scene);
  const ElementBlock block = read_elements(r, nn, ne, *model);
  if (mesh.elements.empty()) r.fail("the file has no solid (type 0 or 2) elements");
  const auto tail = r.next("the two big numbers 'BIG BIGkr'");
  (void)tail;
  mesh.order = block.order;
  for (int i = 0; i < nn; ++i)
    if (!seen[i]) throw InputError(path + ": expected a line for every node 1.." + std::to_string(seen.size()) +
                       ", found none for node " + std::to_string(i + 1));
  mesh.orient_counter_clockwise();
  mesh.build_boundary();
  scene.analysis.order = block.order;
  scene.analysis.state = block.state == 2 ? PlaneState::kPlaneStrain : PlaneState::kPlaneStress;
  scene.analysis.smoothing = Smoothing::kDirectAverage;  // the seed program's smoothing
  scene.materials = model->materials;
  BodySpec body;
  body.name = "body";
  body.material = model->materials.front().name;
  scene.bodies.push_back(body);
  scene.explicit_model = model;
  return scene;
}

}  // namespace c2d::core
