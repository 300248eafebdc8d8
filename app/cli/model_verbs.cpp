// The verbs that mesh a scene without solving it: mesh and info.
#include <filesystem>
#include <iostream>

#include "app/cli/verbs.hpp"
#include "app/output_folder.hpp"
#include "constraints/contact_scene.hpp"
#include "constraints/contact_set.hpp"
#include "core/errors.hpp"
#include "core/model.hpp"
#include "core/probes.hpp"
#include "core/writers.hpp"

namespace c2d::app {

std::string default_out(const Options& o, const core::Scene& scene) {
  if (!o.out.empty()) return o.out;
  if (!scene.output_dir.empty()) return scene.output_dir;
  return "out/" + std::filesystem::path(o.scene).stem().string();
}

namespace {

/// ", staged: a = a0 at λ0, a1 at λ1, ..." for a table with an amplitude; "" without (a = λ).
std::string amplitude_text(const core::AmplitudeTable& table) {
  if (table.empty()) return "";
  std::string text = ", staged: a =";
  for (size_t k = 0; k < table.size(); ++k)
    text += (k ? ", " : " ") + number_text(table[k].second) + " at λ " +
            number_text(table[k].first);
  return text;
}

/// The model, with every table checked as a run checks it before solving, in the same order and
/// with the same messages (solve_scene): [[contact]], [[constraint]] and their friction tables,
/// their selections on the mesh, and the probes. info and mesh exited 0 on tables a run refused
/// (issue 32, finding 9), so they could not check a scene.
core::Model checked_model(const Options& o, const core::Scene& scene) {
  const constraints::ContactSceneSpec contact = constraints::parse_contact_scene(scene, o.method);
  core::Model model = core::build_model(scene);
  if (!contact.empty() || !model.plates.empty() ||
      (scene.explicit_model && !scene.explicit_model->gaps.empty()))
    const constraints::ContactSet resolved(model, contact, scene);  // pairs and constraints
  else if (!o.method.empty())
    throw InputError("--method " + o.method + ": the scene has no [[contact]] to enforce");
  // A probe point outside the mesh is refused when the probes are evaluated.
  core::evaluate_probes(scene, model,
                        core::Results::zeros(model.mesh.num_nodes(), model.mesh.num_elements(),
                                             model.mesh.nodes_per_element()));
  return model;
}

}  // namespace

int cmd_mesh(const Options& o) {
  const core::Scene scene = core::load_scene(o.scene, o.sets);
  const core::Model model = checked_model(o, scene);
  const std::string out = default_out(o, scene);
  create_output_folder(out);
  const core::Results empty = core::Results::zeros(
      model.mesh.num_nodes(), model.mesh.num_elements(), model.mesh.nodes_per_element());
  core::write_file_atomic(out + "/mesh.vtu", core::vtu_document(model, empty, scene.output_vtu));
  const auto [hmin, hmax] = model.mesh.edge_length_range();
  std::cout << (model.mesh.order == 1 ? "T3" : "T6") << " mesh: " << model.mesh.num_nodes()
            << " nodes, " << model.mesh.num_elements() << " elements, " << model.mesh.num_dofs()
            << " DOFs (" << model.dofs.num_free() << " free), edge length " << hmin << " .. "
            << hmax << ", " << model.mesh_seconds << " s\n";
  const auto [min_angle, skinny] = model.mesh.angle_quality();
  std::cout << "quality    smallest angle " << min_angle << " deg";
  if (skinny > 0)
    std::cout << "; warning: " << skinny << " skinny triangle" << (skinny == 1 ? "" : "s")
              << " (an angle below 15 deg)";
  std::cout << "\nwrote " << out << "/mesh.vtu\n";
  return kExitOk;
}

int cmd_info(const Options& o) {
  const core::Scene scene = core::load_scene(o.scene, o.sets);
  const core::Model model = checked_model(o, scene);
  std::cout << "scene      " << scene.path << (scene.title.empty() ? "" : " - " + scene.title)
            << "\nunits      " << (scene.units.empty() ? "(not stated)" : scene.units)
            << "\nanalysis   "
            << (scene.analysis.state == core::PlaneState::kPlaneStrain ? "plane strain"
                                                                       : "plane stress")
            << ", " << (model.mesh.order == 1 ? "T3" : "T6") << "\nmesh       "
            << model.mesh.num_nodes() << " nodes, " << model.mesh.num_elements() << " elements, "
            << model.dofs.num_free() << " free DOFs of " << model.mesh.num_dofs() << "\n";
  for (const auto& m : model.materials)
    std::cout << "material   " << m.name << ": E = " << m.young << ", nu = " << m.poisson
              << ", t = " << m.thickness << "\n";
  for (size_t b = 0; b < model.body_names.size(); ++b) {
    int elements = 0;
    for (int id : model.mesh.element_body) elements += id == static_cast<int>(b);
    std::cout << "body       " << model.body_names[b] << ": " << elements << " elements\n";
  }
  for (const auto& [name, ids] : model.mesh.edge_groups)
    std::cout << "edge set   " << name << ": " << ids.size() << " edges\n";
  for (const auto& [name, ids] : model.mesh.node_groups)
    std::cout << "node set   " << name << ": " << ids.size() << " nodes\n";
  for (const auto& s : scene.supports)
    std::cout << "support    " << s.at.where << ": " << core::select_nodes(model, s.on).size()
              << " nodes" << amplitude_text(s.amplitude) << "\n";
  for (const auto& l : scene.loads)
    std::cout << "load       " << l.name << " (" << l.at.where
              << "): " << core::select_nodes(model, l.on).size() << " nodes"
              << amplitude_text(l.amplitude) << "\n";
  for (const auto& p : scene.plates)
    std::cout << "plate      " << p.name << " (" << p.at.where
              << "): " << core::select_nodes(model, p.on).size() << " nodes"
              << amplitude_text(p.amplitude) << "\n";
  for (const auto& p : scene.probes)
    std::cout << "probe      " << p.name << " (" << p.quantity << ")"
              << (p.on ? ": " + std::to_string(core::select_nodes(model, *p.on).size()) + " nodes"
                       : std::string(""))
              << "\n";
  return kExitOk;
}

}  // namespace c2d::app
