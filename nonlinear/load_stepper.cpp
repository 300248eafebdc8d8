#include "nonlinear/load_stepper.hpp"

#include <algorithm>
#include <cmath>
#include <memory>

#include "core/error_estimator.hpp"
#include "core/errors.hpp"
#include "core/interrupt.hpp"
#include "core/stopwatch.hpp"
#include "core/stress_recovery.hpp"
#include "nonlinear/structural_system.hpp"

namespace c2d::nonlinear {

using namespace c2d::core;

namespace {

/// The load-step driver's state and its named steps: attempt a step (with contact through the
/// constrained step, else Newton from a linear predictor), accept it or cut it back, record it,
/// and recover the fields of a converged state.
class LoadStepper {
 public:
  LoadStepper(StructuralSystem& system, const AnalysisSpec& analysis,
              const StepperOptions& options, std::vector<StepRecord>* trace,
              const constraints::ContactSet* contact)
      : assemble_before_(system.assemble_seconds()), model_(system.model()), analysis_(analysis),
        options_(options), trace_(trace),
        contact_(contact), system_(system), with_contact_(contact && !contact->empty()),
        floor_scale_(residual_floor_scale(model_)),
        u_free_(VecX::Zero(model_.dofs.num_free())), u_prev_full_(prescribe(0.0)),
        nominal_(1.0 / std::max(1, options.steps)),
        smallest_(nominal_ / std::ldexp(1.0, std::clamp(options.max_cutbacks, 0, 40))),
        max_attempts_(options.max_attempts > 0
                          ? options.max_attempts
                          : static_cast<long>(std::min(2.0 / smallest_ + 100.0, 1e7))),
        increment_(nominal_) {
    if (with_contact_) strategy_ = constraints::ConstraintStrategy::create(contact->options());
    last_contact_.method = strategy_ ? strategy_->name() : "";
    const SpMat& k = system_.matrix();  // a small-strain K; a finite-strain K_T at u = 0
    if (with_contact_ && system_.is_linear() && k.nonZeros())
      last_contact_.stiffness_max = k.coeffs().cwiseAbs().maxCoeff();
    r_.time.mesh = model_.mesh_seconds;
    r_.status = SolveStatus::kConverged;
  }

  Results run(constraints::ContactReport* contact_report) {
    while (lambda_ < 1.0 - 1e-12)
      if (!step()) break;
    return finish(contact_report);
  }

 private:
  /// Prescribed displacements at load factor λ (full vector).
  VecX prescribe(double lambda) const {
    if (!options_.prescribe) return system_.prescribed(lambda);
    VecX u = VecX::Zero(model_.dofs.num_dofs());
    options_.prescribe(lambda, u);
    return u;
  }

