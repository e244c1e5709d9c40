// SPDX-License-Identifier: MIT
#pragma once
/// @file Static equilibrium at a given (pseudo-)time: one SNES Newton solve with the exact
/// Jacobian, on the director constraint manifold (ManifoldNewton: condensed LU and rotated
/// directors, as in the time steps). Defaults suit the banded saddle-point systems of beams; the
/// options database (no prefix: -snes_*, -ksp_*, -pc_*) overrides every one of them.

#include "model/model.hpp"
#include "solvers/manifold_newton.hpp"
#include "solvers/newton.hpp"

#include <memory>

namespace slidebeam {

class StaticSolver {
 public:
  explicit StaticSolver(Model& model);
  ~StaticSolver();
  StaticSolver(const StaticSolver&) = delete;
  StaticSolver& operator=(const StaticSolver&) = delete;

  /// Solve F(x; t) = 0 starting from the model's current x (updated in place), with the
  /// attempts asked for (ManifoldNewton::Attempts): `first` alone ends at a zero pivot or a
  /// third of the iteration limit, so that the caller can take the step to the pseudo-transient
  /// continuation before the `fallbacks`.
  SolveResult solve(double t, ManifoldNewton::Attempts attempts = ManifoldNewton::Attempts::all);
  SNES snes() const { return snes_; }
  /// Newton on the manifold with the condensed LU (false: the full system's LU, or plain Newton).
  bool condensed() const { return manifold_ && manifold_->condensed(); }
  double time() const { return t_; }
  void set_time(double t) { t_ = t; }

 private:
  static PetscErrorCode form_function(SNES, Vec x, Vec F, void* ctx);
  static PetscErrorCode form_jacobian(SNES, Vec x, Mat J, Mat P, void* ctx);
  RoundoffTest test_;
  Model& model_;
  SNES snes_ = nullptr;
  double t_ = 0.0;
  int pattern_seen_ = 0;  // CooAssembly generation the factorisation was set up for
  std::unique_ptr<ManifoldNewton> manifold_;
};

}  // namespace slidebeam
