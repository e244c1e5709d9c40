// SPDX-License-Identifier: MIT
#pragma once
/// @file Newton set-up shared by the static solver and the time integrators: SNES defaults
/// that suit the banded saddle-point systems of director beams, a roundoff-aware convergence
/// test, and the summary of a solve. The options database overrides every default.

#include <petscsnes.h>

#include <vector>

namespace slidebeam {

struct SolveResult {
  int reason = 0;            ///< SNESConvergedReason
  int iterations = 0;        ///< Newton iterations
  int linear_iterations = 0; ///< total KSP iterations
  double residual_norm = 0;  ///< final ||F||_2
  bool converged() const { return reason > 0; }
};

/// Memory of the roundoff convergence test (one per SNES).
struct RoundoffTest {
  double fnorm0 = 0.0, fnorm_prev = 0.0;
  double xnorm1 = 0.0;  ///< |x| of the first iterate (SNES passes no |x| at iteration 0)
  /// Whether the iterate ran away: its |F| 10x the initial one and its |x| 1000x the first
  /// iterate's. The roundoff level eps || |J| |x| || of such an iterate grows with it, so |F|
  /// below that level says nothing there.
  bool ran_away(double xnorm, double fnorm) const { return fnorm > 10.0 * fnorm0 && xnorm > 1e3 * xnorm1; }
  RoundoffTest() = default;
  ~RoundoffTest();
  RoundoffTest(const RoundoffTest&) = delete;
  RoundoffTest& operator=(const RoundoffTest&) = delete;
  static PetscErrorCode test(SNES, PetscInt it, PetscReal xnorm, PetscReal snorm, PetscReal fnorm,
                             SNESConvergedReason* reason, void* ctx);
  /// eps || |J| |x| ||_2 with the SNES's last Jacobian and current iterate: the residual that
  /// rounding x alone can cause (0 before the first Jacobian or for a matrix that is not AIJ).
  PetscErrorCode rounding_level(SNES snes, double* level);
  /// The Jacobian's pattern generation (CooAssembly::generation), set where it is assembled: a
  /// pattern rebuilt by COO preallocation can come back with the same nonzero state.
  int pattern_generation = 0;

 private:
  Mat abs_ = nullptr;  // |J|, entry by entry
  Vec ax_ = nullptr, y_ = nullptr;
  PetscObjectId id_ = 0;
  PetscObjectState state_ = -1;
  int generation_ = -1;
};

/// The SNES's KSP and PC (either pointer may be null).
PetscErrorCode snes_ksp_pc(SNES snes, KSP* ksp, PC* pc);
/// The same, the PC's set-up dropped first (before another solver takes over).
PetscErrorCode reset_snes_pc(SNES snes, KSP* ksp = nullptr, PC* pc = nullptr);
/// One application of a PC of `type` per linear solve (KSPPREONLY): a direct solve. Its PC.
PetscErrorCode set_preonly(SNES snes, PCType type, PC* pc);

/// Newton line search off, tolerances, divergence test off, roundoff test, direct LU (SuperLU
/// serial, MUMPS parallel). Call before SNESSetFromOptions.
PetscErrorCode configure_newton(SNES snes, RoundoffTest* test);
/// MUMPS's workspace (ICNTL(14) = 200 %: pivoting on the zero diagonal of the saddle-point
/// matrix needs more than its analysis reserves) for the solver of `prefix`, unless given.
PetscErrorCode default_mumps_workspace(const char* prefix);

/// After the Jacobian's sparsity pattern changed (a sliding joint moved its window of carrier
/// points: CooAssembly::generation differs from *seen), reset the SNES's preconditioner so that
/// the next set-up factors the matrix symbolically anew; a numeric refactorisation on the old
/// symbolic structure would read the wrong memory (MUMPS crashed so).
PetscErrorCode reset_factorization_on_pattern_change(SNES snes, int generation, int* seen);

/// Name of the MatOrdering that factors a matrix in the permutation attached to it by
/// attach_elimination_order (PCFactorSetMatOrderingType(pc, kModelOrdering), or
/// -pc_factor_mat_ordering_type sb_model); natural order on a matrix without one.
inline constexpr const char* kModelOrdering = "sb_model";
/// Attach a permutation (new position -> old index, Model::elimination_order) to a sequential
/// matrix for the kModelOrdering ordering (registers it on first use).
PetscErrorCode attach_elimination_order(Mat A, const std::vector<PetscInt>& order);

/// Reason, iterations and final residual of the last SNESSolve.
SolveResult solve_result(SNES snes);

/// Name of a SNESConvergedReason.
const char* reason_name(int reason);

}  // namespace slidebeam