  /// One attempt; false when the analysis gives up.
  bool step() {
    core::check_interrupt();
    if (++attempts_ > max_attempts_) {
      r_.status = SolveStatus::kStalled;
      r_.message = "load stepping stopped at λ = " + number_text(lambda_) + " after " +
                   std::to_string(max_attempts_) + " attempts (the bound on attempts)";
      return false;
    }
    const Stopwatch step_clock;
    const double target = std::min(1.0, lambda_ + increment_);
    StepRecord rec;
    rec.load_factor = target;
    rec.attempt = cutbacks_;
    // An attempt works on copies (its trial displacements, its own detection, active set,
    // multipliers and penalties), so a cutback restarts from exactly the converged state.
    ContactStepResult cstep;
    const VecX trial = attempt(target, rec, cstep);
    rec.seconds = step_clock.elapsed();
    const bool ok = rec.newton.status == SolveStatus::kConverged;
    // The lowest load at which an attempt inverted an element, kept until a step gets past it:
    // near a limit point the steps crawl up to it while the larger attempts crush an element,
    // and whether the last attempt itself inverts or meets the singular tangent is round-off.
    if (!ok && (inverted_at_.empty() || target < inverted_lambda_))
      if (std::string at = inversion(target, rec, cstep); !at.empty()) {
        inverted_at_ = std::move(at);
        inverted_lambda_ = target;
      }
    bool give_up = false;
    if (ok) accept(target, trial, cstep, rec);
    else if (extrapolated_ && rec.newton.status != SolveStatus::kIllConditioned)
      retry_from_predictor();  // the same increment again, from the tangent predictor
    else if (rec.newton.status == SolveStatus::kIllConditioned)
      give_up = true;  // a penalty beyond what double precision resolves: no step size cures it
    else if (rec.newton.status == SolveStatus::kCycling && with_contact_ && !strict_ &&
             strategy_->exact())  // (a regularised method's steps are strict already)
      strict_ = true;  // the same increment again, each method step taken further (below)
    else if (increment_ > smallest_ * (1 + 1e-9)) cut_back();
    else give_up = true;  // the smallest increment failed
    rec.step = converged_steps_;
    if (with_contact_) record_contact_history(rec, cstep);
    if (trace_) trace_->push_back(rec);
    if (options_.on_step) options_.on_step(rec);
    if (ok && options_.on_state) emit_state(rec);
    if (!ok && give_up) {
      r_.status = rec.newton.status;
      std::string why = rec.newton.message;
      // The load crushes an element: an attempt of this step inverted one (its Newton solve, or
      // the contact method's trial state), and the smaller steps then stopped on what comes
      // before inversion (a singular tangent at the limit point, a method's iteration cap).
      // Not when the smallest step from the unloaded state found the tangent singular: a body
      // free to move (a missing support) or a mechanism, whose displacements at a larger
      // increment were the singular solve's, inverting an element on the way.
      const bool singular_unloaded = lambda_ == 0.0 && r_.status == SolveStatus::kSingular;
      if (r_.status != SolveStatus::kInvertedElement && !inverted_at_.empty()) {
        if (singular_unloaded) {
          why +=
              "; singular from the unloaded state on (a body free to move, or a mechanism): "
              "a larger increment's displacements inverted an element (" +
              inverted_at_ + ")";
        } else {
          r_.status = SolveStatus::kInvertedElement;
          why = inverted_at_ + "; the smaller steps ended: " + why;
        }
      }
      // Attempts from the converged state (the increment may have stayed at its smallest
      // since an earlier cutback: "after 1 cutbacks" then hid that it could not be cut again).
      r_.message = "load step to λ = " + number_text(target) + " from λ = " + number_text(lambda_) +
                   " failed after " + std::to_string(cutbacks_ + 1) + " attempt" +
                   (cutbacks_ ? "s" : "") + " from that state, the last at the smallest increment " +
                   number_text(increment_) + " (" + why + ")";
      return false;
    }
    return true;
  }

  /// Solves toward `target`; returns the trial free displacements, `rec.newton` says how.
  VecX attempt(double target, StepRecord& rec, ContactStepResult& cstep) {
    const double load_scale = target * system_.load_scale();
    system_.set_state(target, prescribe(target));
    if (with_contact_) {
      ContactStepInput in;
      in.u_free = u_free_;
      in.u_prev_full = u_prev_full_;
      in.u_guess = extrapolate_ ? extrapolated_start(target) : VecX();
      extrapolated_ = in.u_guess.size() > 0;
      in.newton = options_.newton;
      in.newton.residual_scale = load_scale;
      in.floor_scale = floor_scale_;
      // A method's sets decided from states far from the solution can cycle (a penalised
      // frictional first touch); once they have, the attempt is made again with every method
      // step continued by Newton until it divides the residual by ten (ContactStepInput::strict).
      in.strict = strict_;
      cstep = solve_contact_step(system_, *contact_, *strategy_, in);
      add_totals(cstep);
      rec.newton = cstep.newton;
      rec.newton.status = cstep.status;
      rec.newton.message = cstep.message;
      rec.contact = cstep.iterations;
      rec.fallback = cstep.fallback;
      rec.fallback_reason = cstep.fallback_reason;
      rec.factorizations = cstep.strategy.factorizations + cstep.newton.factorizations;
      return cstep.u_free;
    }
    // Linear predictor from the last converged state: K_T Δu_f = λ f − f_int − K_fc Δu_c (a
    // small-strain system's K is factorised once for the run: its predictor is the answer, and
    // Newton finds the residual within its test at once). Not the extrapolated start of a
    // contact step: a cantilever rolled up by a tip load stretches where its rotations are
    // extrapolated linearly (the elastica's first residual doubles, and Newton needs as many
    // iterations as from the predictor).
    const int factorized_before = system_.linear_report().numeric_factorizations;
    extrapolated_ = false;
    VecX guess = u_free_, rhs, step;
    if (system_.step_predictor(u_prev_full_, rhs) && system_.factorize_jacobian_assembled())
      if (system_.solve(rhs, step) && step.allFinite()) guess = u_free_ + step;
    NewtonOptions newton = options_.newton;
    newton.residual_scale = std::max({load_scale, system_.reaction_scale(guess), floor_scale_});
    VecX trial = guess;
    rec.newton = solve_newton_with_fallback(system_, trial, newton);
    rec.factorizations = system_.linear_report().numeric_factorizations - factorized_before;
    return trial;
  }

