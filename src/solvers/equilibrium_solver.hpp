// SPDX-License-Identifier: MIT
#pragma once
/// @file Static equilibrium of a scene that may be a mechanism at its start: a hanging beam that
/// can swing about its slider, a slider free to move along a straight cable, a straight cable
/// whose only transverse stiffness is a tiny EI. Plain Newton on F(x) = 0 meets a singular or
/// nearly singular tangent there (zero tension: zero geometric stiffness). Pseudo-transient
/// continuation (Kelley & Keyes 1998) solves instead a sequence of heavily damped steps from rest
///
///   F(x) + M (x - x_k) / h_k^2 = 0,
///
/// whose matrix K + M/h^2 is regular wherever a dynamic step's is, and lets h grow by the ratio
/// of successive residuals (switched evolution relaxation) until the term vanishes: the limit is
/// a root of F: the continuation ends at the tolerance or at the residual's roundoff floor. Only
/// where it stalls close to equilibrium does a plain Newton solve (the polish, on a pivoting LU
/// of the whole system) try to finish it. Sliders can be held (s prescribed at its current value) during the solve.
/// Every Newton solve, the continuation's and the polish, is Newton on the director constraint
/// manifold (ManifoldNewton), as in the time steps.
///
/// Distributed, a continuation step's matrix K + M/h^2 is regular on every rank's block as a time
/// step's is, so its Newton solve takes the time steps' parallel path (BlockSolvePath: condensed
/// exact blocks, the coupling correction where ranks are coupled, one application per Newton
/// step) on a SNES of its own. A step that fails on the fast solve (this, or the condensed LU
/// serially) is cut to half its pseudo-step; only after two cuts in a row is it tried again on
/// the direct solve of the whole system (MUMPS, SuperLU serially). A polish, K alone (a rank's stretch of rope floats),
/// is MUMPS's. -sb_equilibrium_blocks false: every solve on MUMPS.

#include "model/model.hpp"
#include "solvers/block_solve_path.hpp"
#include "solvers/manifold_newton.hpp"
#include "solvers/newton.hpp"

#include <memory>

#include <vector>

namespace slidebeam {

struct EquilibriumResult {
  bool converged = false;
  int pseudo_steps = 0;       ///< continuation steps taken (accepted)
  int block_steps = 0;        ///< ... of which solved on the parallel block path (distributed)
  int full_system_steps = 0;  ///< ... of which needed the pivoting LU of the whole saddle-point system
  int cut_steps = 0;          ///< continuation steps whose solve failed, retried with half the pseudo-step
  int newton_iterations = 0;  ///< all Newton iterations, polish included
  double residual0 = 0.0;     ///< ||F|| of the start state
  double residual = 0.0;      ///< ||F|| of the final state
  bool polished = false;      ///< a plain Newton solve finished what the continuation could not
  bool at_roundoff = false;   ///< stopped at the residual's roundoff floor, the state at rest
  int interrupted = 0;        ///< the signal (SIGINT, SIGTERM) that stopped the continuation, or 0
};

class EquilibriumSolver {
 public:
  explicit EquilibriumSolver(Model& model);
  ~EquilibriumSolver();
  EquilibriumSolver(const EquilibriumSolver&) = delete;
  EquilibriumSolver& operator=(const EquilibriumSolver&) = delete;

  /// Unknowns kept at their current values during the solve (held sliding coordinates); global
  /// indices, any rank may list any row.
  void set_held(const std::vector<PetscInt>& rows);
  /// Unknowns that must stay within [lo, hi] (free sliders' s within their carriers): a
  /// continuation step or the polish that leaves the range is rejected (the step cut, the polish
  /// dropped). Without it, the polish's plain Newton can land on a stationary point of the
  /// carrier's curve extended beyond its end. Global indices, any rank may list any row.
  void set_bounds(const std::vector<PetscInt>& rows, const std::vector<double>& lo, const std::vector<double>& hi);
  /// Continuation from the model's current x to equilibrium under the loads at time t, with
  /// initial pseudo-step h0 (the scene's dt is a good start), to ||F|| <= rtol ||F_0|| (or the
  /// Newton tolerance). x is updated in place: the last accepted state if it did not converge.
  EquilibriumResult solve(double t, double h0, double rtol = 1e-10, int max_steps = 200);
  SNES snes() const { return snes_; }

 private:
  static PetscErrorCode form_function(SNES, Vec x, Vec F, void* ctx);
  static PetscErrorCode form_jacobian(SNES, Vec x, Mat J, Mat P, void* ctx);
  static PetscErrorCode converged(SNES, PetscInt it, PetscReal xnorm, PetscReal snorm, PetscReal fnorm,
                                  SNESConvergedReason* reason, void* ctx);
  PetscErrorCode static_residual_norm(Vec x, double* norm);
  /// A Newton SNES (prefix sb_eq_) on F + c M (x - x_k) and its Jacobian J_, with this solver's
  /// convergence test, at most max_it iterations; before SNESSetFromOptions.
  SNES newton_snes(PetscInt max_it);

  Model& model_;
  RoundoffTest test_;
  SNES snes_ = nullptr;
  SNES block_snes_ = nullptr;  // distributed continuation steps (BlockSolvePath), or null
  std::unique_ptr<BlockSolvePath> blocks_;
  Mat J_ = nullptr, M_ = nullptr;
  CooAssembly coo_;
  Vec x_k_ = nullptr, work_ = nullptr;
  /// Whether every bounded row of x is within its range (collective).
  bool within_bounds(Vec x) const;

  std::vector<PetscInt> held_;  // owned rows
  struct Bound {
    PetscInt row;  // owned
    double lo, hi;
  };
  std::vector<Bound> bounds_;
  double t_ = 0.0;
  double c_ = 0.0;  // 1 / h^2 (0: plain statics)
  // A continuation step's solve on the fast path alone gives up at the second rise of |F| after
  // its first iterate (converged's count): the caller cuts the pseudo-step instead.
  bool give_up_on_rises_ = false;
  int rises_ = 0;
  int pattern_seen_ = 0, block_pattern_seen_ = 0;
  std::unique_ptr<ManifoldNewton> manifold_;
  /// Newton on the continuation step from x on the block path; false if it failed (x then
  /// undefined).
  bool block_solve(Vec x, int* iterations);
};

}  // namespace slidebeam
