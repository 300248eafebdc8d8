#include "core/mesher.hpp"

#include <gmsh.h>
#include <omp.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <mutex>
#include <numbers>
#include <unordered_map>

#include "core/errors.hpp"
#include "core/mesh_budget.hpp"
#include "core/mesh_refine.hpp"
#include "core/msh_check.hpp"
#include "core/point_cloud.hpp"
#include "core/shape_check.hpp"

namespace c2d::core {

namespace {

/// gmsh is a process-wide singleton; initialise it once, quietly, meshing on one thread (its
/// parallel loops run one face at a time; the caller's OpenMP count is OneThreadForGmsh's).
void ensure_gmsh() {
  static bool initialised = false;
  if (!initialised) {
    gmsh::initialize(0, nullptr, false);
    gmsh::option::setNumber("General.Terminal", 0);
    gmsh::option::setNumber("General.Verbosity", 1);
    gmsh::option::setNumber("General.NumThreads", 1);
    gmsh::option::setNumber("Mesh.MaxNumThreads1D", 1);
    gmsh::option::setNumber("Mesh.MaxNumThreads2D", 1);
    initialised = true;
  }
}

/// gmsh's API reports an error by throwing its message (General.AbortOnError = 2, set by
/// gmsh::initialize). Its curve and surface meshing run inside OpenMP parallel loops, whose
/// bodies GCC compiles as must-not-throw whatever the thread count: a message thrown there
/// (a thin rectangle's "Unable to recover the edge") calls std::terminate. While gmsh meshes,
/// errors are logged instead (AbortOnError = 0: gmsh records the failure and goes on), and the
/// first one is thrown here, outside gmsh. The constructor and destructor never throw on their
/// own: gmsh's logger and option calls only fail when gmsh is not initialised.
class GmshErrorsLogged {
 public:
  GmshErrorsLogged() {
    gmsh::option::setNumber("General.AbortOnError", 0);
    gmsh::logger::start();
  }
  ~GmshErrorsLogged() {
    gmsh::logger::stop();
    gmsh::option::setNumber("General.AbortOnError", 2);
  }
  GmshErrorsLogged(const GmshErrorsLogged&) = delete;
  GmshErrorsLogged& operator=(const GmshErrorsLogged&) = delete;

