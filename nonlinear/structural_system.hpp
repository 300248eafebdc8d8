// The structure's equations on the free DOFs as the constrained step sees them, whatever the
// kinematics: R(u_f) = f_int(u) − λ f_ext, its tangent, and the linearisation of a load step.
// FiniteStrainSystem is the updated-Lagrangian model (K_T = K_D + K_σ); SmallStrainSystem the
// linear one (K constant, K_σ = 0). solve_contact_step takes either.
#pragma once

#include "core/model.hpp"
#include "nonlinear/newton_solver.hpp"

namespace c2d::nonlinear {

class StructuralSystem : public NewtonSystem {
 public:
  virtual const core::Model& model() const = 0;
  /// Full displacement from the free values and the current prescribed values.
  virtual VecX full(const VecX& u_free) const = 0;
  /// Assembles the tangent at u (full) into matrix(); false if an element is inverted.
  virtual bool assemble_tangent(const VecX& u_full) = 0;
  virtual const SpMat& matrix() const = 0;
  /// The load step's linearisation about the converged full state u0: assembles the tangent
  /// there into matrix() and returns the out-of-balance force at the current load factor with
  /// the prescribed increment carried as a lift. False if an element is inverted.
  virtual bool step_predictor(const VecX& u0, VecX& load) = 0;
  /// Largest support reaction at the free values u_free (0 when unknown or inverted).
  virtual double reaction_scale(const VecX& u_free) const = 0;
  /// True when R is affine in u (the tangent never changes): a linearised problem that the
  /// state reproduces needs no second solve.
  virtual bool is_linear() const = 0;
};

/// The small-displacement equations K_ff u_f = f_f − K_fc u_c of an assembled linear system
/// (referenced, not copied): residual K_ff u_f − rhs, constant tangent K_ff.
class SmallStrainSystem final : public StructuralSystem {
 public:
  SmallStrainSystem(const core::Model& model, const SpMat& k_ff, const VecX& rhs,
                    const VecX& u_prescribed)
      : model_(model), k_ff_(k_ff), rhs_(rhs), u_prescribed_(u_prescribed) {}
  const core::Model& model() const override { return model_; }
  VecX full(const VecX& u_free) const override;
  bool assemble_tangent(const VecX&) override { return true; }
  const SpMat& matrix() const override { return k_ff_; }
  bool step_predictor(const VecX& u0, VecX& load) override;
  double reaction_scale(const VecX&) const override { return 0.0; }
  bool is_linear() const override { return true; }
  bool residual(const VecX& u_free, VecX& r) override;
  bool factorize_jacobian(const VecX&) override { return false; }  // the constraint terms solve
  bool solve(const VecX&, VecX&) override { return false; }

 private:
  const core::Model& model_;
  const SpMat& k_ff_;
  const VecX& rhs_;
  const VecX& u_prescribed_;
};

}  // namespace c2d::nonlinear