  /// Where a finite-strain contact step's first iterate starts: the last accepted increment
  /// scaled to this one, u + (Δλ/Δλ_last) Δu_last, while the load path goes on as it went (the
  /// prescribed values and the loads change in proportion to the last step's change, to a
  /// tenth) and so does the response (the last two increments alike, to a quarter). Empty, for
  /// the tangent predictor from the converged state, in the first two steps (a first touch
  /// from a stress-free state is no guide), where the path turns (a load followed by an
  /// unload, a normal load by a tangential one), and for a small-strain system (its predictor
  /// is its answer). A block dragged over a deforming base takes 3.0 Newton iterations a step
  /// from there with lagrange and 4.2 with penalty, against 3.9 and 5.5 from the predictor,
  /// whose linear step across a curved master leaves a penalty's gaps far off.
  VecX extrapolated_start(double target) const {
    if (system_.is_linear() || last_dlambda_ <= 0.0 || earlier_dlambda_ <= 0.0 ||
        last_increment_.size() != u_free_.size() || earlier_increment_.size() != u_free_.size())
      return {};
    const double ratio = (target - lambda_) / last_dlambda_, before = lambda_ - last_dlambda_;
    const auto in_proportion = [&](const VecX& a, const VecX& b, const VecX& c) {
      const VecX now = c - b, last = b - a;  // the change this step asks for, and the last one
      return (now - ratio * last).norm() <= 0.1 * std::max(now.norm(), ratio * last.norm());
    };
    // The response too: the last two increments alike (not a first touch from a stress-free
    // state, nor the first step after the path turned).
    const double r_last = last_dlambda_ / earlier_dlambda_;
    if ((last_increment_ - r_last * earlier_increment_).norm() >
        0.25 * std::max(last_increment_.norm(), r_last * earlier_increment_.norm()))
      return {};
    if (!in_proportion(prescribe(before), prescribe(lambda_), prescribe(target)) ||
        !in_proportion(model_.external_force_at(before), model_.external_force_at(lambda_),
                       model_.external_force_at(target)))
      return {};
    return u_free_ + ratio * last_increment_;
  }

  /// Adds an attempt's method work to the run's totals.
  void add_totals(const ContactStepResult& cstep) {
    totals_.add_work(cstep.strategy);
    totals_.factorizations += cstep.newton.factorizations;
    detection_seconds_ += cstep.detection_seconds;
  }

  /// What a failed attempt says of inverted elements ("" when none inverted): its Newton solve
  /// met one, or the contact method's last trial state has one.
  std::string inversion(double target, const StepRecord& rec, const ContactStepResult& cstep) {
    const std::string at = "at the step to λ = " + number_text(target) + ", ";
    if (rec.newton.status == SolveStatus::kInvertedElement) {
      const std::string which = system_.evaluation_failure();
      return at + (which.empty() ? std::string("an element inverted") : which);
    }
    if (with_contact_ && cstep.u_free.size() == u_free_.size() &&
        !system_.admissible(system_.full(cstep.u_free)))
      return at + "in the method's last trial state " + system_.evaluation_failure();
    return "";
  }

