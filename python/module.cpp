// The Python module's compiled part, contact2d._contact2d: a scene (a file or a dict) run in
// this process through the entry point `contact2d run` uses (app/run/run_scene.hpp), returned
// as the run's summary (a dict, the same as summary.json) with its fields as NumPy arrays. The GIL is released while the scene is
// meshed and solved; bad input raises contact2d.InputError with the command line's located
// message; a file of `out` that cannot be written (a full disk) raises OSError with its errno,
// naming the output folder, and leaves no folder (the command line's exit 3). The pure-Python part
// (contact2d/__init__.py) adds compare and sweep.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <unistd.h>

#include <cstdlib>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <toml++/toml.h>

#include "app/run/run_scene.hpp"
#include "core/errors.hpp"
#include "core/interrupt.hpp"
#include "core/scene.hpp"
#include "core/writers.hpp"

namespace py = pybind11;
using namespace c2d;

namespace {

/// Scenes nest a few levels (a body's shape's refinement list); anything deeper is not a scene
/// and would only exhaust the stack.
constexpr int kMaxDepth = 32;

/// A Python value as a TOML node (dicts are tables, lists of dicts arrays of tables).
toml::table to_table(const py::dict& d, const std::string& path, int depth);

void append(toml::array& a, const py::handle& v, const std::string& path, int depth);

/// A Python int as TOML's 64-bit integer, refused with its path when it does not fit.
std::int64_t integer(const py::handle& v, const std::string& path) {
  int overflow = 0;
  const long long value = PyLong_AsLongLongAndOverflow(v.ptr(), &overflow);
  if (overflow != 0 || (value == -1 && PyErr_Occurred())) {
    PyErr_Clear();
    throw InputError(path + ": expected an integer within 64 bits, found " +
                     std::string(py::str(v)).substr(0, 40));
  }
  return value;
}

void insert(toml::table& t, const std::string& key, const py::handle& v, const std::string& path,
            int depth) {
  if (depth > kMaxDepth)
    throw InputError(path + ": expected a scene nested at most " + std::to_string(kMaxDepth) +
                     " levels deep, found a deeper dict or list");
  if (py::isinstance<py::bool_>(v)) t.insert(key, v.cast<bool>());
  else if (py::isinstance<py::int_>(v)) t.insert(key, integer(v, path));
  else if (py::isinstance<py::float_>(v)) t.insert(key, v.cast<double>());
  else if (py::isinstance<py::str>(v)) t.insert(key, v.cast<std::string>());
  else if (py::isinstance<py::dict>(v))
    t.insert(key, to_table(v.cast<py::dict>(), path, depth + 1));
  else if (py::isinstance<py::list>(v) || py::isinstance<py::tuple>(v)) {
    toml::array a;
    int i = 0;
    for (const py::handle& item : v)
      append(a, item, path + "[" + std::to_string(i++) + "]", depth + 1);
    t.insert(key, std::move(a));
  } else {
    throw InputError(path + ": expected a bool, number, string, list or dict, found " +
                     std::string(py::str(v.get_type().attr("__name__"))));
  }
}

void append(toml::array& a, const py::handle& v, const std::string& path, int depth) {
  toml::table holder;
  insert(holder, "v", v, path, depth);
  a.push_back(std::move(*holder.get("v")));
}

toml::table to_table(const py::dict& d, const std::string& path, int depth) {
  toml::table t;
  for (const auto& [k, v] : d) {
    const std::string key = py::str(k);
    insert(t, key, v, path.empty() ? key : path + "." + key, depth);
  }
  return t;
}

/// The scene: a path, or a dict written out as TOML (named "<dict>" in messages).
core::Scene load(const py::object& scene, const std::vector<std::string>& sets) {
  if (py::isinstance<py::dict>(scene)) {
    std::ostringstream text;
    text << to_table(scene.cast<py::dict>(), "", 0);
    return core::parse_scene(text.str(), "<dict>", sets);
  }
  return core::load_scene(py::str(scene).cast<std::string>(), sets);
}

py::array_t<double> matrix(const double* data, py::ssize_t rows, py::ssize_t cols) {
  py::array_t<double> out({rows, cols});
  std::copy(data, data + rows * cols, out.mutable_data());
  return out;
}

/// The fields of a solved scene as NumPy arrays.
py::dict fields(const app::SceneRun& run) {
  const core::Mesh& mesh = run.model.mesh;
  const py::ssize_t n = mesh.num_nodes(), e = mesh.num_elements(), npe = mesh.nodes_per_element();
  py::dict f;
  std::vector<double> xy;
  for (const Vec2& x : mesh.nodes) xy.insert(xy.end(), {x.x(), x.y()});
  f["nodes"] = matrix(xy.data(), n, 2);
  py::array_t<int> elements({e, npe});
  for (py::ssize_t k = 0; k < e; ++k)
    for (py::ssize_t j = 0; j < npe; ++j) elements.mutable_at(k, j) = mesh.elements[k][j];
  f["elements"] = elements;
  const core::Results& r = run.results;
  if (r.displacement.size() == 2 * n) f["displacement"] = matrix(r.displacement.data(), n, 2);
  if (r.reaction.size() == 2 * n) f["reaction"] = matrix(r.reaction.data(), n, 2);
  if (r.nodal_stress.cols() == n) {  // rows: nodes, columns: σxx, σyy, σxy
    const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> s = r.nodal_stress.transpose();
    f["stress"] = matrix(s.data(), n, 3);
  }
  if (run.contact) {
    const auto& nodes = run.contact_report.nodes;
    const py::ssize_t m = static_cast<py::ssize_t>(nodes.size());
    py::array_t<int> node(m), active(m), state(m);
    py::array_t<double> x({m, py::ssize_t{2}}), gap(m), force(m), pressure(m), tangential(m),
        shear(m), slip(m);
    for (py::ssize_t i = 0; i < m; ++i) {
      const auto& c = nodes[i];
      node.mutable_at(i) = c.node, active.mutable_at(i) = c.active;
      state.mutable_at(i) = static_cast<int>(c.state);
      x.mutable_at(i, 0) = c.x.x(), x.mutable_at(i, 1) = c.x.y();
      gap.mutable_at(i) = c.gap, force.mutable_at(i) = c.force, pressure.mutable_at(i) = c.pressure;
      tangential.mutable_at(i) = c.tangent_force, shear.mutable_at(i) = c.shear;
      slip.mutable_at(i) = c.slip;
    }
    f["contact"] = py::dict(py::arg("node") = node, py::arg("x") = x, py::arg("gap") = gap,
                            py::arg("force") = force, py::arg("pressure") = pressure,
                            py::arg("active") = active, py::arg("tangential_force") = tangential,
                            py::arg("shear") = shear, py::arg("slip") = slip,
                            py::arg("state") = state);
  }
  if (!run.steps.empty()) {  // one entry per attempt, as trace.csv
    std::vector<double> lambda;
    std::vector<int> step, newton, active, stick, slip, converged;
    for (const auto& s : run.steps) {
      lambda.push_back(s.load_factor), step.push_back(s.step);
      newton.push_back(s.newton.iterations);
      converged.push_back(s.newton.status == SolveStatus::kConverged);
      const auto* last = s.contact.empty() ? nullptr : &s.contact.back();
      active.push_back(last ? last->active : 0);
      stick.push_back(last ? last->stick : 0), slip.push_back(last ? last->slip : 0);
    }
    f["attempts"] = py::dict(py::arg("load_factor") = py::array(py::cast(lambda)),
                             py::arg("step") = py::array(py::cast(step)),
                             py::arg("converged") = py::array(py::cast(converged)),
                             py::arg("newton_iterations") = py::array(py::cast(newton)),
                             py::arg("active") = py::array(py::cast(active)),
                             py::arg("stick") = py::array(py::cast(stick)),
                             py::arg("slip") = py::array(py::cast(slip)));
  }
  {  // one entry per converged step, as steps.csv: a load-deflection curve with no work
    const auto& rows = run.step_rows;
    auto column = [&](auto get) {
      std::vector<double> v;
      for (const app::StepRow& r : rows) v.push_back(static_cast<double>(get(r)));
      return py::array(py::cast(v));
    };
    py::dict steps;
    for (const app::StepColumn& c : app::step_columns())
      if (run.contact || !c.contact) steps[c.name] = column(c.value);
    py::dict probes;
    if (!rows.empty())
      for (const auto& [name, value] : rows[0].probes)
        probes[py::str(name)] = column([&, key = name](const app::StepRow& r) { return r.probes.at(key); });
    steps["probes"] = probes;
    f["steps"] = steps;
  }
  return f;
}

/// The caller's Ctrl-C while the GIL is released: asks Python's signal handlers (main thread
/// only) and keeps the exception they raise, to be raised again once the solve has unwound.
class PythonInterrupt {
 public:
  bool poll() {
    py::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() == 0) return false;
    PyErr_Fetch(&type_, &value_, &trace_);
    return true;
  }
  /// Raises the kept exception (KeyboardInterrupt) in Python.
  [[noreturn]] void raise() {
    PyErr_Restore(type_, value_, trace_);
    type_ = value_ = trace_ = nullptr;
    throw py::error_already_set();
  }
  ~PythonInterrupt() {
    Py_XDECREF(type_);
    Py_XDECREF(value_);
    Py_XDECREF(trace_);
  }

