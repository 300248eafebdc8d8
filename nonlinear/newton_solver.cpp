#include "nonlinear/newton_solver.hpp"

#include <kinsol/kinsol.h>
#include <kinsol/kinsol_ls.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sundials/sundials_linearsolver.h>
#include <sundials/sundials_matrix.h>

#include <cmath>
#include <cstdlib>
#include <exception>
#include <limits>
#include <string>

#include "core/errors.hpp"
#include "core/interrupt.hpp"

namespace c2d::nonlinear {

namespace {

/// Newton makes no progress when this many iterations in a row leave the residual above
/// kProgress × its least value so far: a 2-cycle (a node flipping between two master edges at
/// a free end) or a plateau. Such an attempt stops there instead of running to the iteration
/// limit (it cost the load stepper 25 factorisations per cutback on a block dragged off its
/// master's end). One or two rising iterations, as on slender structures before the residual
/// collapses, are within the window.
constexpr int kNoProgressIterations = 5;
constexpr double kProgress = 0.9;

struct Bridge {
  NewtonSystem* system = nullptr;
  std::vector<double>* history = nullptr;
  int factorizations = 0;  ///< successful factorize_jacobian calls
  std::string error;  ///< KINSOL's last error message
  double least = std::numeric_limits<double>::infinity();  ///< least residual norm so far
  int since_least = 0;       ///< iterations since it was set
  bool no_progress = false;  ///< stopped for that
};

Eigen::Map<VecX> view(N_Vector v) {
  return {N_VGetArrayPointer(v), static_cast<Eigen::Index>(N_VGetLength(v))};
}

// C callbacks: catch everything, answer with KINSOL's flags (> 0 recoverable, < 0 fatal).
int residual_callback(N_Vector u, N_Vector f, void* data) {
  auto* b = static_cast<Bridge*>(data);
  try {
    VecX r;
    if (!b->system->residual(view(u), r) || !r.allFinite()) return 1;
    view(f) = r;
    return 0;
  } catch (const std::exception& e) {
    b->error = e.what();
    return -1;
  }
}

int jacobian_callback(N_Vector u, N_Vector fu, SUNMatrix, void* data, N_Vector, N_Vector) {
  auto* b = static_cast<Bridge*>(data);
  if (core::interrupt_requested()) return -1;  // unwound below, after KINSOL has returned
  try {
    const double norm = view(fu).cwiseAbs().maxCoeff();
    b->history->push_back(norm);
    if (norm < kProgress * b->least || !std::isfinite(b->least)) {
      b->least = norm;
      b->since_least = 0;
    } else if (++b->since_least >= kNoProgressIterations) {
      b->no_progress = true;
      return -1;
    }
    if (!b->system->factorize_jacobian(view(u))) return 1;
    ++b->factorizations;
    return 0;
  } catch (const std::exception& e) {
    b->error = e.what();
    return -1;
  }
}

// The matrix is a placeholder: the system owns the real one, so zero() has nothing to clear.
SUNMatrix_ID matrix_id(SUNMatrix) { return SUNMATRIX_CUSTOM; }
int matrix_zero(SUNMatrix) { return 0; }
void matrix_destroy(SUNMatrix m) { SUNMatFreeEmpty(m); }

SUNLinearSolver_Type solver_type(SUNLinearSolver) { return SUNLINEARSOLVER_DIRECT; }
SUNLinearSolver_ID solver_id(SUNLinearSolver) { return SUNLINEARSOLVER_CUSTOM; }
int solver_initialize(SUNLinearSolver) { return SUNLS_SUCCESS; }
int solver_setup(SUNLinearSolver, SUNMatrix) { return SUNLS_SUCCESS; }  // done in the Jacobian
int solver_solve(SUNLinearSolver s, SUNMatrix, N_Vector x, N_Vector rhs, realtype) {
  auto* b = static_cast<Bridge*>(s->content);
  try {
    VecX sol;
    if (!b->system->solve(view(rhs), sol) || !sol.allFinite()) return SUNLS_PACKAGE_FAIL_REC;
    view(x) = sol;
    return SUNLS_SUCCESS;
  } catch (const std::exception& e) {
    b->error = e.what();
    return SUNLS_PACKAGE_FAIL_UNREC;
  }
}
sunindextype solver_lastflag(SUNLinearSolver) { return 0; }
int solver_free(SUNLinearSolver s) {
  s->content = nullptr;
  SUNLinSolFreeEmpty(s);
  return 0;
}

void error_handler(int, const char*, const char*, char* msg, void* data) {
  static_cast<Bridge*>(data)->error = msg ? msg : "";
}

/// KINSOL stopped because the residual could not be evaluated (its first call, repeated
/// recoverable failures, or a failed setup): an input or step-size fault, said where.
void name_evaluation_failure(int flag, const NewtonSystem& system, NewtonReport& report) {
  const bool evaluation = flag == KIN_FIRST_SYSFUNC_ERR || flag == KIN_REPTD_SYSFUNC_ERR ||
                          flag == KIN_SYSFUNC_FAIL || flag == KIN_LSETUP_FAIL ||
                          flag == KIN_LSOLVE_FAIL || flag == KIN_LINSOLV_NO_RECOVERY;
  const std::string why = evaluation ? system.evaluation_failure() : std::string();
  if (why.empty()) return;
  report.status = SolveStatus::kInvertedElement;
  report.message = "the residual could not be evaluated: " + why;
}

SolveStatus map_flag(int flag, std::string& message) {
  switch (flag) {
    case KIN_SUCCESS:
    case KIN_INITIAL_GUESS_OK: return SolveStatus::kConverged;
    case KIN_MAXITER_REACHED: message = "Newton iteration limit reached"; return SolveStatus::kMaxIterations;
    case KIN_LINESEARCH_NONCONV:
    case KIN_LINESEARCH_BCFAIL: message = "line search failed"; return SolveStatus::kDiverged;
    case KIN_MXNEWT_5X_EXCEEDED: message = "five maximal Newton steps in a row"; return SolveStatus::kDiverged;
    case KIN_LSETUP_FAIL:
    case KIN_LSOLVE_FAIL: message = "the Newton system could not be factorised"; return SolveStatus::kSingular;
    case KIN_LINSOLV_NO_RECOVERY:
      message = "the Newton system could not be solved at a freshly factorised Jacobian";
      return SolveStatus::kSingular;
    case KIN_STEP_LT_STPTOL:
      message = "Newton could not move (a zero step) with the residual above its tolerance";
      return SolveStatus::kStalled;
    case KIN_FIRST_SYSFUNC_ERR:
    case KIN_REPTD_SYSFUNC_ERR:
    case KIN_SYSFUNC_FAIL:
      message = "the residual could not be evaluated";
      return SolveStatus::kFailed;
    case KIN_MEM_FAIL: message = "out of memory in the Newton solver"; return SolveStatus::kFailed;
    default: {
      char* name = KINGetReturnFlagName(flag);
      message = std::string("the Newton solver stopped (KINSOL flag ") + (name ? name : "?") + ")";
      std::free(name);
      return SolveStatus::kFailed;
    }
  }
}

}  // namespace

NewtonReport solve_newton(NewtonSystem& system, VecX& u, const NewtonOptions& o) {
  NewtonReport report;
  const int n = static_cast<int>(u.size());
  if (n == 0) {
    report.status = SolveStatus::kConverged;
    return report;
  }
  Bridge bridge;
  bridge.system = &system;
  bridge.history = &report.residual_norms;

  SUNContext ctx = nullptr;
  if (SUNContext_Create(nullptr, &ctx) != 0) {
    report.message = "SUNContext_Create failed";
    return report;
  }
  N_Vector x = N_VNew_Serial(n, ctx), uscale = N_VNew_Serial(n, ctx), fscale = N_VNew_Serial(n, ctx);
  void* kin = KINCreate(ctx);
  SUNMatrix mat = SUNMatNewEmpty(ctx);
  SUNLinearSolver ls = SUNLinSolNewEmpty(ctx);
  int flag = -1;
  bool interrupted = false;
  if (x && uscale && fscale && kin && mat && ls) {
    mat->ops->getid = matrix_id;
    mat->ops->zero = matrix_zero;
    mat->ops->destroy = matrix_destroy;
    ls->content = &bridge;
    ls->ops->gettype = solver_type;
    ls->ops->getid = solver_id;
    ls->ops->initialize = solver_initialize;
    ls->ops->setup = solver_setup;
    ls->ops->solve = solver_solve;
    ls->ops->lastflag = solver_lastflag;
    ls->ops->free = solver_free;
    view(x) = u;
    N_VConst(1.0, uscale);
    N_VConst(1.0 / std::max(o.residual_scale, 1e-300), fscale);
    flag = KINInit(kin, residual_callback, x);
    if (flag == KIN_SUCCESS) flag = KINSetUserData(kin, &bridge);
    if (flag == KIN_SUCCESS) flag = KINSetErrHandlerFn(kin, error_handler, &bridge);
    if (flag == KIN_SUCCESS) flag = KINSetLinearSolver(kin, ls, mat);
    if (flag == KIN_SUCCESS) flag = KINSetJacFn(kin, jacobian_callback);
    // Exact Newton (a new Jacobian every iteration), no clipping of long first steps.
    if (flag == KIN_SUCCESS) flag = KINSetMaxSetupCalls(kin, 1);
    if (flag == KIN_SUCCESS) flag = KINSetMaxNewtonStep(kin, 1e300);
    if (flag == KIN_SUCCESS) flag = KINSetFuncNormTol(kin, o.residual_tolerance);
    if (flag == KIN_SUCCESS) flag = KINSetScaledStepTol(kin, 1e-300);
    if (flag == KIN_SUCCESS) flag = KINSetNumMaxIters(kin, o.max_iterations);
    if (flag == KIN_SUCCESS)
      flag = KINSol(kin, x, o.line_search ? KIN_LINESEARCH : KIN_NONE, uscale, fscale);
    long iters = 0;
    KINGetNumNonlinSolvIters(kin, &iters);
    realtype step = 0;
    KINGetStepLength(kin, &step);
    interrupted = core::interrupt_requested();
    report.iterations = static_cast<int>(iters);
    report.factorizations = bridge.factorizations;
    report.last_step = step;
    report.status = map_flag(flag, report.message);
    if (bridge.no_progress) {
      report.status = SolveStatus::kStalled;
      report.message = "no progress: the residual stayed above " + number_text(kProgress) +
                       " of its least value for " + std::to_string(kNoProgressIterations) +
                       " Newton iterations";
    } else {
      if (!bridge.error.empty() && report.status != SolveStatus::kConverged)
        report.message += ": " + bridge.error;
      name_evaluation_failure(flag, system, report);
    }
    u = view(x);
    VecX r;
    const bool evaluated = system.residual(u, r) && r.allFinite();
    report.final_residual = evaluated ? r.cwiseAbs().maxCoeff() : 0.0;
    // KINSOL's exits other than success (a zero step, a failed line search) may leave an
    // iterate that meets the test: the state, not the flag, decides.
    const double tolerance = o.residual_tolerance * std::max(o.residual_scale, 1e-300);
    if (report.status != SolveStatus::kConverged && report.status != SolveStatus::kInvertedElement &&
        evaluated && report.final_residual <= tolerance) {
      report.status = SolveStatus::kConverged;
      report.message.clear();
    }
  } else {
    report.message = "could not allocate KINSOL objects";
  }
  report.residual_norms.push_back(report.final_residual);
  if (!u.allFinite()) {
    report.status = SolveStatus::kFailed;
    report.message = "Newton produced non-finite values";
  }
  if (kin) KINFree(&kin);
  if (ls) SUNLinSolFree(ls);
  if (mat) SUNMatDestroy(mat);
  if (x) N_VDestroy(x);
  if (uscale) N_VDestroy(uscale);
  if (fscale) N_VDestroy(fscale);
  SUNContext_Free(&ctx);
  if (interrupted) throw core::Interrupted();
  return report;
}

NewtonReport solve_newton_with_fallback(NewtonSystem& system, VecX& u, const NewtonOptions& o) {
  const VecX guess = u;
  NewtonOptions plain = o;
  plain.line_search = false;
  NewtonReport report = solve_newton(system, u, plain);
  if (report.status == SolveStatus::kConverged || !o.line_search) return report;
  u = guess;
  NewtonReport searched = solve_newton(system, u, o);
  searched.iterations += report.iterations;
  searched.factorizations += report.factorizations;
  searched.residual_norms.insert(searched.residual_norms.begin(), report.residual_norms.begin(),
                                 report.residual_norms.end());
  return searched;
}

}  // namespace c2d::nonlinear
