// SPDX-License-Identifier: MIT
#include "solvers/newton.hpp"

#include "util/petsc_check.hpp"

#include <cmath>
#include <string>

namespace slidebeam {

PetscErrorCode snes_ksp_pc(SNES snes, KSP* ksp, PC* pc) {
  PetscFunctionBeginUser;
  KSP k = nullptr;
  PetscCall(SNESGetKSP(snes, &k));
  if (ksp) *ksp = k;
  if (pc) PetscCall(KSPGetPC(k, pc));
  PetscFunctionReturn(0);
}

PetscErrorCode reset_snes_pc(SNES snes, KSP* ksp, PC* pc) {
  PetscFunctionBeginUser;
  PC p = nullptr;
  PetscCall(snes_ksp_pc(snes, ksp, &p));
  PetscCall(PCReset(p));
  if (pc) *pc = p;
  PetscFunctionReturn(0);
}

PetscErrorCode set_preonly(SNES snes, PCType type, PC* pc) {
  PetscFunctionBeginUser;
  KSP ksp = nullptr;
  PetscCall(snes_ksp_pc(snes, &ksp, pc));
  PetscCall(KSPSetType(ksp, KSPPREONLY));
  PetscCall(PCSetType(*pc, type));
  PetscFunctionReturn(0);
}

PetscErrorCode configure_newton(SNES snes, RoundoffTest* test) {
  PetscFunctionBeginUser;
  PetscCall(SNESSetType(snes, SNESNEWTONLS));
  // Exact Newton: full steps (a line search on a saddle-point residual norm mostly gets in the way).
  SNESLineSearch ls = nullptr;
  PetscCall(SNESGetLineSearch(snes, &ls));
  PetscCall(SNESLineSearchSetType(ls, SNESLINESEARCHBASIC));
  // Converged when |F| < 1e-10, or |F| fell by 1e-12, or the Newton step is below 1e-12 |x|:
  // with quadratic convergence the last criterion leaves an error at roundoff level whatever the
  // units of the scene.
  PetscCall(SNESSetTolerances(snes, 1e-10, 1e-12, 1e-12, 50, 10000));
  // The first iterate of a director beam often has a residual 1e4-1e6 times the initial one
  // (linearised directors leave the constraint manifold) and then converges quadratically:
  // that is not divergence, so PETSc's dtol test is off. NaN/Inf and max_it still stop.
  PetscCall(SNESSetDivergenceTolerance(snes, -1.0));
  PetscCall(SNESSetConvergenceTest(snes, guarded<&RoundoffTest::test>, test, nullptr));
  // Sparse direct solve. The saddle-point matrix has zero diagonal entries (multipliers, and d1
  // for the seed's strains), so the factorisation must pivot: PETSc's own LU does not.
  // Serial: SuperLU; parallel: MUMPS. Both can be changed from the options database.
  PC pc = nullptr;
  PetscCall(set_preonly(snes, PCLU, &pc));
  MPI_Comm comm;
  PetscCall(PetscObjectGetComm(reinterpret_cast<PetscObject>(snes), &comm));
  int size = 1;
  MPI_Comm_size(comm, &size);
  // (PETSc's own LU after -pc_factor_nonzeros_along_diagonal is 3x faster on small systems,
  // but crashed inside MatLUFactorNumeric on a scene with joint multipliers: not a default.)
  PetscCall(PCFactorSetMatSolverType(pc, size == 1 ? MATSOLVERSUPERLU : MATSOLVERMUMPS));
  // MUMPS sizes its workspace from the analysis; pivoting on the zero diagonal of the
  // saddle-point matrix needs more (INFOG(1) = -9 otherwise). Users' own value wins.
  const char* prefix = nullptr;
  PetscCall(SNESGetOptionsPrefix(snes, &prefix));
  PetscCall(default_mumps_workspace(prefix));
  PetscFunctionReturn(0);
}

PetscErrorCode default_mumps_workspace(const char* prefix) {
  PetscFunctionBeginUser;
  // The factored matrix exists only at the first solve: the default goes into the database,
  // under the solver's prefix.
  PetscBool has = PETSC_FALSE;
  PetscCall(PetscOptionsHasName(nullptr, prefix, "-mat_mumps_icntl_14", &has));
  if (!has) {
    const std::string key = std::string("-") + (prefix ? prefix : "") + "mat_mumps_icntl_14";
    PetscCall(PetscOptionsSetValue(nullptr, key.c_str(), "200"));
  }
  PetscFunctionReturn(0);
}

/// PETSc's default test, plus: converged at roundoff. In large units (EA = 1e7, coordinates of
/// 100) the residual bottoms out well above any fixed atol, and the multiplier part of the
/// Newton step stays noisy, so stol cannot fire either. Two signs of roundoff stop Newton:
/// - |F| <= eps || |J| |x| ||: no better x is representable (the componentwise backward error of
///   x is at the unit roundoff). This holds the first time an iterate reaches the floor, so no
///   iteration is spent only to see |F| stagnate; and it holds where the floor lies above 1e-6 of
///   the initial residual (a small load step on a slender beam: EA/EI = 1e7 put the floor at 2e-6
///   of the first step's residual, and Newton ran to its iteration limit).
/// - |F| 1e6 below the step's initial residual, no longer falling quadratically, and a Newton
///   step below 1e-7 of the state (a large load step's initial residual, 1e5 on the roll-up at
///   half a turn per step, let a residual still at 1e-2 that merely failed to fall once pass).
PetscErrorCode RoundoffTest::test(SNES snes, PetscInt it, PetscReal xnorm, PetscReal snorm, PetscReal fnorm,
                                  SNESConvergedReason* reason, void* ctx) {
  PetscFunctionBeginUser;
  auto* self = static_cast<RoundoffTest*>(ctx);
  PetscCall(SNESConvergedDefault(snes, it, xnorm, snorm, fnorm, reason, nullptr));
  if (it == 0) self->fnorm0 = fnorm;
  if (it == 1) self->xnorm1 = xnorm;
  if (*reason == SNES_CONVERGED_ITERATING && it > 0) {
    double level = 0.0;
    PetscCall(self->rounding_level(snes, &level));
    if (fnorm <= level && !self->ran_away(xnorm, fnorm)) {
      PetscCall(PetscInfo(snes, "Converged at roundoff: ||F|| %g <= eps || |J| |x| || = %g\n", (double)fnorm, level));
      *reason = SNES_CONVERGED_FNORM_ABS;
    }
  }
  if (*reason == SNES_CONVERGED_ITERATING && it > 1 && fnorm <= 1e-6 * self->fnorm0 &&
      fnorm >= 0.5 * self->fnorm_prev && snorm <= 1e-7 * xnorm) {
    PetscCall(PetscInfo(snes, "Converged at roundoff: ||F|| %g stagnates (initial %g)\n", (double)fnorm,
                        (double)self->fnorm0));
    *reason = SNES_CONVERGED_FNORM_RELATIVE;
  }
  self->fnorm_prev = fnorm;
  PetscFunctionReturn(0);
}

RoundoffTest::~RoundoffTest() {
  MatDestroy(&abs_);
  VecDestroy(&ax_);
  VecDestroy(&y_);
}

namespace {
PetscErrorCode abs_values(Mat A) {  // a sequential AIJ matrix's stored entries, in place
  PetscFunctionBeginUser;
  MatInfo info;
  PetscCall(MatGetInfo(A, MAT_LOCAL, &info));
  PetscScalar* v = nullptr;
  PetscCall(MatSeqAIJGetArray(A, &v));
  for (PetscInt k = 0; k < static_cast<PetscInt>(info.nz_used); ++k) v[k] = std::abs(v[k]);
  PetscCall(MatSeqAIJRestoreArray(A, &v));
  PetscFunctionReturn(0);
}
}  // namespace

PetscErrorCode RoundoffTest::rounding_level(SNES snes, double* level) {
  PetscFunctionBeginUser;
  *level = 0.0;
  Mat P = nullptr;
  PetscCall(SNESGetJacobian(snes, nullptr, &P, nullptr, nullptr));
  PetscBool aij = PETSC_FALSE, assembled = PETSC_FALSE;
  if (P) PetscCall(PetscObjectTypeCompareAny(reinterpret_cast<PetscObject>(P), &aij, MATSEQAIJ, MATMPIAIJ, ""));
  if (aij) PetscCall(MatAssembled(P, &assembled));
  if (!aij || !assembled) PetscFunctionReturn(0);
  PetscObjectState state = 0;
  PetscObjectId id = 0;
  PetscCall(MatGetNonzeroState(P, &state));
  PetscCall(PetscObjectGetId(reinterpret_cast<PetscObject>(P), &id));
  // (a matrix whose pattern grows during a run, contact on several ranks, may keep its nonzero
  // state on one rank while another's blocks change: the stored entries are compared too, and
  // every rank makes the same choice)
  int fresh = !abs_ || state != state_ || id != id_ || pattern_generation != generation_;
  if (!fresh) {
    MatInfo now, kept;
    PetscCall(MatGetInfo(P, MAT_LOCAL, &now));
    PetscCall(MatGetInfo(abs_, MAT_LOCAL, &kept));
    fresh = now.nz_used != kept.nz_used;
  }
  MPI_Comm comm = MPI_COMM_NULL;
  PetscCall(PetscObjectGetComm(reinterpret_cast<PetscObject>(P), &comm));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &fresh, 1, MPI_INT, MPI_LOR, comm));
  if (fresh) {  // a new pattern
    PetscCall(MatDestroy(&abs_));
    PetscCall(VecDestroy(&ax_));
    PetscCall(VecDestroy(&y_));
    PetscCall(MatDuplicate(P, MAT_COPY_VALUES, &abs_));
    PetscCall(MatCreateVecs(abs_, &ax_, &y_));
    state_ = state;
    id_ = id;
    generation_ = pattern_generation;
  } else {
    PetscCall(MatCopy(P, abs_, SAME_NONZERO_PATTERN));
  }
  PetscBool seq = PETSC_FALSE;
  PetscCall(PetscObjectTypeCompare(reinterpret_cast<PetscObject>(abs_), MATSEQAIJ, &seq));
  if (seq) {
    PetscCall(abs_values(abs_));
  } else {
    Mat Ad = nullptr, Ao = nullptr;
    PetscCall(MatMPIAIJGetSeqAIJ(abs_, &Ad, &Ao, nullptr));
    PetscCall(abs_values(Ad));
    PetscCall(abs_values(Ao));
  }
  Vec x = nullptr;
  PetscCall(SNESGetSolution(snes, &x));
  PetscCall(VecCopy(x, ax_));
  PetscCall(VecAbs(ax_));
  PetscCall(MatMult(abs_, ax_, y_));
  PetscReal n = 0;
  PetscCall(VecNorm(y_, NORM_2, &n));
  *level = PETSC_MACHINE_EPSILON * n;
  PetscFunctionReturn(0);
}

