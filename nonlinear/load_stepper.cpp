#include "nonlinear/load_stepper.hpp"

#include <algorithm>
#include <cmath>
#include <memory>

#include "core/error_estimator.hpp"
#include "core/stopwatch.hpp"
#include "core/stress_recovery.hpp"
#include "nonlinear/finite_strain_system.hpp"

namespace c2d::nonlinear {

using namespace c2d::core;

Results solve_geometric_nonlinear(const Model& model, const AnalysisSpec& analysis,
                                  const StepperOptions& options, std::vector<StepRecord>* trace,
                                  const constraints::ContactSet* contact,
                                  constraints::ContactReport* contact_report) {
  using constraints::ContactReport;
  const Stopwatch run_clock;
  const DofMap& dofs = model.dofs;
  const Mesh& mesh = model.mesh;
  auto prescribe = [&](double lambda) {
    VecX u = VecX::Zero(mesh.num_dofs());
    if (options.prescribe) options.prescribe(lambda, u);
    else u = prescribed_displacement(model, lambda);
    return u;
  };
  FiniteStrainSystem system(model);
  const bool with_contact = contact && !contact->empty();
  std::unique_ptr<constraints::ConstraintStrategy> strategy;
  if (with_contact) strategy = constraints::ConstraintStrategy::create(contact->options());
  // Residuals are measured against the largest nodal force in the system (load, reaction or
  // contact force); a displacement-driven problem free of stress falls back to the force of a
  // 1e-6 strain on the smallest element edge.
  double e_t = 0.0;
  for (const auto& m : model.materials) e_t = std::max(e_t, m.young * m.thickness);
  const double floor_scale = 1e-6 * e_t * mesh.edge_length_range().first;

  Results r;
  r.time.mesh = model.mesh_seconds;
  // The converged state: everything a failed attempt must not touch. An attempt works on
  // copies (its trial displacements, its own detection, active set, multipliers and penalties),
  // so a cutback restarts from exactly this.
  VecX u_free = VecX::Zero(dofs.num_free());
  VecX u_prev_full = prescribe(0.0);
  double lambda = 0.0;
  ContactMemory memory(with_contact ? contact->num_slots() : 0, 0);
  ContactReport last_contact;
  last_contact.method = strategy ? strategy->name() : "";
  // The fields of a converged state: displacement, reactions, stresses (smoothed, ZZ estimate)
  // and the contact fields. For the final results and, on request, every converged step (the
  // last of which then is the final results).
  Results last_state;
  bool have_state = false;
  double recovery_seconds = 0.0, output_seconds = 0.0;  // spent on on_state, not on solving
  auto fill_state = [&](Results& out, double lam, const VecX& u_full,
                        const ContactReport* contact_state) {
    system.set_state(lam, u_full);
    out.displacement = u_full;
    VecX f_int;
    system.internal_force(out.displacement, f_int);
    out.reaction = VecX::Zero(mesh.num_dofs());
    for (int dof = 0; dof < mesh.num_dofs(); ++dof)
      if (dofs.is_constrained(dof)) out.reaction[dof] = f_int[dof] - lam * model.external_force[dof];
    out.element_stresses = compute_element_stresses(mesh, model.materials, out.displacement, true);
    out.nodal_stress = smooth_stresses(mesh, model.materials, out.element_stresses, analysis.smoothing);
    out.error = estimate_error(mesh, model.materials, out.element_stresses, out.nodal_stress,
                               analysis.target_error);
    out.globals["load_factor"] = lam;
    if (contact_state) store_contact_results(*contact_state, mesh.num_nodes(), out);
  };

  const double nominal = 1.0 / std::max(1, options.steps);
  double increment = nominal;
  int converged_steps = 0, cutbacks = 0;
  r.status = SolveStatus::kConverged;
  while (lambda < 1.0 - 1e-12) {
    const Stopwatch step_clock;
    const double target = std::min(1.0, lambda + increment);
    const VecX u_target = prescribe(target);
    StepRecord rec;
    rec.load_factor = target;
    rec.attempt = cutbacks;
    const double load_scale =
        system.f_ext_free().size() ? target * system.f_ext_free().cwiseAbs().maxCoeff() : 0.0;
    VecX trial;
    ContactStepResult cstep;
    system.set_state(target, u_target);
    if (with_contact) {
      ContactStepInput in;
      in.u_free = u_free;
      in.u_prev_full = u_prev_full;
      in.memory = memory;
      in.newton = options.newton;
      in.newton.residual_scale = load_scale;
      in.floor_scale = floor_scale;
      cstep = solve_contact_step(system, *contact, *strategy, in);
      rec.newton = cstep.newton;
      rec.newton.status = cstep.status;
      rec.newton.message = cstep.message;
      rec.contact = cstep.iterations;
      trial = cstep.u_free;
    } else {
      // Linear predictor from the last converged state: K_T Δu_f = λ f − f_int − K_fc Δu_c.
      VecX guess = u_free, rhs, step;
      if (system.step_predictor(u_prev_full, rhs) && system.factorize_jacobian_assembled() &&
          system.solve(rhs, step) && step.allFinite())
        guess = u_free + step;
      NewtonOptions newton = options.newton;
      newton.residual_scale = std::max({load_scale, system.reaction_scale(guess), floor_scale});
      trial = guess;
      rec.newton = solve_newton_with_fallback(system, trial, newton);
    }
    rec.seconds = step_clock.elapsed();
    const bool ok = rec.newton.status == SolveStatus::kConverged;
    bool give_up = false;
    if (ok) {
      ++converged_steps;
      u_free = trial;
      u_prev_full = system.full(u_free);
      lambda = target;
      if (with_contact) {
        strategy->step_accepted();
        memory = cstep.memory;
        last_contact.status = SolveStatus::kConverged;
        contact->report(cstep.rows, cstep.state, last_contact);
        rec.contact_state = last_contact;
      }
      // After a cutback, grow back toward the nominal increment once a step comes easily.
      if (cutbacks > 0 && rec.newton.iterations <= 4) increment = std::min(nominal, 2.0 * increment);
      cutbacks = 0;
    } else if (rec.newton.status == SolveStatus::kIllConditioned) {
      give_up = true;  // a penalty beyond what double precision resolves: no step size cures it
    } else if (cutbacks < options.max_cutbacks) {
      if (with_contact) strategy->step_rejected();
      ++cutbacks;
      increment *= 0.5;
    } else {
      give_up = true;
    }
    rec.step = converged_steps;
    if (with_contact) {
      for (const auto& it : rec.contact) {
        last_contact.iterations += it.strategy_iterations;
        ++last_contact.detection_passes;
        constraints::IterationRecord h;
        h.iteration = static_cast<int>(last_contact.history.size()) + 1;
        h.active = it.active;
        h.entering = it.entering;
        h.leaving = it.leaving;
        h.max_penetration = it.max_penetration;
        h.penalty = it.penalty;
        h.residual = it.newton.final_residual;
        last_contact.history.push_back(h);
      }
    }
    if (trace) trace->push_back(rec);
    if (options.on_step) options.on_step(rec);
    if (ok && options.on_state) {
      Stopwatch clock;
      last_state = Results();
      last_state.status = SolveStatus::kConverged;
      fill_state(last_state, lambda, u_prev_full, with_contact ? &last_contact : nullptr);
      last_state.globals["steps"] = converged_steps;
      recovery_seconds += clock.lap();
      options.on_state(rec, last_state);
      output_seconds += clock.lap();
      have_state = true;
    }
    if (!ok && give_up) {
      r.status = rec.newton.status;
      r.message = "load step to λ = " + std::to_string(target) + " failed after " +
                  std::to_string(cutbacks) + " cutbacks (" + rec.newton.message + ")";
      break;
    }
  }
  r.time.solve = run_clock.elapsed() - recovery_seconds - output_seconds;
  r.time.output = output_seconds;
  r.solver = system.linear_report();
  const Stopwatch recovery_clock;
  if (have_state) {
    // The last converged step's fields, recovered for on_state already.
    r.displacement = std::move(last_state.displacement);
    r.reaction = std::move(last_state.reaction);
    r.element_stresses = std::move(last_state.element_stresses);
    r.nodal_stress = std::move(last_state.nodal_stress);
    r.error = std::move(last_state.error);
    r.point_fields = std::move(last_state.point_fields);
    for (const auto& [key, value] : last_state.globals) r.globals[key] = value;
  } else {
    fill_state(r, lambda, u_prev_full, with_contact ? &last_contact : nullptr);
  }
  r.globals["steps"] = converged_steps;
  if (with_contact) {
    last_contact.status = r.status;
    last_contact.message = r.message;
    r.solver.backend = last_contact.method;
    if (contact_report) *contact_report = last_contact;
  }
  r.time.recovery = recovery_seconds + recovery_clock.elapsed();
  return r;
}

}  // namespace c2d::nonlinear