  /// The first error gmsh logged since construction, empty if none.
  std::string first_error() const {
    std::vector<std::string> log;
    gmsh::logger::get(log);
    const std::string prefix = "Error: ";
    for (const auto& line : log)
      if (line.rfind(prefix, 0) == 0) return line.substr(prefix.size());
    return {};
  }
};

/// Meshes the current model's curves and surfaces; a gmsh error becomes a std::string thrown
/// here, as the API's other errors are (mesh_body turns it into an InputError).
void generate_surface_mesh() {
  const GmshErrorsLogged errors;
  gmsh::model::mesh::generate(2);
  if (const std::string error = errors.first_error(); !error.empty())
    throw "could not mesh the shape: " + error;
}

/// A boundary curve of a body's shape: its gmsh tag, its name, and for a circular arc its
/// circle (where subdivision puts new boundary nodes).
struct NamedCurve {
  int tag;
  std::string name;
  bool arc = false;
  Vec2 center = Vec2::Zero();
  double radius = 0.0;
};

/// A full circle of four quarter arcs named `name`: its curve loop's tag.
int add_circle(const Vec2& center, double radius, const std::string& name,
               std::vector<NamedCurve>& curves) {
  namespace geo = gmsh::model::geo;
  const int c = geo::addPoint(center.x(), center.y(), 0.0);
  std::vector<int> points, arcs;
  for (int i = 0; i < 4; ++i) {
    const double t = i * std::numbers::pi / 2.0;
    points.push_back(geo::addPoint(center.x() + radius * std::cos(t),
                                   center.y() + radius * std::sin(t), 0.0));
  }
  for (int i = 0; i < 4; ++i) {
    arcs.push_back(geo::addCircleArc(points[i], c, points[(i + 1) % 4]));
    curves.push_back({arcs.back(), name, true, center, radius});
  }
  return geo::addCurveLoop(arcs);
}

// Builds the primitive in gmsh's built-in (geo) kernel; returns the named boundary curves.
std::vector<NamedCurve> build_geometry(const ShapeSpec& s) {
  namespace geo = gmsh::model::geo;
  std::vector<NamedCurve> curves;
  std::vector<int> loop;
  auto add_line = [&](int a, int b, const std::string& name) {
    const int c = geo::addLine(a, b);
    curves.push_back({c, name});
    loop.push_back(c);
  };
  std::vector<Vec2> interior;
  if (s.type == "rectangle" || s.type == "polygon" || s.type == "points") {
    std::vector<Vec2> pts = polygon_outline(s);
    if (s.type == "points") {
      pts.clear();
      split_point_cloud(s, pts, interior);
    }
    std::vector<int> tags;
    for (const auto& p : pts) tags.push_back(geo::addPoint(p.x(), p.y(), 0.0));
    static const char* rect_names[] = {"bottom", "right", "top", "left"};
    for (size_t i = 0; i < pts.size(); ++i) {
      const std::string name = s.type == "rectangle" ? rect_names[i] : "edge" + std::to_string(i);
      const int next = tags[(i + 1) % pts.size()];
      const auto arc = std::find_if(s.arcs.begin(), s.arcs.end(), [i](const ShapeSpec::Arc& a) {
        return a.edge == static_cast<int>(i);
      });
      if (arc == s.arcs.end()) {
        add_line(tags[i], next, name);
        continue;
      }
      const int center = geo::addPoint(arc->center.x(), arc->center.y(), 0.0);
      curves.push_back(
          {geo::addCircleArc(tags[i], center, next), name, true, arc->center, arc->radius});
      loop.push_back(curves.back().tag);
    }
  } else if (s.type == "annulus") {
    // Two full circles; the inner one bounds the hole.
    const int outer = add_circle(s.center, s.radius, "outer", curves);
    geo::addPlaneSurface({outer, add_circle(s.center, s.inner_radius, "inner", curves)});
    geo::synchronize();
    return curves;
  } else {
    const bool full = s.type == "disk" || s.to_deg - s.from_deg >= 360.0 - 1e-9;
    const double from = full ? 0.0 : s.from_deg, to = full ? 360.0 : s.to_deg;
    const int pieces = std::max(full ? 4 : 1, static_cast<int>(std::ceil((to - from) / 90.0)));
    const int center = geo::addPoint(s.center.x(), s.center.y(), 0.0);
    std::vector<int> arc_points;
    for (int i = 0; i <= pieces; ++i) {
      if (full && i == pieces) {
        arc_points.push_back(arc_points.front());
        break;
      }
      const double t = (from + (to - from) * i / pieces) * std::numbers::pi / 180.0;
      arc_points.push_back(geo::addPoint(s.center.x() + s.radius * std::cos(t),
                                         s.center.y() + s.radius * std::sin(t), 0.0));
    }
    for (int i = 0; i < pieces; ++i) {
      const int c = geo::addCircleArc(arc_points[i], center, arc_points[i + 1]);
      curves.push_back({c, "arc", true, s.center, s.radius});
      loop.push_back(c);
    }
    if (!full) {
      add_line(arc_points.back(), center, "end");
      add_line(center, arc_points.front(), "start");
    }
  }
  std::vector<int> loops = {geo::addCurveLoop(loop)};
  for (size_t k = 0; k < s.holes.size(); ++k)
    loops.push_back(add_circle(s.holes[k].center, s.holes[k].radius, "hole" + std::to_string(k), curves));
  const int surface = geo::addPlaneSurface(loops);
  std::vector<int> inside;
  for (const auto& q : interior) inside.push_back(geo::addPoint(q.x(), q.y(), 0.0));
  geo::synchronize();
  if (!inside.empty()) gmsh::model::mesh::embed(0, inside, 2, surface);
  return curves;
}

// Reads the current gmsh model's 2D mesh (nodes compacted to those of triangles) with the
// segments of the named curves.
CurveMesh read_gmsh_model(int order, const std::vector<NamedCurve>& named) {
  std::vector<std::size_t> node_tags;
  std::vector<double> coords, param;
  gmsh::model::mesh::getNodes(node_tags, coords, param, -1, -1, false, false);
  std::unordered_map<std::size_t, size_t> tag_pos;
  for (size_t i = 0; i < node_tags.size(); ++i) tag_pos[node_tags[i]] = i;

  std::vector<int> types;
  std::vector<std::vector<std::size_t>> elem_tags, elem_nodes;
  gmsh::model::mesh::getElements(types, elem_tags, elem_nodes, 2, -1);
  const int want = order == 1 ? 2 : 9;  // gmsh: 3-node and 6-node triangles
  CurveMesh mesh;
  mesh.order = order;
  std::unordered_map<std::size_t, int> index;  // gmsh tag -> mesh node
  auto node_of = [&](std::size_t tag) {
    auto [it, inserted] = index.try_emplace(tag, static_cast<int>(mesh.nodes.size()));
    if (inserted) {
      const size_t p = tag_pos.at(tag);
      mesh.nodes.emplace_back(coords[3 * p], coords[3 * p + 1]);
    }
    return it->second;
  };
  for (size_t t = 0; t < types.size(); ++t) {
    if (types[t] != want)
      throw InputError("mesh contains gmsh element type " + std::to_string(types[t]) +
                       ", expected only " + (order == 1 ? "3-node" : "6-node") + " triangles");
    const int nn = order == 1 ? 3 : 6;
    for (size_t e = 0; e < elem_tags[t].size(); ++e) {
      std::array<int, 6> conn{-1, -1, -1, -1, -1, -1};
      for (int i = 0; i < nn; ++i) conn[i] = node_of(elem_nodes[t][e * nn + i]);
      mesh.elements.push_back(conn);
    }
  }
  if (mesh.elements.empty()) throw InputError("the mesh has no triangles");
  for (size_t c = 0; c < named.size(); ++c) {
    std::vector<int> ctypes;
    std::vector<std::vector<std::size_t>> ctags, cnodes;
    gmsh::model::mesh::getElements(ctypes, ctags, cnodes, 1, named[c].tag);
    for (size_t t = 0; t < ctypes.size(); ++t) {
      const size_t nn = ctypes[t] == 1 ? 2 : 3;
      for (size_t e = 0; e < ctags[t].size(); ++e) {
        auto a = index.find(cnodes[t][e * nn]), b = index.find(cnodes[t][e * nn + 1]);
        if (a != index.end() && b != index.end())
          mesh.segments.push_back({a->second, b->second, static_cast<int>(c)});
      }
    }
  }
  return mesh;
}

std::vector<std::string> curve_names(const std::vector<NamedCurve>& named) {
  std::vector<std::string> names;
  for (const auto& c : named) names.push_back(c.name);
  return names;
}

/// Lawson's edge flips on the (linear) triangles of the model's surface: an interior edge whose
/// two opposite angles sum to more than π is replaced by the other diagonal, until none is left.
/// The result is the Delaunay triangulation of the vertices, constrained by the boundary (whose
/// edges have one triangle and are never flipped). Used for point clouds, which MeshAdapt
/// triangulates with exactly the given points but not always Delaunay.
void make_delaunay() {
  gmsh::vectorpair surfaces;
  gmsh::model::getEntities(surfaces, 2);
  for (const auto& [dim, surface] : surfaces) {
    std::vector<std::size_t> tags, nodes;
    gmsh::model::mesh::getElementsByType(2, tags, nodes, surface);
    std::map<std::size_t, Vec2> x;
    for (std::size_t n : nodes) {
      if (x.count(n)) continue;
      std::vector<double> coord, param;
      gmsh::model::mesh::getNode(n, coord, param);
      x[n] = Vec2(coord[0], coord[1]);
    }
    std::vector<std::array<std::size_t, 3>> tri;
    for (size_t k = 0; k + 2 < nodes.size(); k += 3) {
      std::array<std::size_t, 3> t{nodes[k], nodes[k + 1], nodes[k + 2]};
      if (orientation(x[t[0]], x[t[1]], x[t[2]]) < 0) std::swap(t[1], t[2]);
      tri.push_back(t);
    }
    auto angle_at = [&](std::size_t at, std::size_t a, std::size_t b) {
      return angle_between(x[a] - x[at], x[b] - x[at]);
    };
    bool flipped = true;
    for (int pass = 0; flipped && pass < 1000; ++pass) {
      flipped = false;
      std::map<std::pair<std::size_t, std::size_t>, std::vector<std::pair<int, int>>> edges;
      for (int t = 0; t < static_cast<int>(tri.size()); ++t)
        for (int k = 0; k < 3; ++k) {
          const std::size_t a = tri[t][k], b = tri[t][(k + 1) % 3];
          edges[{std::min(a, b), std::max(a, b)}].push_back({t, k});
        }
      std::vector<char> touched(tri.size(), 0);
      for (const auto& [edge, sides] : edges) {
        if (sides.size() != 2) continue;
        const auto [t1, k1] = sides[0];
        const auto [t2, k2] = sides[1];
        if (touched[t1] || touched[t2]) continue;  // flip each triangle once per pass
        const std::size_t a = tri[t1][k1], b = tri[t1][(k1 + 1) % 3], c = tri[t1][(k1 + 2) % 3];
        const std::size_t d = tri[t2][(k2 + 2) % 3];
        if (angle_at(c, a, b) + angle_at(d, a, b) <= std::numbers::pi * (1 + 1e-12)) continue;
        tri[t1] = {a, d, c};
        tri[t2] = {d, b, c};
        touched[t1] = touched[t2] = 1;
        flipped = true;
      }
    }
    std::vector<std::size_t> flat;
    for (const auto& t : tri) flat.insert(flat.end(), t.begin(), t.end());
    gmsh::model::mesh::clear({{2, surface}});
    gmsh::model::mesh::addElementsByType(surface, 2, {}, flat);
  }
}

}  // namespace

double requested_size(const BodySpec& body, const Vec2& p) {
  double h = body.mesh_size;
  for (const auto& r : body.refine) {
    const double d = r.segment ? distance_to_segment(p, r.p0, r.p1) : (p - r.p0).norm();
    h = std::min(h, r.size + (r.growth - 1.0) * std::max(0.0, d - r.radius));
  }
  return h;
}

namespace {

/// Opens a .msh file: its physical curves as named curves, with the element order converted if
/// the file's differs from the scene's.
std::vector<NamedCurve> open_msh_file(const std::string& file, int order) {
  check_msh_file(file);  // gmsh's reader crashes on malformed files instead of reporting them
  gmsh::open(file);
  std::vector<NamedCurve> named;
  gmsh::vectorpair groups;
  gmsh::model::getPhysicalGroups(groups, 1);
  for (const auto& [dim, tag] : groups) {
    std::string name;
    gmsh::model::getPhysicalName(dim, tag, name);
    std::vector<int> entities;
    gmsh::model::getEntitiesForPhysicalGroup(dim, tag, entities);
    for (int c : entities) named.push_back({c, name.empty() ? std::to_string(tag) : name});
  }
  std::vector<int> types;
  gmsh::model::mesh::getElementTypes(types, 2);
  const bool has_t6 = std::find(types.begin(), types.end(), 9) != types.end();
  if ((order == 2) != has_t6) gmsh::model::mesh::setOrder(order);
  return named;
}

/// The previous cycle's sizes as a gmsh background mesh (a list-based scalar-triangle view,
/// located through gmsh's octree).
void set_background_size_field(const SizeField& f) {
  std::vector<double> data;
  data.reserve(12 * f.triangles.size());
  for (size_t t = 0; t < f.triangles.size(); ++t) {
    for (int c = 0; c < 2; ++c)
      for (int i = 0; i < 3; ++i) data.push_back(f.triangles[t][i][c]);
    data.insert(data.end(), {0.0, 0.0, 0.0});
    data.insert(data.end(), f.sizes[t].begin(), f.sizes[t].end());
  }
  const int view = gmsh::view::add("size_field");
  gmsh::view::addListData(view, "ST", static_cast<int>(f.triangles.size()), data);
  const int field = gmsh::model::mesh::field::add("PostView");
  gmsh::model::mesh::field::setNumber(field, "ViewTag", view);
  gmsh::model::mesh::field::setAsBackgroundMesh(field);
}

/// Builds the body's shape and meshes it with linear triangles: sizes from the adapted size
/// field, else from the body's mesh size and refinements times `coarsen` (which is 1 for a
/// point cloud or an adapted field); a point cloud is triangulated as given.
std::vector<NamedCurve> mesh_shape(const BodySpec& body, double coarsen) {
  std::vector<NamedCurve> named = build_geometry(body.shape);
  // A point cloud is triangulated as given (Delaunay, no points added): a size far above
  // the cloud's extent.
  const bool cloud = body.shape.type == "points";
  double extent = 0.0;
  for (const auto& q : body.shape.points) extent = std::max(extent, q.norm());
  for (const auto& q : body.shape.boundary) extent = std::max(extent, q.norm());
  const double cloud_size = 1e3 * (1.0 + extent);
  gmsh::option::setNumber("Mesh.MeshSizeFromPoints", 0);
  gmsh::option::setNumber("Mesh.MeshSizeFromCurvature", 0);
  gmsh::option::setNumber("Mesh.MeshSizeExtendFromBoundary", 0);
  const bool adapted = body.size_field && !body.size_field->empty() && !cloud;
  gmsh::option::setNumber("Mesh.MeshSizeMax", cloud     ? cloud_size
                                              : adapted ? body.size_field->max()
                                                        : body.mesh_size * coarsen);
  // A point cloud: MeshAdapt with the boundary imposed and the interior points embedded keeps
  // exactly the given points (gmsh's Delaunay mesher inserted points into a 3 x 3 grid, and
  // gmsh::model::mesh::triangulate drops hull edges); Lawson flips then make it Delaunay.
  gmsh::option::setNumber("Mesh.Algorithm", cloud ? 1 : body.algorithm == "delaunay" ? 5 : 6);
  gmsh::option::setNumber("Mesh.ElementOrder", 1);
  if (adapted) {
    set_background_size_field(*body.size_field);
  } else {
    gmsh::model::mesh::setSizeCallback(
        [&body, cloud, cloud_size, coarsen](int, int, double x, double y, double) {
          return cloud ? cloud_size : coarsen * requested_size(body, {x, y});
        });
  }
  generate_surface_mesh();
  if (!adapted) gmsh::model::mesh::removeSizeCallback();
  if (cloud) make_delaunay();
  return named;
}

/// Subdivisions for a body: none for a file, a point cloud or an adapted size field (whose
/// sizes are the adaptivity's own).
int body_subdivisions(const BodySpec& body) {
  const bool adapted = body.size_field && !body.size_field->empty();
  if (!body.msh_file.empty() || body.shape.type == "points" || adapted) return 0;
  return subdivision_levels(estimate_elements(body), kCoarseElements);
}

/// The coarse mesh read from gmsh, subdivided `levels` times, raised to order 2 if asked, and
/// renumbered for locality; new boundary nodes on arcs go onto their circles.
Mesh subdivided_mesh(const std::vector<NamedCurve>& named, int order, int levels) {
  CurveMesh coarse = read_gmsh_model(1, named);
  const CurveProjector onto_curve = [&named](int curve, Vec2& p) {
    const NamedCurve& c = named[curve];
    const Vec2 d = p - c.center;
    if (c.arc && d.norm() > 0) p = c.center + c.radius * d / d.norm();
  };
  for (int k = 0; k < levels; ++k) subdivide(coarse, onto_curve);
  if (order == 2) make_quadratic(coarse, onto_curve);
  renumber_spatially(coarse);
  return to_mesh(std::move(coarse), curve_names(named));
}

/// The triangulation of a point cloud must use the cloud's points and no others.
void check_cloud_vertices(const ShapeSpec& shape, const Mesh& mesh) {
  std::vector<Vec2> boundary, interior;
  split_point_cloud(shape, boundary, interior);
  std::vector<char> corner(mesh.num_nodes(), 0);
  for (const auto& e : mesh.elements)
    for (int k = 0; k < 3; ++k) corner[e[k]] = 1;
  const auto vertices = std::count(corner.begin(), corner.end(), 1);
  if (vertices != static_cast<long>(boundary.size() + interior.size()))
    throw InputError("shape.points: the triangulation has " + std::to_string(vertices) +
                     " vertices for " + std::to_string(boundary.size() + interior.size()) +
                     " points (gmsh added or dropped some)");
}

/// A .msh file's physical groups as node sets, mapped by coordinates (node tags were
/// compacted).
void add_physical_node_groups(Mesh& mesh) {
  gmsh::vectorpair groups;
  gmsh::model::getPhysicalGroups(groups, -1);
  const PointLocator locator(mesh);
  for (const auto& [dim, tag] : groups) {
    std::string name;
    gmsh::model::getPhysicalName(dim, tag, name);
    std::vector<std::size_t> tags;
    std::vector<double> xyz;
    gmsh::model::mesh::getNodesForPhysicalGroup(dim, tag, tags, xyz);
    auto& dst = mesh.node_groups[name.empty() ? std::to_string(tag) : name];
    for (size_t i = 0; i < tags.size(); ++i) {
      const Vec2 p(xyz[3 * i], xyz[3 * i + 1]);
      const int n = locator.nearest_node(p);
      if (n >= 0 && (mesh.nodes[n] - p).norm() <= 1e-12 * (1.0 + p.norm())) dst.push_back(n);
    }
  }
}

}  // namespace

/// gmsh sets OpenMP's thread count (the calling thread's) to its option General.NumThreads, 1,
/// when it starts, which left every later parallel loop of the run (assembly, the split
/// factorisation) on one thread. gmsh meshes on one thread as it always did; the caller's count
/// is restored when it returns.
class OneThreadForGmsh {
 public:
  OneThreadForGmsh() : saved_(omp_get_max_threads()) { omp_set_num_threads(1); }
  ~OneThreadForGmsh() { omp_set_num_threads(saved_); }
  OneThreadForGmsh(const OneThreadForGmsh&) = delete;
  OneThreadForGmsh& operator=(const OneThreadForGmsh&) = delete;