 private:
  PyObject *type_ = nullptr, *value_ = nullptr, *trace_ = nullptr;
};

/// contact2d.run: the summary dict, with the fields under "fields".
py::dict run(const py::object& scene_in, const std::string& method,
             const std::vector<std::string>& sets, const std::optional<std::string>& out) {
  if (out && out->empty()) throw InputError("out: expected a folder name, found ''");
  app::RunOptions options;
  options.start = app::RunOutput::Clock::now();
  const core::Scene scene = load(scene_in, sets);
  options.method = method;
  options.out = out.value_or("");
  app::RunResult result;
  PythonInterrupt interrupt;
  bool interrupted = false;
  {
    py::gil_scoped_release release;
    const core::InterruptPoll poll([&] { return interrupt.poll(); });
    try {
      result = app::run_scene(scene, options);
    } catch (const core::Interrupted&) {
      interrupted = true;
    }
  }
  if (interrupted) interrupt.raise();
  py::dict summary = py::module_::import("json").attr("loads")(result.summary.dump());
  summary["fields"] = fields(*result.run);
  return summary;
}

}  // namespace

PYBIND11_MODULE(_contact2d, m) {
  m.doc() = "contact2d's solver, in process (see the contact2d package)";
  py::register_exception<InputError>(m, "InputError", PyExc_ValueError);
  // A write failure is the machine's, not the input's: OSError(errno, message), which Python
  // turns into its subclass for that errno (PermissionError for EACCES, ...).
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const core::WriteError& e) {
      const py::object error =
          py::reinterpret_borrow<py::object>(PyExc_OSError)(e.error_number(), e.what());
      PyErr_SetObject(reinterpret_cast<PyObject*>(Py_TYPE(error.ptr())), error.ptr());
    }
  });
  m.def("run", &run, py::arg("scene"), py::arg("method") = "",
        py::arg("set") = std::vector<std::string>{}, py::arg("out") = std::nullopt,
        "Solves a scene (a path or a dict) and returns its summary with the fields.");
  m.def("to_toml", [](const py::dict& scene) {
        std::ostringstream text;
        text << to_table(scene, "", 0);
        return text.str();
      }, py::arg("scene"), "A dict scene as the TOML text a scene file holds (for the studies).");
  m.def("executable", [] {
        // The environment's C2D_EXECUTABLE, else the build tree's program, else the installed.
        if (const char* env = std::getenv("C2D_EXECUTABLE"); env && *env) return std::string(env);
        for (const char* path : {C2D_EXECUTABLE, C2D_INSTALLED_EXECUTABLE})
          if (::access(path, X_OK) == 0) return std::string(path);
        return std::string("contact2d");
      }, "The contact2d program the studies run.");
}
