// The discrete updated-Lagrangian St. Venant–Kirchhoff problem on the free DOFs:
// R(u_f) = f_int(u) − λ f_ext with u the full vector (prescribed values of the current load
// factor), and its tangent K_T = K_D + K_σ. Follower pressures enter f_int as −λ M x (their
// forces at the current positions) and the tangent as −λ M, which is not symmetric: with them
// the Newton system is factorised by LU (UMFPACK) instead of Cholesky.
#pragma once

#include "core/assembler.hpp"
#include "core/model.hpp"
#include "constraints/kkt_solver.hpp"
#include "core/spd_solver.hpp"
#include "nonlinear/newton_solver.hpp"
#include "nonlinear/structural_system.hpp"

namespace c2d::nonlinear {

class FiniteStrainSystem final : public StructuralSystem {
 public:
  explicit FiniteStrainSystem(const core::Model& model);

  /// λ × the supports' values; rotated supports turn through λθ.
  VecX prescribed(double lambda) const override;
  void set_state(double lambda, const VecX& u_prescribed) override;
  double load_factor() const { return lambda_; }
  const core::Model& model() const override { return model_; }
  VecX full(const VecX& u_free) const override;
  /// Full internal force vector at a full displacement, less the follower pressures' forces
  /// there (at the current load factor); false if an element is inverted.
  bool internal_force(const VecX& u_full, VecX& f) const;
  /// Assembles K_T,ff at u (full) into matrix(); with `du_constrained`, also lift = K_fc du_c.
  /// False if an element is inverted.
  bool assemble(const VecX& u_full, const VecX* du_constrained = nullptr, VecX* lift = nullptr);
  bool assemble_tangent(const VecX& u_full) override { return assemble(u_full); }
  bool is_linear() const override { return false; }
  /// Largest support reaction |f_int| on the prescribed DOFs at the free values u_free (0 if an
  /// element is inverted): the force scale of supports that carry the load.
  double reaction_scale(const VecX& u_free) const override;
  /// K_T,ff: the elements' (and the springs', when the model has any).
  const SpMat& matrix() const override { return extra_ ? tangent_ : assembler_.matrix(); }
  /// The largest external load (dead and follower, reference values, amplitudes' peaks).
  double load_scale() const override { return load_scale_; }
  bool admissible(const VecX& u_full) const override;
  VecX reactions(const VecX& u_full) const override;
  double assemble_seconds() const override { return assemble_seconds_; }
  /// The dead loads at load factor λ, amplitudes included (full vector): the external force
  /// less the follower pressures, which internal_force counts at the current positions.
  VecX dead_load_at(double lambda) const;
  /// The load step's linearisation about the converged full state u0 (with its own prescribed
  /// values): assembles K_T(u0) into matrix() and returns the out-of-balance force at the
  /// current load factor, the prescribed increment carried as a lift:
  /// λ f − f_int(u0) − K_fc (u_c − u0_c). False if an element is inverted.
  bool step_predictor(const VecX& u0, VecX& load) override;
  const VecX& f_ext_free() const { return f_ext_free_; }

  // NewtonSystem: the unconstrained problem, factorised with CHOLMOD (symbolic analysis kept).
  bool residual(const VecX& u_free, VecX& r) override;
  bool factorize_jacobian(const VecX& u_free) override;
  /// Factorises the matrix last assembled.
  bool factorize_jacobian_assembled() override;
  bool solve(const VecX& b, VecX& x) override;
  const core::SpdSolveReport& linear_report() const override { return solver_.report(); }
  /// "element N (1-based) is inverted" after an evaluation that met one; "" otherwise.
  std::string evaluation_failure() const override;

 private:
  /// internal_force without the memory of the last evaluation.
  bool evaluate_internal_force(const VecX& u_full, VecX& f) const;
  mutable int inverted_ = -1;  ///< the first inverted element of the last evaluation
  /// The last internal force evaluated: Newton asks for the force at one state several times
  /// (the residual that ends an outer iteration is the next one's linearisation point, the
  /// reaction scale and the admissibility check read the same state).
  struct LastForce {
    VecX u;
    double lambda = 0.0;
    VecX f;
    bool ok = false;
    int inverted = -1;
  };
  mutable LastForce last_;
  const core::Model& model_;
  core::Assembler assembler_;
  bool extra_ = false;  ///< springs or follower loads add to the elements' K_T
  SpMat tangent_;       ///< the assembled K_T plus the springs' stiffness and −λ M_ff
  SpMat follower_ff_;   ///< M on the free DOFs
  core::SpdSolver solver_;
  constraints::KktSolver lu_;  ///< with follower loads
  double load_scale_ = 0.0;
  VecX f_dead_, f_ext_free_, u_prescribed_;
  VecX f_now_free_;  ///< the dead loads at the state's λ, free DOFs
  double lambda_ = 0.0;
  double assemble_seconds_ = 0.0;
};

}  // namespace c2d::nonlinear
