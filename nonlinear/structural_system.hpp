// The structure's equations on the free DOFs as the load stepper and the constrained step see
// them, whatever the kinematics: R(u_f) = f_int(u) − f_ext(λ), its tangent, the linearisation of
// a load step, and what a converged state reports (reactions, stresses). FiniteStrainSystem is
// the updated-Lagrangian model (K_T = K_D + K_σ); SmallStrainSystem the linear one (K constant,
// factorised once per run, K_σ = 0). The load stepper (load_stepper.hpp) drives either.
#pragma once

#include <memory>
#include <string>

#include "core/model.hpp"
#include "core/scene.hpp"
#include "core/spd_solver.hpp"
#include "core/stress_recovery.hpp"
#include "nonlinear/newton_solver.hpp"

namespace c2d::nonlinear {

class StructuralSystem : public NewtonSystem {
 public:
  virtual const core::Model& model() const = 0;
  /// True when R is affine in u (the tangent never changes): small strain. A linearised
  /// problem that the state reproduces needs no second solve, and stresses are linear ones.
  virtual bool is_linear() const = 0;

  /// The prescribed displacements at load factor λ (full vector; free entries 0).
  virtual VecX prescribed(double lambda) const = 0;
  /// The load factor and the full vector carrying the prescribed values at it.
  virtual void set_state(double lambda, const VecX& u_prescribed) = 0;
  /// Full displacement from the free values and the current prescribed values.
  virtual VecX full(const VecX& u_free) const = 0;
  /// The largest external load the run reaches (amplitudes' peaks included): the force scale.
  virtual double load_scale() const = 0;

  /// Assembles the tangent at u (full) into matrix(); false if an element is inverted.
  virtual bool assemble_tangent(const VecX& u_full) = 0;
  virtual const SpMat& matrix() const = 0;
  /// Factorises matrix() as last assembled (the Newton solve's Jacobian).
  virtual bool factorize_jacobian_assembled() = 0;
  /// The load step's linearisation about the converged full state u0: assembles the tangent
  /// there into matrix() and returns the out-of-balance force at the current load factor with
  /// the prescribed increment carried as a lift. False if an element is inverted.
  virtual bool step_predictor(const VecX& u0, VecX& load) = 0;
  /// False when the full state u has an inverted element (evaluation_failure() names it).
  virtual bool admissible(const VecX& u_full) const = 0;

  /// Largest support reaction at the free values u_free (0 when inverted).
  virtual double reaction_scale(const VecX& u_free) const = 0;
  /// The support reactions at the full state u and the current load factor: f_int − f_ext on
  /// the constrained DOFs, 0 elsewhere (follower pressures count at the current positions).
  virtual VecX reactions(const VecX& u_full) const = 0;
  /// The linear solver's work and the factor's description (the system's own factorisations).
  virtual const core::SpdSolveReport& linear_report() const = 0;
  /// Seconds spent assembling matrices so far.
  virtual double assemble_seconds() const = 0;
};

/// The largest external nodal load a run reaches, dead and follower at their reference values,
/// each amplitude at its peak (free DOFs): the force scale of both systems.
double largest_external_load(const core::Model& model);

/// The structural system of an analysis: FiniteStrainSystem when the analysis has geometric
/// nonlinearity, else SmallStrainSystem.
std::unique_ptr<StructuralSystem> make_structural_system(const core::Model& model,
                                                         const core::AnalysisSpec& analysis);

/// The small-displacement equations K_ff u_f = f_f(λ) − K_fc u_c(λ): K (elements and springs)
/// assembled once, with the prescribed values growing linearly in λ or by their amplitudes
/// (their lifts K_fc u_c at 1 kept) and the loads by theirs. The tangent is K; it is factorised
/// once (CHOLMOD, or Eigen's LDLᵀ when analysis.solver is "ldlt") and the factor kept for every
/// step.
class SmallStrainSystem final : public StructuralSystem {
 public:
  SmallStrainSystem(const core::Model& model, const core::AnalysisSpec& analysis);
  const core::Model& model() const override { return model_; }
  bool is_linear() const override { return true; }
  VecX prescribed(double lambda) const override;
  void set_state(double lambda, const VecX& u_prescribed) override;
  VecX full(const VecX& u_free) const override;
  double load_scale() const override { return load_scale_; }
  bool assemble_tangent(const VecX&) override { return true; }
  const SpMat& matrix() const override { return k_ff_; }
  bool factorize_jacobian_assembled() override;
  bool step_predictor(const VecX& u0, VecX& load) override;
  bool admissible(const VecX&) const override { return true; }
  double reaction_scale(const VecX& u_free) const override;
  VecX reactions(const VecX& u_full) const override;
  const core::SpdSolveReport& linear_report() const override { return solver_.report(); }
  double assemble_seconds() const override { return assemble_seconds_; }

  // NewtonSystem: R(u_f) = K_ff u_f − rhs(λ), Jacobian K_ff (factorised once).
  bool residual(const VecX& u_free, VecX& r) override;
  bool factorize_jacobian(const VecX&) override { return factorize_jacobian_assembled(); }
  bool solve(const VecX& b, VecX& x) override;

 private:
  const core::Model& model_;
  SpMat k_ff_;          ///< elements and springs, free DOFs
  VecX lift_one_;       ///< K_fc u_c at λ = 1 of the values growing as λ (elements and springs)
  /// Per motion amplitude: K_fc u_c of its values at a = 1.
  std::vector<VecX> lift_amplitude_;
  VecX rhs_;            ///< f_f(λ) − K_fc u_c(λ) at the state's λ
  VecX u_prescribed_;   ///< the state's full vector of prescribed values
  double lambda_ = 0.0;
  core::SpdSolver solver_;
  bool factorized_ = false;
  double load_scale_ = 0.0;
  double assemble_seconds_ = 0.0;
};

}  // namespace c2d::nonlinear