namespace {
constexpr const char* kOrderKey = "sb_elimination_order";

PetscErrorCode model_ordering(Mat A, MatOrderingType, IS* row, IS* col) {
  PetscFunctionBeginUser;
  PetscObject obj = nullptr;
  PetscCall(PetscObjectQuery(reinterpret_cast<PetscObject>(A), kOrderKey, &obj));
  if (obj) {
    PetscCall(ISDuplicate(reinterpret_cast<IS>(obj), row));
    PetscCall(ISDuplicate(reinterpret_cast<IS>(obj), col));
  } else {
    PetscInt n = 0;
    PetscCall(MatGetLocalSize(A, &n, nullptr));
    PetscCall(ISCreateStride(PETSC_COMM_SELF, n, 0, 1, row));
    PetscCall(ISCreateStride(PETSC_COMM_SELF, n, 0, 1, col));
  }
  PetscCall(ISSetPermutation(*row));
  PetscCall(ISSetPermutation(*col));
  PetscFunctionReturn(0);
}
}  // namespace

PetscErrorCode attach_elimination_order(Mat A, const std::vector<PetscInt>& order) {
  PetscFunctionBeginUser;
  static bool registered = false;
  if (!registered) {
    PetscCall(MatOrderingRegister(kModelOrdering, model_ordering));
    registered = true;
  }
  IS is = nullptr;
  PetscCall(ISCreateGeneral(PETSC_COMM_SELF, static_cast<PetscInt>(order.size()), order.data(), PETSC_COPY_VALUES, &is));
  PetscCall(ISSetPermutation(is));
  PetscCall(PetscObjectCompose(reinterpret_cast<PetscObject>(A), kOrderKey, reinterpret_cast<PetscObject>(is)));
  PetscCall(ISDestroy(&is));
  PetscFunctionReturn(0);
}

PetscErrorCode reset_factorization_on_pattern_change(SNES snes, int generation, int* seen) {
  PetscFunctionBeginUser;
  if (generation == *seen) PetscFunctionReturn(0);
  *seen = generation;
  PetscCall(PetscInfo(snes, "Jacobian pattern changed (generation %d): the factorisation is set up anew\n", generation));
  PetscCall(reset_snes_pc(snes));
  PetscFunctionReturn(0);
}

SolveResult solve_result(SNES snes) {
  SolveResult r;
  SNESConvergedReason reason;
  SB_CHECK(SNESGetConvergedReason(snes, &reason));
  r.reason = static_cast<int>(reason);
  PetscInt it = 0, lit = 0;
  SB_CHECK(SNESGetIterationNumber(snes, &it));
  SB_CHECK(SNESGetLinearSolveIterations(snes, &lit));
  r.iterations = static_cast<int>(it);
  r.linear_iterations = static_cast<int>(lit);
  PetscReal fnorm = 0;
  SB_CHECK(SNESGetFunctionNorm(snes, &fnorm));
  r.residual_norm = fnorm;
  return r;
}

const char* reason_name(int reason) { return SNESConvergedReasons[reason]; }

}  // namespace slidebeam
