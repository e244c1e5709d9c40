// SPDX-License-Identifier: MIT
#include "solvers/static_solver.hpp"

#include "util/petsc_check.hpp"

namespace slidebeam {

StaticSolver::StaticSolver(Model& model) : model_(model) {
  if (!model.finalized()) model.finalize();
  SB_CHECK(SNESCreate(model.comm(), &snes_));
  SB_CHECK(SNESSetType(snes_, SNESNEWTONLS));
  SB_CHECK(SNESSetFunction(snes_, model.residual_vector(), &StaticSolver::form_function, this));
  SB_CHECK(SNESSetJacobian(snes_, model.jacobian(), model.jacobian(), &StaticSolver::form_jacobian, this));
  // Exact Newton: full steps (a line search on a saddle-point residual norm mostly gets in the way).
  SNESLineSearch ls = nullptr;
  SB_CHECK(SNESGetLineSearch(snes_, &ls));
  SB_CHECK(SNESLineSearchSetType(ls, SNESLINESEARCHBASIC));
  // Converged when |F| < 1e-10, or |F| fell by 1e-12, or the Newton step is below 1e-12 |x|:
  // with quadratic convergence the last criterion leaves an error at roundoff level whatever the
  // units of the scene.
  SB_CHECK(SNESSetTolerances(snes_, 1e-10, 1e-12, 1e-12, 50, 10000));
  // The first iterate of a director beam often has a residual 1e4-1e6 times the initial one
  // (linearised directors leave the constraint manifold) and then converges quadratically:
  // that is not divergence, so PETSc's dtol test is off. NaN/Inf and max_it still stop.
  SB_CHECK(SNESSetDivergenceTolerance(snes_, -1.0));
  // Sparse direct solve. The saddle-point matrix has zero diagonal entries (multipliers, and d1
  // for the seed's strains), so the factorisation must pivot: PETSc's own LU does not.
  // Serial: SuperLU; parallel: MUMPS. Both can be changed from the options database.
  SB_CHECK(SNESSetConvergenceTest(snes_, &StaticSolver::converged, this, nullptr));
  KSP ksp = nullptr;
  PC pc = nullptr;
  SB_CHECK(SNESGetKSP(snes_, &ksp));
  SB_CHECK(KSPSetType(ksp, KSPPREONLY));
  SB_CHECK(KSPGetPC(ksp, &pc));
  SB_CHECK(PCSetType(pc, PCLU));
  int size = 1;
  MPI_Comm_size(model.comm(), &size);
  SB_CHECK(PCFactorSetMatSolverType(pc, size == 1 ? MATSOLVERSUPERLU : MATSOLVERMUMPS));
  // MUMPS sizes its workspace from the analysis; pivoting on the zero diagonal of the
  // saddle-point matrix needs more (INFOG(1) = -9 otherwise). Users' own value wins.
  PetscBool has = PETSC_FALSE;
  SB_CHECK(PetscOptionsHasName(nullptr, nullptr, "-mat_mumps_icntl_14", &has));
  if (!has) SB_CHECK(PetscOptionsSetValue(nullptr, "-mat_mumps_icntl_14", "200"));
  SB_CHECK(SNESSetFromOptions(snes_));
}

StaticSolver::~StaticSolver() { SNESDestroy(&snes_); }

PetscErrorCode StaticSolver::form_function(SNES, Vec x, Vec F, void* ctx) {
  PetscFunctionBeginUser;
  auto* self = static_cast<StaticSolver*>(ctx);
  PetscCall(self->model_.assemble_residual(self->t_, x, F));
  PetscFunctionReturn(0);
}

PetscErrorCode StaticSolver::form_jacobian(SNES, Vec x, Mat J, Mat, void* ctx) {
  PetscFunctionBeginUser;
  auto* self = static_cast<StaticSolver*>(ctx);
  PetscCall(self->model_.assemble_jacobian(self->t_, x, J));
  PetscFunctionReturn(0);
}

/// PETSc's default test, plus: converged at roundoff. In large units (EA = 1e7, coordinates of
/// 100) the residual bottoms out well above any fixed atol, and the multiplier part of the
/// Newton step stays noisy, so stol cannot fire either. Once the residual is 1e6 below the
/// step's initial residual and no longer falls quadratically, it is at roundoff: stop there.
PetscErrorCode StaticSolver::converged(SNES snes, PetscInt it, PetscReal xnorm, PetscReal snorm, PetscReal fnorm,
                                       SNESConvergedReason* reason, void* ctx) {
  PetscFunctionBeginUser;
  auto* self = static_cast<StaticSolver*>(ctx);
  PetscCall(SNESConvergedDefault(snes, it, xnorm, snorm, fnorm, reason, nullptr));
  if (it == 0) self->fnorm0_ = fnorm;
  if (*reason == SNES_CONVERGED_ITERATING && it > 1 && fnorm <= 1e-6 * self->fnorm0_ &&
      fnorm >= 0.5 * self->fnorm_prev_) {
    PetscCall(PetscInfo(snes, "Converged at roundoff: ||F|| %g stagnates (initial %g)\n", (double)fnorm,
                        (double)self->fnorm0_));
    *reason = SNES_CONVERGED_FNORM_RELATIVE;
  }
  self->fnorm_prev_ = fnorm;
  PetscFunctionReturn(0);
}

SolveResult StaticSolver::solve(double t) {
  t_ = t;
  model_.apply_prescribed(model_.x());
  SB_CHECK(SNESSolve(snes_, nullptr, model_.x()));
  SolveResult r;
  SNESConvergedReason reason;
  SB_CHECK(SNESGetConvergedReason(snes_, &reason));
  r.reason = static_cast<int>(reason);
  PetscInt it = 0, lit = 0;
  SB_CHECK(SNESGetIterationNumber(snes_, &it));
  SB_CHECK(SNESGetLinearSolveIterations(snes_, &lit));
  r.iterations = static_cast<int>(it);
  r.linear_iterations = static_cast<int>(lit);
  PetscReal fnorm = 0;
  SB_CHECK(SNESGetFunctionNorm(snes_, &fnorm));
  r.residual_norm = fnorm;
  return r;
}

const char* StaticSolver::reason_name(int reason) { return SNESConvergedReasons[reason]; }

}  // namespace slidebeam
