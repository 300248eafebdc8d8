#include "nonlinear/load_stepper.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "core/assembler.hpp"
#include "core/error_estimator.hpp"
#include "core/finite_strain_kernels.hpp"
#include "core/spd_solver.hpp"
#include "core/stress_recovery.hpp"

namespace c2d::nonlinear {

using namespace c2d::core;

namespace {

/// R(u_f) = f_int(u) − λ f_ext on the free DOFs, u the full vector with the prescribed values of
/// the current load factor; Jacobian K_T,ff.
class FiniteStrainSystem final : public NewtonSystem {
 public:
  explicit FiniteStrainSystem(const Model& model)
      : model_(model), assembler_(model.mesh, model.dofs),
        f_ext_free_(model.dofs.restrict(model.external_force)) {}

  void set_state(double lambda, const VecX& u_prescribed) {
    lambda_ = lambda;
    u_prescribed_ = u_prescribed;
  }
  VecX full(const VecX& u_free) const {
    VecX u = u_prescribed_;
    for (int dof = 0; dof < model_.dofs.num_dofs(); ++dof) {
      const int eq = model_.dofs.equation(dof);
      if (eq >= 0) u[dof] = u_free[eq];
    }
    return u;
  }
  /// Full internal force vector at a full displacement; false if an element is inverted.
  bool internal_force(const VecX& u, VecX& f) const {
    const Mesh& mesh = model_.mesh;
    const int nn = mesh.nodes_per_element();
    f = VecX::Zero(mesh.num_dofs());
    LocalVector ue(2 * nn), fe;
    for (int e = 0; e < mesh.num_elements(); ++e) {
      for (int i = 0; i < nn; ++i) ue.segment<2>(2 * i) = u.segment<2>(2 * mesh.elements[e][i]);
      if (!finite_strain_element(mesh.element_coords(e), ue,
                                 model_.materials[mesh.element_material[e]], &fe, nullptr))
        return false;
      for (int i = 0; i < nn; ++i) f.segment<2>(2 * mesh.elements[e][i]) += fe.segment<2>(2 * i);
    }
    return true;
  }
  bool residual(const VecX& u_free, VecX& r) override {
    VecX f;
    if (!internal_force(full(u_free), f)) return false;
    r = model_.dofs.restrict(f) - lambda_ * f_ext_free_;
    return true;
  }
  /// Assembles K_T,ff at u (full); with `du_constrained`, also lift = K_fc du_c.
  bool assemble_tangent(const VecX& u, const VecX* du_constrained, VecX* lift) {
    const Mesh& mesh = model_.mesh;
    const int nn = mesh.nodes_per_element();
    bool ok = true;
    LocalVector ue(2 * nn);
    assembler_.assemble(
        [&](int e, LocalMatrix& ke) {
          for (int i = 0; i < nn; ++i) ue.segment<2>(2 * i) = u.segment<2>(2 * mesh.elements[e][i]);
          if (!finite_strain_element(mesh.element_coords(e), ue,
                                     model_.materials[mesh.element_material[e]], nullptr, &ke)) {
            ok = false;
            ke = LocalMatrix::Zero(2 * nn, 2 * nn);
          }
        },
        du_constrained, lift);
    return ok && solver_.factorize(assembler_.matrix()) == SolveStatus::kConverged;
  }
  bool factorize_jacobian(const VecX& u_free) override {
    return assemble_tangent(full(u_free), nullptr, nullptr);
  }
  bool solve(const VecX& b, VecX& x) override {
    return solver_.solve(b, x) == SolveStatus::kConverged;
  }
  const VecX& f_ext_free() const { return f_ext_free_; }
  const SpdSolveReport& linear_report() const { return solver_.report(); }

