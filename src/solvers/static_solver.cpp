// SPDX-License-Identifier: MIT
#include "solvers/static_solver.hpp"

#include "solvers/solver_options.hpp"
#include "util/petsc_check.hpp"

namespace slidebeam {

StaticSolver::StaticSolver(Model& model) : model_(model) {
  finalize_from_options(model);
  SB_CHECK(SNESCreate(model.comm(), &snes_));
  SB_CHECK(set_solver_prefix(snes_, kStaticPrefix));  // -sb_static_snes_rtol, or plain -snes_rtol
  SB_CHECK(SNESSetFunction(snes_, model.residual_vector(), guarded<&StaticSolver::form_function>, this));
  SB_CHECK(SNESSetJacobian(snes_, model.jacobian(), model.jacobian(), guarded<&StaticSolver::form_jacobian>, this));
  SB_CHECK(configure_newton(snes_, &test_));
  manifold_ = std::make_unique<ManifoldNewton>(model, snes_);
  SB_CHECK(SNESSetFromOptions(snes_));
}

StaticSolver::~StaticSolver() {
  manifold_.reset();
  SNESDestroy(&snes_);
}

PetscErrorCode StaticSolver::form_function(SNES, Vec x, Vec F, void* ctx) {
  PetscFunctionBeginUser;
  auto* self = static_cast<StaticSolver*>(ctx);
  PetscCall(self->model_.assemble_residual(self->t_, x, F));
  PetscFunctionReturn(0);
}

PetscErrorCode StaticSolver::form_jacobian(SNES snes, Vec x, Mat J, Mat, void* ctx) {
  PetscFunctionBeginUser;
  auto* self = static_cast<StaticSolver*>(ctx);
  PetscCall(self->model_.assemble_jacobian(self->t_, x, J));
  self->test_.pattern_generation = self->model_.jacobian_pattern_generation();
  PetscCall(reset_factorization_on_pattern_change(snes, self->model_.jacobian_pattern_generation(), &self->pattern_seen_));
  PetscFunctionReturn(0);
}

SolveResult StaticSolver::solve(double t, ManifoldNewton::Attempts attempts) {
  t_ = t;
  model_.set_prescribed_time(t);
  model_.apply_prescribed(model_.x());
  return manifold_->solve(model_.x(), false, attempts);
}

}  // namespace slidebeam