  void accept(double target, const VecX& trial, const ContactStepResult& cstep, StepRecord& rec) {
    if (target >= inverted_lambda_) inverted_at_.clear();
    strict_ = false;
    ++converged_steps_;
    extrapolate_ = true;
    earlier_increment_ = std::move(last_increment_);
    earlier_dlambda_ = last_dlambda_;
    last_increment_ = trial - u_free_;
    last_dlambda_ = target - lambda_;
    u_free_ = trial;
    u_prev_full_ = system_.full(u_free_);
    lambda_ = target;
    if (with_contact_) {
      strategy_->step_accepted(cstep.history);
      last_contact_.status = SolveStatus::kConverged;
      contact_->report(cstep.rows, cstep.state, last_contact_);
      // Friction: the slip accumulated over the converged steps, per slave node.
      accumulated_slip_.resize(last_contact_.nodes.size(), 0.0);
      for (size_t i = 0; i < last_contact_.nodes.size(); ++i) {
        accumulated_slip_[i] += std::abs(last_contact_.nodes[i].slip);
        last_contact_.nodes[i].accumulated_slip = accumulated_slip_[i];
      }
      contact_->report_plates(u_prev_full_, cstep.state.eq_multiplier, system_.is_linear(),
                              last_contact_);
      last_contact_.measured_penetration = cstep.measured_penetration;
      last_contact_.penetration_tolerance = cstep.penetration_tolerance;
      last_contact_.nodal_penetration = cstep.nodal_penetration;
      if (!cstep.fallback.empty()) {
        ++last_contact_.fallback_steps;
        last_contact_.fallback_method = cstep.fallback;
        last_contact_.fallback_reason = cstep.fallback_reason;
      }
      rec.contact_state = last_contact_;
    }
    // Below the nominal increment, grow back toward it: at once after a cutback when the step
    // came easily, and after every two easy steps in a row (one growth per cutback kept a run
    // that had been cut back once at its small increment for the rest of the load: a drag
    // with friction took 1,616 steps for 30).
    // (Easy as Newton with the set held measures it: the method's steps it continued from,
    // counted among the step's iterations, are not its own.)
    const bool easy = rec.newton.iterations - rec.newton.method_steps <= 4;
    easy_in_a_row_ = easy ? easy_in_a_row_ + 1 : 0;
    if (increment_ < nominal_ && easy && (cutbacks_ > 0 || easy_in_a_row_ >= 2)) {
      increment_ = std::min(nominal_, 2.0 * increment_);
      easy_in_a_row_ = 0;
    }
    cutbacks_ = 0;
  }

  /// An attempt from the extrapolated start failed: the same increment once more from the
  /// tangent predictor, before any cutback (extrapolation resumes after the next accepted step).
  void retry_from_predictor() {
    if (with_contact_) strategy_->step_rejected();
    extrapolate_ = false;
  }

  void cut_back() {
    if (with_contact_) strategy_->step_rejected();
    ++cutbacks_;
    increment_ = std::max(smallest_, 0.5 * increment_);
  }

  /// The attempt's work in the contact report: its outer iterations (detection passes), and the
  /// method's own iterations, numbered on over the run, with its penalty raises.
  void record_contact_history(const StepRecord& rec, const ContactStepResult& cstep) {
    for (const auto& it : rec.contact) {
      last_contact_.iterations += it.strategy_iterations;
      ++last_contact_.detection_passes;
    }
    for (constraints::IterationRecord h : cstep.strategy.history) {
      h.iteration = static_cast<int>(last_contact_.history.size()) + 1;
      last_contact_.history.push_back(h);
    }
    last_contact_.penalty_history.insert(last_contact_.penalty_history.end(),
                                         cstep.strategy.penalty_history.begin(),
                                         cstep.strategy.penalty_history.end());
  }