 private:
  const Model& model_;
  Assembler assembler_;
  SpdSolver solver_;
  VecX f_ext_free_, u_prescribed_;
  double lambda_ = 0.0;
};

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

Results solve_geometric_nonlinear(const Model& model, const AnalysisSpec& analysis,
                                  const StepperOptions& options, std::vector<StepRecord>* trace) {
  const auto t_start = std::chrono::steady_clock::now();
  const DofMap& dofs = model.dofs;
  const Mesh& mesh = model.mesh;
  auto prescribe = [&](double lambda) {
    VecX u = VecX::Zero(mesh.num_dofs());
    if (options.prescribe) options.prescribe(lambda, u);
    else u = dofs.expand(VecX::Zero(dofs.num_free()), lambda);
    return u;
  };
  FiniteStrainSystem system(model);
  // Residuals are measured against the largest nodal force in the system (load or reaction);
  // a displacement-driven problem free of stress falls back to the force of a 1e-6 strain on the
  // smallest element edge.
  double e_t = 0.0;
  for (const auto& m : model.materials) e_t = std::max(e_t, m.young * m.thickness);
  const double floor_scale = 1e-6 * e_t * mesh.edge_length_range().first;

  Results r;
  r.time.mesh = model.mesh_seconds;
  VecX u_free = VecX::Zero(dofs.num_free());
  VecX u_prev_full = prescribe(0.0);
  double lambda = 0.0;
  const double nominal = 1.0 / std::max(1, options.steps);
  double increment = nominal;
  int converged_steps = 0, cutbacks = 0;
  r.status = SolveStatus::kConverged;
  while (lambda < 1.0 - 1e-12) {
    const auto t_step = std::chrono::steady_clock::now();
    const double target = std::min(1.0, lambda + increment);
    const VecX u_target = prescribe(target);
    // Linear predictor from the last converged state: K_T Δu_f = λ f − f_int − K_fc Δu_c.
    VecX guess = u_free;
    double reaction_scale = 0.0;
    {
      VecX du = u_target - u_prev_full, lift, f_int;
      for (int dof = 0; dof < mesh.num_dofs(); ++dof)
        if (!dofs.is_constrained(dof)) du[dof] = 0.0;
      system.set_state(lambda, u_prev_full);
      if (system.internal_force(u_prev_full, f_int) &&
          system.assemble_tangent(u_prev_full, &du, &lift)) {
        VecX step;
        const VecX rhs = target * system.f_ext_free() - dofs.restrict(f_int) - lift;
        if (system.solve(rhs, step) && step.allFinite()) guess = u_free + step;
      }
    }
    system.set_state(target, u_target);
    {
      // Reactions at the predicted state: the force scale of supports carrying the load.
      VecX f_int;
      if (system.internal_force(system.full(guess), f_int))
        for (int dof = 0; dof < mesh.num_dofs(); ++dof)
          if (dofs.is_constrained(dof)) reaction_scale = std::max(reaction_scale, std::abs(f_int[dof]));
    }
    NewtonOptions newton = options.newton;
    const double load_scale =
        system.f_ext_free().size() ? target * system.f_ext_free().cwiseAbs().maxCoeff() : 0.0;
    newton.residual_scale = std::max({load_scale, reaction_scale, floor_scale});
    StepRecord rec;
    rec.load_factor = target;
    rec.attempt = cutbacks;
    // Full Newton steps first: on slender structures the residual may rise for one iteration
    // before it collapses, which a line search mistakes for divergence. The line search is the
    // fallback before a cutback.
    VecX trial = guess;
    newton.line_search = false;
    rec.newton = solve_newton(system, trial, newton);
    if (rec.newton.status != SolveStatus::kConverged && options.newton.line_search) {
      trial = guess;
      NewtonReport plain = rec.newton;
      newton.line_search = true;
      rec.newton = solve_newton(system, trial, newton);
      rec.newton.iterations += plain.iterations;
      rec.newton.residual_norms.insert(rec.newton.residual_norms.begin(),
                                       plain.residual_norms.begin(), plain.residual_norms.end());
    }
    rec.seconds = seconds_since(t_step);
    const bool ok = rec.newton.status == SolveStatus::kConverged;
    if (ok) {
      ++converged_steps;
      u_free = trial;
      u_prev_full = system.full(u_free);
      lambda = target;
      // After a cutback, grow back toward the nominal increment once a step comes easily.
      if (cutbacks > 0 && rec.newton.iterations <= 4) increment = std::min(nominal, 2.0 * increment);
      cutbacks = 0;
    } else if (cutbacks < options.max_cutbacks) {
      ++cutbacks;  // the snapshot is u_free / u_prev_full / lambda, untouched by the attempt
      increment *= 0.5;
    }
    rec.step = converged_steps;
    if (trace) trace->push_back(rec);
    if (options.on_step) options.on_step(rec);
    if (!ok && rec.attempt >= options.max_cutbacks) {
      r.status = rec.newton.status;
      r.message = "load step to λ = " + std::to_string(target) + " failed after " +
                  std::to_string(options.max_cutbacks) + " cutbacks (" + rec.newton.message + ")";
      break;
    }
  }
  r.time.solve = seconds_since(t_start);
  r.solver = system.linear_report();
  const auto t_rec = std::chrono::steady_clock::now();
  system.set_state(lambda, u_prev_full);
  r.displacement = u_prev_full;
  VecX f_int;
  system.internal_force(r.displacement, f_int);
  r.reaction = VecX::Zero(mesh.num_dofs());
  for (int dof = 0; dof < mesh.num_dofs(); ++dof)
    if (dofs.is_constrained(dof)) r.reaction[dof] = f_int[dof] - lambda * model.external_force[dof];
  r.element_stresses = compute_element_stresses(mesh, model.materials, r.displacement, true);
  r.nodal_stress = smooth_stresses(mesh, model.materials, r.element_stresses, analysis.smoothing);
  r.error = estimate_error(mesh, model.materials, r.element_stresses, r.nodal_stress,
                           analysis.target_error);
  r.globals["load_factor"] = lambda;
  r.globals["steps"] = converged_steps;
  r.time.recovery = seconds_since(t_rec);
  return r;
}

}  // namespace c2d::nonlinear
