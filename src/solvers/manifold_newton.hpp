// SPDX-License-Identifier: MIT
#pragma once
/// @file Newton on the director constraint manifold for the static solves (StaticSolver and the
/// continuation of EquilibriumSolver), as in the time steps (DirectorCondensation).
///
/// Plain Newton on the saddle-point system updates directors linearly, d + dd: the iterate leaves
/// the manifold by O(|w|^2), the orthonormality multipliers absorb the error, and the next
/// Jacobian is taken at a state no equilibrium is near. A load step of a large rotation then
/// needs several iterations before the quadratic range (the roll-up, 64 spans, 20 steps: 7 per
/// step). Here every iterate is a rotation of the last one: the Newton step's director part
/// w x d_i is applied as the rotation exp([w]x) (-sb_exponential_update false: the closest
/// orthonormal frame of d + w x d, as in the time steps), and the multipliers are set from the
/// force rows (least squares), so Newton solves the 6-unknown-per-point equilibrium of the
/// triads with the Jacobian N^T J N' (exact at equilibrium; off it short by a term proportional
/// to the residual, sum_i [f_i]x [d_i]x per triad, so convergence stays quadratic).
///
/// Serial: the condensed LU of DirectorCondensation (Manifold mode). Several ranks, or a linear
/// solver chosen in the options database: that solve on the full system, with the manifold
/// update on each rank's triads (DirectorCondensation, Update mode). On the manifold the full
/// system's step has C dq = 0, so both give the same iterates.
///
/// The least-squares multipliers make the Jacobian that of the reduced equations at
/// equilibrium, hence the fast local convergence; far from equilibrium they are what the
/// unbalanced director forces make them, and a large load step can fail where other Newton
/// variants still converge. So a solve that fails, or takes more than a quarter of the
/// iteration limit, is tried again from the same start on the full system: first with Newton's
/// own multipliers (the directors still rotated), then with plain Newton (linear
/// director updates, as with -sb_condense_directors false). A zero pivot of the condensed LU (a
/// mechanism, a free slider without stiffness) leaves it for the pivoting LU (SuperLU) for good.
/// Only then does the caller cut the load step. Each fall-back converges where the others fail
/// on some of the large load steps measured (docs/verification.md).
/// -sb_condense_directors false: plain Newton on the full system (linear director updates).

#include "model/model.hpp"
#include "solvers/director_condensation.hpp"
#include "solvers/newton.hpp"

#include <memory>

namespace slidebeam {

class ManifoldNewton {
 public:
  /// Configure snes (after configure_newton, before SNESSetFromOptions). Collective.
  ManifoldNewton(const Model& model, SNES snes);
  ~ManifoldNewton();
  ManifoldNewton(const ManifoldNewton&) = delete;
  ManifoldNewton& operator=(const ManifoldNewton&) = delete;

  /// Any rank has a triad on the manifold update.
  bool active() const { return active_; }
  /// The linear solve is the condensed LU (serial).
  bool condensed() const { return condensed_; }
  /// Replace every free triad of x by its closest orthonormal frame (a predictor's may be off).
  PetscErrorCode project(Vec x) const;
  /// The attempts of a solve: all (the first; after a zero pivot of the condensed LU, the first
  /// again on the pivoting LU; the fall-backs); first_and_pivoting_lu (no fall-backs: a
  /// continuation step, whose caller cuts the step instead); first (the first alone, ended by a
  /// zero pivot too: a static load step, whose caller takes a singular tangent to the
  /// continuation); fallbacks (the fall-backs alone, after the caller saw the first fail).
  /// After a zero pivot the condensed LU is dropped for good.
  enum class Attempts { all, first_and_pivoting_lu, first, fallbacks };
  /// Newton from x (projected first); the attempts asked for, each from the same x. The
  /// iterations of every attempt count. pivoting: the pivoting LU on the full system instead of
  /// the condensed LU for this solve (a tangent that may be singular).
  SolveResult solve(Vec x, bool pivoting = false, Attempts attempts = Attempts::all);
  /// Newton attempts so far on the full saddle-point system (the pivoting LU: SuperLU serially,
  /// MUMPS on several ranks), not on the condensed LU.
  long full_system_attempts() const { return full_system_attempts_; }

 private:
  PetscErrorCode use_condensed();
  PetscErrorCode use_full_lu();
  SolveResult attempt(Vec x, PetscInt max_it);

  SNES snes_ = nullptr;
  std::unique_ptr<DirectorCondensation> condensation_;
  bool active_ = false;
  bool serial_ = false;            // the condensed LU is available (Manifold mode)
  bool condensed_ = false;         // ... and in use
  bool condensed_failed_ = false;  // it met a zero pivot: the pivoting LU from then on
  Vec x_start_ = nullptr;
  long full_system_attempts_ = 0;
};

}  // namespace slidebeam