  /// The fields of a converged state: displacement, reactions, stresses (smoothed, ZZ
  /// estimate) and the contact fields.
  void fill_state(Results& out, double lam, const VecX& u_full) {
    const Mesh& mesh = model_.mesh;
    system_.set_state(lam, u_full);
    out.displacement = u_full;
    out.reaction = system_.reactions(out.displacement);
    out.element_stresses = compute_element_stresses(mesh, model_.materials, out.displacement,
                                                    !system_.is_linear());
    out.nodal_stress = smooth_stresses(mesh, model_.materials, out.element_stresses, analysis_.smoothing);
    out.error = estimate_error(mesh, model_.materials, out.element_stresses, out.nodal_stress,
                               analysis_.target_error);
    out.globals["load_factor"] = lam;
    if (with_contact_) store_contact_results(last_contact_, mesh.num_nodes(), out);
  }

  /// Every converged step's fields for on_state (the last of which then is the final results).
  void emit_state(const StepRecord& rec) {
    Stopwatch clock;
    last_state_ = Results();
    last_state_.status = SolveStatus::kConverged;
    fill_state(last_state_, lambda_, u_prev_full_);
    last_state_.globals["steps"] = converged_steps_;
    recovery_seconds_ += clock.lap();
    options_.on_state(rec, last_state_);
    output_seconds_ += clock.lap();
    have_state_ = true;
  }

  Results finish(constraints::ContactReport* contact_report) {
    // Assembly: a small-strain K before the stepper's clock started, a tangent inside it.
    r_.time.assemble = system_.assemble_seconds();
    r_.time.solve = std::max(0.0, run_clock_.elapsed() - recovery_seconds_ - output_seconds_ -
                                      (r_.time.assemble - assemble_before_));
    r_.time.output = output_seconds_;
    r_.solver = system_.linear_report();
    // The run's status, not the last factorisation's (a failed run said "converged" here).
    r_.solver.status = r_.status;
    if (r_.status != SolveStatus::kConverged) r_.solver.message = r_.message;
    const Stopwatch recovery_clock;
    if (have_state_) {
      // The last converged step's fields, recovered for on_state already.
      r_.displacement = std::move(last_state_.displacement);
      r_.reaction = std::move(last_state_.reaction);
      r_.element_stresses = std::move(last_state_.element_stresses);
      r_.nodal_stress = std::move(last_state_.nodal_stress);
      r_.error = std::move(last_state_.error);
      r_.point_fields = std::move(last_state_.point_fields);
      for (const auto& [key, value] : last_state_.globals) r_.globals[key] = value;
    } else {
      fill_state(r_, lambda_, u_prev_full_);
    }
    r_.globals["steps"] = converged_steps_;
    if (with_contact_) {
      last_contact_.status = r_.status;
      last_contact_.message = r_.message;
      last_contact_.seconds = totals_.seconds;
      last_contact_.detection_seconds = detection_seconds_;
      // The run's linear solves: the structural system's own and the method's, over every
      // attempt (cut back ones too), under the run's status.
      r_.solver.backend = last_contact_.method;
      r_.solver.status = r_.status;
      r_.solver.message = r_.message;
      r_.solver.numeric_factorizations += totals_.factorizations;
      r_.solver.symbolic_analyses += totals_.symbolic_analyses;
      r_.solver.symbolic_seconds += totals_.symbolic_seconds;
      r_.solver.numeric_seconds += totals_.numeric_seconds;
      r_.solver.solve_seconds += totals_.solve_seconds;
      if (std::isfinite(totals_.pivot_ratio)) r_.solver.pivot_ratio = totals_.pivot_ratio;
      if (!totals_.factor.ordering.empty())
        static_cast<core::FactorInfo&>(r_.solver) = totals_.factor;
      if (contact_report) *contact_report = last_contact_;
    }
    r_.time.recovery = recovery_seconds_ + recovery_clock.elapsed();
    return std::move(r_);
  }

