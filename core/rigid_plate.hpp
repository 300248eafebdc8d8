// Rigid plates and caps ([[plate]], docs/scene.md): their scene tables, their three DOFs in the
// model's numbering, their prescribed motion and their loads. The rows that attach them to the
// structure are equality rows of the constraints module (constraints/equalities/rigid_plate.hpp).
#pragma once

#include "core/model.hpp"
#include "core/scene.hpp"
#include "core/toml_view.hpp"

namespace c2d::core {

/// Parses one [[plate]] table (the `index`th: its default name).
PlateSpec parse_plate(const TomlView& v, int index);

/// The scene's plates on the model's mesh: attached nodes, outward normal (a plate attached by
/// the normal component needs a straight edge), reference point and DOF numbers after the
/// nodes' (call before the DOF map is made). Throws InputError, located at the plate.
void add_plates(const Scene& scene, Model& model);

/// Prescribes the plates' fixed components in the DOF map (before it is finalised).
void prescribe_plates(const Scene& scene, Model& model);

/// Adds the plates' forces and moments to the model's loads (external_force, or a load of its
/// own under the plate's amplitude).
void add_plate_loads(const Scene& scene, Model& model);

}  // namespace c2d::core
