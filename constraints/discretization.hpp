// How a [[contact]] pair becomes gap rows: a discretization owns the pair's slave points and,
// at any configuration, produces the row of each slot it finds (slots are the pair's stable row
// identities across detections). One class per discretization in constraints/discretizations/,
// one line in the registry of discretization.cpp; ContactPairs holds one per pair.
#pragma once

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "constraints/contact_detection.hpp"
#include "constraints/gap_linearisation.hpp"
#include "constraints/contact_scene.hpp"
#include "core/model.hpp"

namespace c2d::constraints {

/// Where rows are evaluated. Finite strain (load-stepped runs): everything at the current
/// positions x. Small strain (a linear analysis): which master edge or point a slave meets is
/// found at the current positions, so a slave may slide past a segment end, but normals and
/// integration measures are the reference configuration's, so every row is linear in u and the
/// row forces sum to the force transmitted.
struct Configuration {
  const std::vector<Vec2>& x;          ///< current positions (reference + displacement)
  const std::vector<Vec2>& reference;  ///< the mesh's node positions
  bool small_strain = false;
  const VecX* u = nullptr;  ///< the displacement (2 per node) x was formed from, when known
  /// Finite strain: the rows' curvature (their Hessian, for the contact's geometric stiffness)
  /// too, else their values and gradients only (a residual's needs; curvature left empty).
  bool curvature = true;

  /// The positions for exact gap derivatives (displacement kept apart when known).
  Positions positions() const { return u ? Positions{reference, u} : Positions{x, nullptr}; }
};

class ContactDiscretization {
 public:
  virtual ~ContactDiscretization() = default;
  /// Row slots of the pair: the slot of row k is first_slot + (its index among the slots).
  virtual int num_slots() const = 0;
  /// The nodes whose rows this pair produces (each may appear in several pairs).
  virtual const std::vector<int>& slave_nodes() const = 0;
  /// Appends the rows found in configuration `c`, numbered from `first_slot`.
  virtual void detect(const Configuration& c, int first_slot, std::vector<GapRow>& rows) const = 0;
};

/// What a discretization is built from: the model, its pair's table, the scene's obstacles,
/// and the pair's index (GapRow::pair).
struct DiscretizationInput {
  const core::Model& model;
  const ContactPairSpec& pair;
  const std::vector<Obstacle>& obstacles;
  int index = 0;
};

struct DiscretizationInfo {
  std::string name;     ///< the value of a [[contact]]'s `detection`
  std::string summary;  ///< one line for the docs
  bool obstacles = false;  ///< accepts a rigid obstacle as master
  /// The slave selection must hold boundary edges (the surface the pressure is recovered on);
  /// else a selection of nodes alone is enough.
  bool slave_surface = true;
  std::unique_ptr<ContactDiscretization> (*create)(const DiscretizationInput&) = nullptr;
};

/// The nodes of `nodes` on the mesh's boundary, in their order: a contact's slave nodes, whatever
/// the selection (a box or a near_line also holds interior nodes, which no contact reaches; a
/// box slave once took 1,196 nodes where ~150 were on the surface, p_max +16 %).
std::vector<int> on_boundary(const core::Mesh& mesh, const std::vector<int>& nodes);

/// Every registered discretization, in the order the docs list them.
const std::vector<DiscretizationInfo>& discretization_registry();
/// The registered discretization of that name, or nullptr.
const DiscretizationInfo* find_discretization(std::string_view name);
/// The registered names.
const std::vector<std::string>& discretization_names();
/// The detection table of docs/scene.md (Markdown).
std::string discretization_table_markdown();

}  // namespace c2d::constraints