 private:
  int saved_;
};

Mesh mesh_body(const BodySpec& body, int order) {
  // gmsh's model is process-wide: one body at a time, whatever the calling thread (the Python
  // module runs scenes in several threads).
  static std::mutex gmsh_mutex;
  const std::lock_guard<std::mutex> lock(gmsh_mutex);
  const OneThreadForGmsh one_thread;
  ensure_gmsh();
  gmsh::clear();
  gmsh::model::add(body.name);
  try {
    const bool from_file = !body.msh_file.empty();
    const int levels = body_subdivisions(body);
    const std::vector<NamedCurve> named =
        from_file ? open_msh_file(body.msh_file, order) : mesh_shape(body, std::ldexp(1.0, levels));
    // Mid-side nodes: gmsh's on its own mesh (a file's order is converted on opening), ours on
    // a subdivided one.
    if (!from_file && levels == 0 && order == 2) gmsh::model::mesh::setOrder(2);
    Mesh mesh = levels > 0 ? subdivided_mesh(named, order, levels)
                           : to_mesh(read_gmsh_model(order, named), curve_names(named));
    if (body.shape.type == "points" && !from_file) check_cloud_vertices(body.shape, mesh);
    if (from_file) add_physical_node_groups(mesh);
    gmsh::clear();
    return mesh;
  } catch (const std::string& message) {  // gmsh API errors are thrown as std::string
    gmsh::clear();
    throw InputError(body.at.where + ": gmsh: " + message);
  } catch (const InputError& e) {
    gmsh::clear();
    throw InputError(body.at.where + ": " + e.what());
  }
}

}  // namespace c2d::core
