// SPDX-License-Identifier: MIT
#pragma once
/// @file Static equilibrium at a given (pseudo-)time: one SNES Newton solve with the exact
/// Jacobian. Defaults suit the banded saddle-point systems of beams; the options database
/// (no prefix: -snes_*, -ksp_*, -pc_*) overrides every one of them.

#include "model/model.hpp"

#include <petscsnes.h>

namespace slidebeam {

struct SolveResult {
  int reason = 0;            ///< SNESConvergedReason
  int iterations = 0;        ///< Newton iterations
  int linear_iterations = 0; ///< total KSP iterations
  double residual_norm = 0;  ///< final ||F||_2
  bool converged() const { return reason > 0; }
};

class StaticSolver {
 public:
  explicit StaticSolver(Model& model);
  ~StaticSolver();
  StaticSolver(const StaticSolver&) = delete;
  StaticSolver& operator=(const StaticSolver&) = delete;

  /// Solve F(x; t) = 0 starting from the model's current x (updated in place).
  SolveResult solve(double t);
  SNES snes() const { return snes_; }
  double time() const { return t_; }
  void set_time(double t) { t_ = t; }
  /// Name of the SNESConvergedReason.
  static const char* reason_name(int reason);

 private:
  static PetscErrorCode form_function(SNES, Vec x, Vec F, void* ctx);
  static PetscErrorCode form_jacobian(SNES, Vec x, Mat J, Mat P, void* ctx);
  static PetscErrorCode converged(SNES, PetscInt it, PetscReal xnorm, PetscReal snorm, PetscReal fnorm,
                                  SNESConvergedReason* reason, void* ctx);
  double fnorm0_ = 0.0, fnorm_prev_ = 0.0;
  Model& model_;
  SNES snes_ = nullptr;
  double t_ = 0.0;
};

}  // namespace slidebeam
