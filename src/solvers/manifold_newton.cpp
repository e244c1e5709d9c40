// SPDX-License-Identifier: MIT
#include "solvers/manifold_newton.hpp"

#include "solvers/solver_options.hpp"
#include "util/petsc_check.hpp"

#include <algorithm>
#include <cmath>

namespace slidebeam {

ManifoldNewton::ManifoldNewton(const Model& model, SNES snes) : snes_(snes) {
  const CoreOptions options = core_options(model.comm());
  if (!options.condense_directors) return;
  const PetscBool exponential = options.exponential_update;
  int size = 1;
  MPI_Comm_size(model.comm(), &size);
  // A solver or preconditioner from the options database is the user's: keep it (full system).
  const char* prefix = nullptr;
  SB_CHECK(SNESGetOptionsPrefix(snes, &prefix));
  const bool user_solver = solver_option_set(prefix, "-pc_factor_mat_solver_type");
  const bool user_pc = solver_option_set(prefix, "-pc_type");
  if (size == 1 && !user_solver && !user_pc) {
    condensation_ = std::make_unique<DirectorCondensation>(model, model.elimination_order());
    if (condensation_->empty()) {
      condensation_.reset();
      return;
    }
    active_ = true;
    serial_ = true;
    condensation_->set_exponential_update(exponential);
    SB_CHECK(use_condensed());
  } else {
    condensation_ = std::make_unique<DirectorCondensation>(model, model.elimination_order(),
                                                           DirectorCondensation::Mode::Update);
    int any = condensation_->empty() ? 0 : 1;
    MPI_Allreduce(MPI_IN_PLACE, &any, 1, MPI_INT, MPI_MAX, model.comm());
    if (!any) {
      condensation_.reset();
      return;
    }
    active_ = true;
    condensation_->set_exponential_update(exponential);
    SB_CHECK(condensation_->attach_update(snes_));
  }
  SB_CHECK(VecDuplicate(model.x(), &x_start_));
}

ManifoldNewton::~ManifoldNewton() { VecDestroy(&x_start_); }

PetscErrorCode ManifoldNewton::use_condensed() {
  PetscFunctionBeginUser;
  PetscCall(reset_snes_pc(snes_));
  PetscCall(condensation_->attach(snes_));  // PC shell (condensed LU) and the manifold line search
  condensed_ = true;
  PetscFunctionReturn(0);
}

PetscErrorCode ManifoldNewton::use_full_lu() {
  PetscFunctionBeginUser;
  PC pc = nullptr;
  PetscCall(reset_snes_pc(snes_));
  PetscCall(set_preonly(snes_, PCLU, &pc));
  PetscCall(PCFactorSetMatSolverType(pc, MATSOLVERSUPERLU));
  // (the line search stays: the serial triads' numbering is the full system's)
  condensed_ = false;
  PetscFunctionReturn(0);
}

PetscErrorCode ManifoldNewton::project(Vec x) const {
  PetscFunctionBeginUser;
  if (condensation_) PetscCall(condensation_->project(x));
  PetscFunctionReturn(0);
}

SolveResult ManifoldNewton::attempt(Vec x, PetscInt max_it) {
  PetscReal atol = 0, rtol = 0, stol = 0;
  PetscInt it = 0, maxf = 0;
  SB_CHECK(SNESGetTolerances(snes_, &atol, &rtol, &stol, &it, &maxf));
  SB_CHECK(SNESSetTolerances(snes_, atol, rtol, stol, max_it, maxf));
  SB_CHECK(VecCopy(x_start_, x));
  if (!condensed_) ++full_system_attempts_;
  SB_CHECK(SNESSolve(snes_, nullptr, x));
  SB_CHECK(SNESSetTolerances(snes_, atol, rtol, stol, it, maxf));
  SolveResult r = solve_result(snes_);
  if (r.converged() && !std::isfinite(r.residual_norm)) r.reason = SNES_DIVERGED_FNORM_NAN;
  return r;
}

SolveResult ManifoldNewton::solve(Vec x, bool pivoting, Attempts attempts) {
  if (!active_) {
    ++full_system_attempts_;
    SB_CHECK(SNESSolve(snes_, nullptr, x));
    return solve_result(snes_);
  }
  SB_CHECK(project(x));
  SB_CHECK(VecCopy(x, x_start_));
  PetscReal atol = 0, rtol = 0, stol = 0;
  PetscInt max_it = 0, maxf = 0;
  SB_CHECK(SNESGetTolerances(snes_, &atol, &rtol, &stol, &max_it, &maxf));
  if (pivoting && condensed_) SB_CHECK(use_full_lu());
  SolveResult total;
  auto add = [&](const SolveResult& r) {
    total.reason = r.reason;
    total.iterations += r.iterations;
    total.linear_iterations += r.linear_iterations;
    total.residual_norm = r.residual_norm;
    return r.converged();
  };
  // 1. least-squares multipliers (condensed LU when serial). Where they converge they take up to
  // about 13 iterations on large load steps (a slender assumed-strain cantilever turning 20
  // degrees a step); a third of the limit (16 of the static solve's 50) leaves the rest to the
  // fall-back.
  const PetscInt first_limit = std::min(max_it, std::max<PetscInt>(10, max_it / 3));
  auto restore = [&]() {  // the condensed LU for the next solve, unless it met a zero pivot
    if (serial_ && !condensed_failed_ && !condensed_) SB_CHECK(use_condensed());
  };
  if (attempts != Attempts::fallbacks) {
    SolveResult r = attempt(x, first_limit);
    if (add(r)) {
      restore();
      return total;
    }
    if (condensed_ && r.reason == SNES_DIVERGED_LINEAR_SOLVE) {
      SB_CHECK(PetscInfo(snes_, "Condensed LU failed (zero pivot): the pivoting LU on the full system from now on\n"));
      condensed_failed_ = true;
      SB_CHECK(use_full_lu());
      if (attempts == Attempts::first) return total;
      if (add(attempt(x, first_limit))) return total;
    }
    if (attempts != Attempts::all) {
      restore();
      return total;
    }
  }
  // 2. Newton's multipliers, directors still rotated (full system)
  SB_CHECK(PetscInfo(snes_, "Manifold Newton failed (%s): once more with Newton's multipliers on the full system\n",
                     reason_name(total.reason)));
  if (condensed_) SB_CHECK(use_full_lu());
  condensation_->set_newton_multipliers(true);
  const bool converged = add(attempt(x, max_it));
  condensation_->set_newton_multipliers(false);
  if (!converged) {
    // 3. plain Newton on the full system: directors updated linearly, back on the manifold only
    // at convergence (the path of -sb_condense_directors false)
    SB_CHECK(PetscInfo(snes_, "Once more with plain Newton on the full system\n"));
    SNESLineSearch ls = nullptr;
    SB_CHECK(SNESGetLineSearch(snes_, &ls));
    SB_CHECK(SNESLineSearchSetType(ls, SNESLINESEARCHBASIC));
    add(attempt(x, max_it));
    SB_CHECK(condensation_->attach_update(snes_));
  }
  restore();
  return total;
}

}  // namespace slidebeam