  const Stopwatch run_clock_;
  const double assemble_before_;  ///< the system's assembly time before the run's clock
  const Model& model_;
  const AnalysisSpec& analysis_;
  const StepperOptions& options_;
  std::vector<StepRecord>* trace_;
  const constraints::ContactSet* contact_;
  StructuralSystem& system_;
  const bool with_contact_;
  const double floor_scale_;
  std::unique_ptr<constraints::ConstraintStrategy> strategy_;
  // The converged state: everything a failed attempt must not touch.
  VecX u_free_, u_prev_full_;
  VecX last_increment_;        ///< the last accepted step's Δu (free)
  double last_dlambda_ = 0.0;  ///< and its Δλ
  VecX earlier_increment_;     ///< the increment of the step before it (free)
  double earlier_dlambda_ = 0.0;  ///< and its Δλ
  bool extrapolate_ = true;    ///< false: the next attempt starts from the tangent predictor
  bool extrapolated_ = false;  ///< the last attempt started from extrapolated_start
  double lambda_ = 0.0;
  /// The attempt at the lowest load (inverted_lambda_) beyond the converged state that
  /// inverted an element; empty when none has.
  std::string inverted_at_;
  double inverted_lambda_ = 0.0;
  std::vector<double> accumulated_slip_;  ///< friction: Σ |slip| per slave node
  constraints::ContactReport last_contact_;
  Results r_, last_state_;
  bool have_state_ = false;
  double recovery_seconds_ = 0.0, output_seconds_ = 0.0;  // spent on on_state, not on solving
  StrategyTotals totals_;            ///< the method's work over every attempt (no history kept)
  double detection_seconds_ = 0.0;   ///< contact search over every attempt
  const double nominal_;
  const double smallest_;     ///< the smallest increment: nominal / 2^max_cutbacks
  const long max_attempts_;   ///< attempts before the run ends `stalled`
  double increment_;
  long attempts_ = 0;
  int converged_steps_ = 0, cutbacks_ = 0;
  bool strict_ = false;  ///< the next attempt repeats one whose sets cycled (attempt())
  int easy_in_a_row_ = 0;  ///< converged steps in a row that took at most 4 Newton iterations
};

}  // namespace

Results solve_load_steps(const Model& model, const AnalysisSpec& analysis,
                         const StepperOptions& options, std::vector<StepRecord>* trace,
                         const constraints::ContactSet* contact,
                         constraints::ContactReport* contact_report) {
  if (analysis.geometric_nonlinearity && contact && !contact->empty() &&
      model.follower_matrix.nonZeros() > 0)
    throw InputError(model.follower_where +
                     ": follower = true: expected a load-stepped run without [[contact]], "
                     "[[constraint]] or [[plate]] (their methods take a symmetric tangent; a "
                     "follower pressure's is not), found both");
  const std::unique_ptr<StructuralSystem> system = make_structural_system(model, analysis);
  // A linear analysis without amplitudes is proportional: its one step is every stage.
  StepperOptions staged = options;
  if (system->is_linear() && !core::has_amplitudes(model)) staged.steps = 1;
  return LoadStepper(*system, analysis, staged, trace, contact).run(contact_report);
}

Results solve_geometric_nonlinear(const Model& model, const AnalysisSpec& analysis,
                                  const StepperOptions& options, std::vector<StepRecord>* trace,
                                  const constraints::ContactSet* contact,
                                  constraints::ContactReport* contact_report) {
  AnalysisSpec finite = analysis;
  finite.geometric_nonlinearity = true;
  return solve_load_steps(model, finite, options, trace, contact, contact_report);
}

Results solve_linear_static(const Model& model, const AnalysisSpec& analysis,
                            const constraints::ContactSet* contact,
                            constraints::ContactReport* contact_report) {
  AnalysisSpec linear = analysis;
  linear.geometric_nonlinearity = false;
  StepperOptions options;
  options.steps = analysis.steps;
  options.newton.max_iterations = analysis.max_newton_iterations;
  return solve_load_steps(model, linear, options, nullptr, contact, contact_report);
}

}  // namespace c2d::nonlinear
