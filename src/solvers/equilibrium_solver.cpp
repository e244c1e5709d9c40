// SPDX-License-Identifier: MIT
#include "solvers/equilibrium_solver.hpp"

#include "solvers/solver_options.hpp"
#include "util/petsc_check.hpp"
#include "util/stop_signal.hpp"

#include <algorithm>
#include <cmath>

namespace slidebeam {

EquilibriumSolver::EquilibriumSolver(Model& model) : model_(model) {
  finalize_from_options(model);
  M_ = model.create_mass_matrix();
  SB_CHECK(MatDuplicate(model.jacobian(), MAT_DO_NOT_COPY_VALUES, &J_));
  SB_CHECK(VecDuplicate(model.x(), &x_k_));
  SB_CHECK(VecDuplicate(model.x(), &work_));
  snes_ = newton_snes(25);
  // This SNES: direct LU whatever -sb_schwarz says, since near equilibrium the continuation's
  // matrix approaches the singular tangent of a mechanism, where GMRES stalls (-pc_type and
  // friends, or -sb_eq_pc_type, still apply). Distributed continuation steps try the exact block
  // solve on a SNES of their own first (block_snes_).
  manifold_ = std::make_unique<ManifoldNewton>(model, snes_);
  SB_CHECK(SNESSetFromOptions(snes_));
  const CoreOptions options = core_options(model.comm());
  if (model.dof_map().owners() > 1 && options.equilibrium_blocks &&
      BlockSolvePath::requested(model.comm(), kEquilibriumPrefix)) {
    // (a step the block path does not solve in 10 iterations goes to the direct solve's
    // fall-backs, as the manifold Newton's first attempt does)
    block_snes_ = newton_snes(10);
    blocks_ = std::make_unique<BlockSolvePath>(model, block_snes_, J_, kEquilibriumPrefix);
    // as the manifold Newton: a continuation step's first iterate may turn a triad by tenths of a radian
    if (blocks_->update()) blocks_->update()->set_exponential_update(options.exponential_update);
    SB_CHECK(SNESSetFromOptions(block_snes_));
  }
}

SNES EquilibriumSolver::newton_snes(PetscInt max_it) {
  SNES snes = nullptr;
  SB_CHECK(SNESCreate(model_.comm(), &snes));
  SB_CHECK(set_solver_prefix(snes, kEquilibriumPrefix));  // -sb_eq_snes_rtol, or plain -snes_rtol
  SB_CHECK(SNESSetFunction(snes, model_.residual_vector(), guarded<&EquilibriumSolver::form_function>, this));
  SB_CHECK(SNESSetJacobian(snes, J_, J_, guarded<&EquilibriumSolver::form_jacobian>, this));
  SB_CHECK(configure_newton(snes, &test_));
  SB_CHECK(SNESSetTolerances(snes, 1e-10, 1e-12, 1e-12, max_it, 10000));
  SB_CHECK(SNESSetConvergenceTest(snes, guarded<&EquilibriumSolver::converged>, this, nullptr));
  return snes;
}

EquilibriumSolver::~EquilibriumSolver() {
  manifold_.reset();
  SNESDestroy(&snes_);
  SNESDestroy(&block_snes_);
  blocks_.reset();
  MatDestroy(&J_);
  MatDestroy(&M_);
  VecDestroy(&x_k_);
  VecDestroy(&work_);
}

void EquilibriumSolver::set_held(const std::vector<PetscInt>& rows) {
  held_.clear();
  const DofMap& map = model_.dof_map();
  std::vector<PetscInt> taken;  // held by an effect's own constraint already (a driven slider)
  for (const auto& e : model_.effects())
    if (const auto* held = part_of<PrescribedMotion>(*e)) held->constrained_state(taken);
  for (PetscInt r : rows)
    if (r >= map.owned_lo() && r < map.owned_hi() && std::find(taken.begin(), taken.end(), r) == taken.end())
      held_.push_back(r);
  std::sort(held_.begin(), held_.end());
  held_.erase(std::unique(held_.begin(), held_.end()), held_.end());
}

void EquilibriumSolver::set_bounds(const std::vector<PetscInt>& rows, const std::vector<double>& lo,
                                   const std::vector<double>& hi) {
  if (lo.size() != rows.size() || hi.size() != rows.size())
    throw std::invalid_argument("set_bounds: rows, lo and hi must have the same length");
  bounds_.clear();
  const DofMap& map = model_.dof_map();
  for (size_t k = 0; k < rows.size(); ++k)
    if (rows[k] >= map.owned_lo() && rows[k] < map.owned_hi()) bounds_.push_back({rows[k], lo[k], hi[k]});
}

bool EquilibriumSolver::within_bounds(Vec x) const {
  int outside = 0;
  if (!bounds_.empty()) {
    const PetscScalar* xa = nullptr;
    const PetscInt first = model_.dof_map().owned_lo();
    SB_CHECK(VecGetArrayRead(x, &xa));
    for (const Bound& b : bounds_) {
      const double v = xa[b.row - first], tol = 1e-12 * std::max(std::abs(b.lo), std::abs(b.hi));
      if (!(v >= b.lo - tol && v <= b.hi + tol)) outside = 1;
    }
    SB_CHECK(VecRestoreArrayRead(x, &xa));
  }
  MPI_Allreduce(MPI_IN_PLACE, &outside, 1, MPI_INT, MPI_MAX, model_.comm());
  return outside == 0;
}

/// F(x) + c M (x - x_k); prescribed and held rows: x_i - (prescribed value | x_k,i).
PetscErrorCode EquilibriumSolver::form_function(SNES, Vec x, Vec F, void* ctx) {
  PetscFunctionBeginUser;
  auto* self = static_cast<EquilibriumSolver*>(ctx);
  PetscCall(self->model_.assemble_effects_residual(StepEval{StepRule::Endpoint, self->t_, 1.0}, x, F));
  if (self->c_ > 0) {
    PetscCall(VecWAXPY(self->work_, -1.0, self->x_k_, x));
    PetscCall(VecScale(self->work_, self->c_));
    PetscCall(MatMultAdd(self->M_, self->work_, F, F));
  }
  PetscCall(self->model_.set_prescribed_residual_rows(x, F));
  if (!self->held_.empty()) {
    const PetscScalar *xa = nullptr, *ka = nullptr;
    PetscScalar* fa = nullptr;
    const PetscInt lo = self->model_.dof_map().owned_lo();
    PetscCall(VecGetArrayRead(x, &xa));
    PetscCall(VecGetArrayRead(self->x_k_, &ka));
    PetscCall(VecGetArray(F, &fa));
    for (PetscInt r : self->held_) fa[r - lo] = xa[r - lo] - ka[r - lo];
    PetscCall(VecRestoreArray(F, &fa));
    PetscCall(VecRestoreArrayRead(self->x_k_, &ka));
    PetscCall(VecRestoreArrayRead(x, &xa));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode EquilibriumSolver::form_jacobian(SNES snes, Vec x, Mat J, Mat, void* ctx) {
  PetscFunctionBeginUser;
  auto* self = static_cast<EquilibriumSolver*>(ctx);
  PetscCall(self->model_.assemble_effects_jacobian(StepEval{StepRule::Endpoint, self->t_, 1.0}, x, J, &self->coo_,
                                                   1.0, self->c_));
  PetscCall(self->model_.set_prescribed_jacobian_rows(J));
  PetscCall(MatZeroRows(J, static_cast<PetscInt>(self->held_.size()), self->held_.data(), 1.0, nullptr, nullptr));
  self->test_.pattern_generation = self->coo_.generation();
  if (snes == self->block_snes_) {
    const int seen = self->block_pattern_seen_;
    PetscCall(reset_factorization_on_pattern_change(snes, self->coo_.generation(), &self->block_pattern_seen_));
    PetscCall(self->blocks_->prepare(J, seen != self->block_pattern_seen_));
  } else {
    PetscCall(reset_factorization_on_pattern_change(snes, self->coo_.generation(), &self->pattern_seen_));
  }
  PetscFunctionReturn(0);
}

/// PETSc's test and the roundoff test, plus: converged once the residual stagnates with a Newton
/// step below 1e-9 of the state. Near equilibrium the residual sits at its roundoff floor
/// (large EA times 1e-16), which no relative decrease can pass.
PetscErrorCode EquilibriumSolver::converged(SNES snes, PetscInt it, PetscReal xnorm, PetscReal snorm, PetscReal fnorm,
                                            SNESConvergedReason* reason, void* ctx) {
  PetscFunctionBeginUser;
  auto* self = static_cast<EquilibriumSolver*>(ctx);
  const double prev = self->test_.fnorm_prev;
  PetscCall(RoundoffTest::test(snes, it, xnorm, snorm, fnorm, reason, &self->test_));
  if (*reason == SNES_CONVERGED_ITERATING && it > 1 && fnorm >= 0.5 * prev && snorm <= 1e-9 * xnorm)
    *reason = SNES_CONVERGED_SNORM_RELATIVE;
  // The first iterate's |F| may grow tenfold (directors, a slack cable pulled taut) before Newton
  // converges; a solve whose |F| rises twice after that oscillates, and mostly runs to the
  // iteration limit (a continuation step of a rope bundle: 10 iterations, then cut).
  if (it == 0) self->rises_ = 0;
  if (it > 1 && fnorm > prev) ++self->rises_;
  if (*reason == SNES_CONVERGED_ITERATING && self->give_up_on_rises_ && self->rises_ >= 2) {
    PetscCall(PetscInfo(snes, "|F| rose twice after the first iterate: the continuation step is cut\n"));
    *reason = SNES_DIVERGED_DTOL;
  }
  PetscFunctionReturn(0);
}

/// ||F(x)|| of plain statics (held rows count as satisfied).
PetscErrorCode EquilibriumSolver::static_residual_norm(Vec x, double* norm) {
  PetscFunctionBeginUser;
  const double c = c_;
  c_ = 0.0;
  PetscCall(VecCopy(x, x_k_));  // held rows: x_i - x_i = 0
  PetscCall(form_function(snes_, x, work_, this));
  c_ = c;
  PetscReal n = 0;
  PetscCall(VecNorm(work_, NORM_2, &n));
  *norm = n;
  PetscFunctionReturn(0);
}

bool EquilibriumSolver::block_solve(Vec x, int* iterations) {
  SB_CHECK(SNESSolve(block_snes_, nullptr, x));
  const SolveResult s = solve_result(block_snes_);
  *iterations += s.iterations;
  return s.converged() && std::isfinite(s.residual_norm);
}

EquilibriumResult EquilibriumSolver::solve(double t, double h0, double rtol, int max_steps) {
  EquilibriumResult res;
  t_ = t;
  Vec x = model_.x();
  model_.set_prescribed_time(t);
  model_.apply_prescribed(x);
  Vec x_start = nullptr;
  SB_CHECK(VecDuplicate(x, &x_start));
  double r = 0.0;
  SB_CHECK(static_residual_norm(x, &r));
  res.residual0 = r;
  const double target = std::max(rtol * r, 1e-10);
  double h = h0;
  SNES last_snes = snes_;  // the solver of the last Newton solve
  // fast_only: the fast solve alone (the condensed LU; the block path on several ranks). A
  // continuation step it does not solve is cut first: a smaller pseudo-step is cheaper than the
  // fall-backs on the full saddle-point system, whose pivoting LU grows much faster than the
  // system (a step of a 34k-unknown bundle: 16 SuperLU factorisations, 17 s, where the halved
  // step took 8 condensed iterations, 0.3 s).
  auto newton = [&](double c, bool fast_only) {
    c_ = c;
    give_up_on_rises_ = fast_only && c > 0.0;
    last_snes = snes_;
    SB_CHECK(manifold_->project(x));  // x_k on the manifold too: the pull c M (x - x_k) vanishes at x = x_k
    SB_CHECK(VecCopy(x, x_k_));
    if (c > 0.0 && blocks_) {  // distributed: the block path first, then the direct solve from the same start
      last_snes = block_snes_;
      if (block_solve(x, &res.newton_iterations)) return true;
      if (fast_only) return false;
      last_snes = snes_;
      SB_CHECK(PetscInfo(snes_, "continuation step failed on the block solve: once more on the direct solve\n"));
      SB_CHECK(VecCopy(x_k_, x));
    }
    // The polish (c = 0) meets the tangent of a mechanism, singular or nearly so: a pivoting LU.
    const SolveResult s = manifold_->solve(x, c == 0.0, fast_only ? ManifoldNewton::Attempts::first_and_pivoting_lu : ManifoldNewton::Attempts::all);
    res.newton_iterations += s.iterations;
    return s.converged() && std::isfinite(s.residual_norm);
  };
  int cuts = 0;
  while (r > target && res.pseudo_steps < max_steps) {
    if ((res.interrupted = stop_signal(model_.comm())) != 0) break;
    SB_CHECK(VecCopy(x, x_start));
    const long full_before = manifold_->full_system_attempts();
    // the fall-backs only once the pseudo-step has been cut twice in a row
    if (!newton(1.0 / (h * h), cuts < 2) || !within_bounds(x)) {
      SB_CHECK(VecCopy(x_start, x));
      ++res.cut_steps;
      h *= 0.5;
      if (++cuts > 12) break;  // in a row: 1/4096 of the pseudo-step that last worked
      continue;
    }
    cuts = 0;
    ++res.pseudo_steps;
    if (last_snes == block_snes_) ++res.block_steps;
    if (manifold_->full_system_attempts() != full_before) ++res.full_system_steps;
    double r_new = 0.0, dx = 0.0, xn = 0.0;
    SB_CHECK(static_residual_norm(x, &r_new));
    // how far the coordinates moved (multipliers are as noisy as the residual is small)
    SB_CHECK(VecWAXPY(work_, -1.0, x_start, x));
    SB_CHECK(VecPointwiseMult(work_, work_, model_.coordinate_mask()));
    SB_CHECK(VecNorm(work_, NORM_INFINITY, &dx));
    SB_CHECK(VecPointwiseMult(work_, x, model_.coordinate_mask()));
    SB_CHECK(VecNorm(work_, NORM_INFINITY, &xn));
    // The pseudo-step grows with the residual's fall (switched evolution relaxation, at most 10x
    // a step), and at least 4x after an easy solve (up to 3 iterations: the first steps, where
    // |F| hardly falls, would otherwise double it a dozen times), 2x after a moderate one (4-5);
    // after a hard one by the fall alone, at most 2x. On the 1e5-unknown bundle of
    // scripts/bench_start.py: 14 steps and 71 iterations, where "2x up to 6 iterations" took 17
    // and 101, and growing after 6 iterations made more steps fail.
    const SolveResult last = solve_result(last_snes);
    const double ser = std::sqrt(r / std::max(r_new, 1e-300));
    const PetscInt its = last.iterations;
    h *= its <= 3 ? std::clamp(ser, 4.0, 10.0) : its <= 5 ? std::clamp(ser, 2.0, 10.0) : std::clamp(ser, 1.0, 2.0);
    const bool stagnant = r_new >= 0.5 * r;
    SB_CHECK(PetscInfo(snes_, "continuation step %d: h %g, |F| %g, |dx| %g, |x| %g, Newton %d\n", res.pseudo_steps,
                       h, r_new, dx, xn, static_cast<int>(last.iterations)));
    r = r_new;
    // At the residual's roundoff floor (large EA times 1e-16) it stops falling: that is the
    // equilibrium. Stop there: a mechanism (a hanger's spin about its own axis, free at a
    // slider) leaves the plain tangent singular, and ever larger pseudo-steps would let roundoff
    // drive the state along it.
    if (stagnant && r <= 1e-6 * res.residual0) {
      res.at_roundoff = true;
      break;
    }
    if (stagnant && r <= 1e-4 * res.residual0) break;  // close, but no longer converging: see below
  }
  // Where the continuation ended close to equilibrium without reaching the tolerance (stagnating,
  // its pseudo-step cut to nothing, or out of steps), plain Newton once: not from far away, where
  // it may find an unstable equilibrium (a hanger pointing up). It is the last resort, not the
  // finish: the continuation closes the gap in 2-3 more steps at up to 10x the pseudo-step each,
  // on the condensed (or block) solve, where the plain tangent needs the pivoting LU of the whole
  // saddle-point system (SuperLU, MUMPS on several ranks), several times as costly on a rope
  // (docs/performance.md, "The equilibrium start on several ranks").
  if (res.interrupted == 0 && !(r <= target || res.at_roundoff) && r <= 1e-4 * res.residual0) {
    SB_CHECK(VecCopy(x, x_start));
    if (newton(0.0, false) && within_bounds(x)) {
      SB_CHECK(static_residual_norm(x, &r));
      res.polished = true;
    } else {
      SB_CHECK(VecCopy(x_start, x));
    }
  }
  c_ = 0.0;
  res.residual = r;
  res.converged = res.interrupted == 0 && (r <= target || res.polished || res.at_roundoff);
  SB_CHECK(VecDestroy(&x_start));
  return res;
}

}  // namespace slidebeam
