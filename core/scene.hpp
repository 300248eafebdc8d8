// A validated scene: what the TOML file (docs/scene.md) or a legacy data file describes.
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <toml++/toml.h>

#include "core/material.hpp"
#include "core/mesh.hpp"
#include "core/size_field.hpp"
#include "core/stress_recovery.hpp"
#include "core/types.hpp"


namespace c2d::core {

/// Where a scene item came from, for error messages about it after parsing.
struct SourceRef {
  std::string where;  ///< "file:line:col: key.path"
};

struct MaterialSpec {
  std::string name;
  double young = 0, poisson = 0, thickness = 1;
  SourceRef at;
};

struct RefineSpec {
  bool segment = false;  ///< refine near a segment p0-p1 (else near the point p0)
  Vec2 p0 = Vec2::Zero(), p1 = Vec2::Zero();
  double size = 0, radius = 0, growth = 1.2;
};

struct ShapeSpec {
  std::string type;  ///< rectangle | polygon | disk | disk_segment | annulus | points
  Vec2 min = Vec2::Zero(), max = Vec2::Zero();  ///< rectangle
  std::vector<Vec2> points;                     ///< polygon (either orientation); points: the cloud
  std::vector<Vec2> boundary;                   ///< points: optional boundary polygon
  Vec2 center = Vec2::Zero();
  double radius = 0, from_deg = 0, to_deg = 360;
  double inner_radius = 0;  ///< annulus: its hole's radius (radius is the outer one)
  /// rectangle, polygon: circular holes (edges hole0, hole1, ...)
  struct Hole {
    Vec2 center = Vec2::Zero();
    double radius = 0;
  };
  std::vector<Hole> holes;
  /// polygon: edges drawn as circular arcs, edge k (points[k] to points[k + 1]) the arc of less
  /// than 180 degrees about `center` between its ends (both at `radius` from it).
  struct Arc {
    int edge = 0;
    Vec2 center = Vec2::Zero();
    double radius = 0;
  };
  std::vector<Arc> arcs;
};

struct BodySpec {
  std::string name, material;
  ShapeSpec shape;
  std::string msh_file;  ///< non-empty: read this Gmsh .msh v4 file instead of meshing a shape
  double mesh_size = 0;
  std::vector<RefineSpec> refine;
  std::string algorithm = "frontal";  ///< frontal | delaunay
  /// Set by the adaptive loop: element sizes from the previous cycle's error estimate, used
  /// instead of mesh_size and refine (gmsh background mesh).
  std::shared_ptr<const SizeField> size_field;
  SourceRef at;
};

/// A set of nodes (and the boundary edges among them), defined by a predicate.
struct SelectionSpec {
  enum class Kind { kBody, kGroup, kEdge, kLine, kSegment, kBox, kArc, kNearest, kNodes };
  Kind kind = Kind::kBody;
  std::string body;   ///< restricts every kind to one body; empty = all bodies
  std::string name;   ///< group or edge name
  Vec2 p0 = Vec2::Zero(), p1 = Vec2::Zero();  ///< line point/direction, segment, box, arc center
  double radius = 0, from_deg = -1e9, to_deg = 1e9;
  double tol = -1;  ///< < 0: 1e-6 x model size
  std::vector<int> nodes;  ///< explicit node ids (legacy files)
  SourceRef at;
};

/// How a load or a prescribed motion grows with the load factor λ: a piecewise-linear table of
/// (λ, a) points from λ = 0 to λ = 1 (the value is a(λ) × its value at 1); empty: a = λ.
using AmplitudeTable = std::vector<std::pair<double, double>>;

/// A rigid rotation prescribed on a support: the nodes follow u(λ) = (R(a θ) − I)(X − c), a = λ
/// or the support's amplitude a(λ).
struct RotationSpec {
  Vec2 center = Vec2::Zero();
  double angle = 0.0;  ///< θ in radians at load factor 1
};

struct SupportSpec {
  SelectionSpec on;
  std::optional<double> ux, uy;  ///< prescribed values (fix = 0)
  std::optional<RotationSpec> rotate;
  AmplitudeTable amplitude;  ///< of its prescribed values (and rotation); empty: λ
  SourceRef at;
};

/// A [[spring]]: to ground on every node of `on` (stiffness k_ground along x and y), or
/// between the single nodes of `a` and `b` (axial stiffness k).
struct SpringSpec {
  std::string name;
  bool to_ground = true;
  SelectionSpec on;            ///< to ground
  Vec2 k_ground = Vec2::Zero();
  SelectionSpec a, b;          ///< node to node
  double k = 0.0;
  SourceRef at;
};

/// A [[plate]] (docs/scene.md): a rigid body with three DOFs, u_x, u_y and θ about `reference`,
/// attached to the boundary edges of `on` wholly (glued) or by their normal component only
/// (frictionless, a flat edge). Each DOF is free (loaded by `force`, `moment`) or prescribed.
struct PlateSpec {
  std::string name;
  SelectionSpec on;
  std::optional<Vec2> reference;  ///< default: the centroid of the attached nodes
  bool normal_only = false;
  Vec2 force = Vec2::Zero();
  double moment = 0.0;
  std::optional<double> ux, uy, rotation;  ///< prescribed (rotation in radians); absent: free
  AmplitudeTable amplitude;  ///< of its prescribed motion, force and moment; empty: λ
  SourceRef at;
};

struct LoadSpec {
  enum class Kind { kNodalForce, kTotalForce, kTraction, kPressure, kBodyForce };
  std::string name;  ///< its `name`, else "loadN" (N from 1)
  Kind kind = Kind::kNodalForce;
  SelectionSpec on;
  Vec2 vector = Vec2::Zero();
  double value = 0;  ///< pressure
  /// A pressure that follows the deformed edge in load-stepped runs (its load stiffness in the
  /// tangent); false: a dead load, fixed at its reference value.
  bool follower = false;
  AmplitudeTable amplitude;  ///< how the load grows with λ; empty: a = λ
  SourceRef at;
};

struct ProbeSpec {
  std::string name, quantity;
  std::optional<Vec2> point;
  std::optional<SelectionSpec> on;
  std::string reduce;  ///< value | max | min | maxabs | sum | mean
  std::string plate;   ///< a [[plate]]'s name, for the plate_* quantities
  SourceRef at;
};

struct AnalysisSpec {
  PlaneState state = PlaneState::kPlaneStress;
  int order = 1;
  bool geometric_nonlinearity = false;
  int steps = 1;
  Smoothing smoothing = Smoothing::kGlobalL2;
  double target_error = 0.05;
  std::string solver = "cholmod";
  /// Multiplies every body's mesh size and refinement sizes (not their radii): the knob of
  /// refinement studies (`contact2d compare --levels` halves it level by level).
  double mesh_scale = 1.0;
  /// Newton iterations per KINSOL solve before a load step is cut back.
  int max_newton_iterations = 25;
  /// Largest mesh, in triangles, a body's sizes may ask for (estimated before meshing).
  /// 0: the default, 2·10⁷ or what the machine's memory holds (core/mesh_budget.hpp).
  double max_elements = 0.0;
};

/// The error-driven adaptive loop (`[adapt]`, or `contact2d run --adapt`): solve, estimate
/// (ZZ), remesh with h_new = h / ξ_e^(1/p), until ξ_g <= 1 or the cycle limit.
struct AdaptSpec {
  bool enabled = false;
  double target = 0.05;    ///< η, the admissible relative error in the energy norm
  int max_cycles = 8;      ///< solves at most (the first mesh included)
  SizeLimits limits;       ///< per-cycle bounds on h_new / h
};

/// An explicit mesh (legacy data files): used instead of meshing bodies.
struct ExplicitModel {
  Mesh mesh;
  std::vector<MaterialSpec> materials;
  /// Node-to-node gap elements (seed type 1): nodes, direction, stiffness.
  struct Gap {
    int node_a, node_b;
    Vec2 direction;
    double stiffness;
  };
  std::vector<Gap> gaps;
};

/// How a VTU file holds its arrays: raw binary appended after the XML (about a tenth of the
/// time and half the size of text, exact, read by ParaView and VTK since 2004) or ASCII text
/// (12 significant digits, readable by eye).
enum class VtuEncoding { kBinary, kAscii };

struct Scene {
  std::string path, title, units;
  AnalysisSpec analysis;
  AdaptSpec adapt;
  std::vector<MaterialSpec> materials;
  std::vector<BodySpec> bodies;
  std::vector<SupportSpec> supports;
  std::vector<LoadSpec> loads;
  std::vector<SpringSpec> springs;
  std::vector<PlateSpec> plates;
  std::vector<ProbeSpec> probes;
  std::string reference_kind;
  std::map<std::string, double> reference;
  std::string output_dir;
  /// [output] fields = false: no VTU series and no nodes.csv; charts = false: no pictures.
  /// summary.json and the CSV tables are always written (a benchmark run wants the figures,
  /// not gnuplot's start-up time).
  bool output_fields = true;
  bool output_charts = true;
  /// [output] vtu = "binary" (raw appended arrays, the default) or "ascii".
  VtuEncoding output_vtu = VtuEncoding::kBinary;
  std::shared_ptr<ExplicitModel> explicit_model;  ///< set for legacy files
  std::shared_ptr<toml::table> raw;              ///< the parsed (overridden) TOML, for later modules
};

/// Reads and validates a scene: TOML by default, the seed's data format for *.dat / *.txt.
/// `overrides` are "key.path=value" strings (--set). Throws InputError on any mistake.
Scene load_scene(const std::string& path, const std::vector<std::string>& overrides = {});

/// Parses TOML text (for tests); `name` is used in messages.
Scene parse_scene(const std::string& text, const std::string& name,
                  const std::vector<std::string>& overrides = {});

class TomlView;
/// Parses a node or edge selection table (shared with the modules that parse their own tables).
SelectionSpec parse_selection(const TomlView& v);

/// Applies one --set override to a TOML table (exposed for tests).
void apply_override(toml::table& root, const std::string& assignment);

/// The tables a dotted key path leads to (`keys`: every key but the value's own): an array of
/// tables fans out to every entry unless an index (`key[i]`, or `key.i` when no entry is named
/// i) or an entry name (`key.NAME`: its `name`, or for contact, constraint, spring, plate and
/// load the default name, `contact1` for the first) picks one. Missing tables are created when
/// `create`, else skipped. Throws InputError, prefixed by `where`, for an index beyond the
/// entries (or into an array the scene does not have) or a key that holds a value, not a table.
std::vector<toml::table*> tables_on_path(toml::table& root, const std::vector<std::string>& keys,
                                         bool create, const std::string& where);

}  // namespace c2d::core
