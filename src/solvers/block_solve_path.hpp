// SPDX-License-Identifier: MIT
#pragma once
/// @file The parallel linear solve of a Newton solver whose Jacobian is regular on every rank's
/// block: a time step's c0 M + K, a continuation step's K + M/h^2 (EquilibriumSolver). Schwarz on
/// the model's subdomains (configure_schwarz), by default block Jacobi with each rank's block
/// solved condensed and exactly: one application per Newton step where no two ranks are coupled,
/// made exact by the coupling correction where they are (prepare_schwarz), and the manifold update
/// of each rank's triads in the line search. Statics proper (no mass) cannot take it: a stretch
/// of rope on a rank of its own floats.

#include "model/model.hpp"
#include "solvers/director_condensation.hpp"

#include <petscsnes.h>

#include <algorithm>
#include <memory>

namespace slidebeam {

class BlockSolvePath {
 public:
  /// How the Jacobians were solved: with one block application (ranks not coupled), one
  /// application plus the coupling correction, or GMRES; and the most rows of a rank coupled to
  /// another rank that any of them had.
  struct Counts {
    long blocks = 0, corrected = 0, krylov = 0;
    long coupled_rows = 0;
    /// The counts of two stretches of a run (the block path is built anew after a fall-back).
    Counts& operator+=(const Counts& o) {
      blocks += o.blocks, corrected += o.corrected, krylov += o.krylov;
      coupled_rows = std::max(coupled_rows, o.coupled_rows);
      return *this;
    }
  };
  /// Whether the solver of `prefix` takes this path (schwarz_requested: several ranks, unless the
  /// options name a solver).
  static bool requested(MPI_Comm comm, const char* prefix);
  /// Configure snes, whose prefix is `prefix` (after configure_newton, before SNESSetFromOptions).
  /// Collective.
  BlockSolvePath(const Model& model, SNES snes, Mat J, const char* prefix);
  BlockSolvePath(const BlockSolvePath&) = delete;
  BlockSolvePath& operator=(const BlockSolvePath&) = delete;
  ~BlockSolvePath();

  /// In the SNES's Jacobian callback, after J is assembled (pattern_changed: its factorisation was
  /// reset for a new pattern).
  PetscErrorCode prepare(Mat J, bool pattern_changed);
  /// The manifold update of the triads (line search), or nullptr: the step's force state and
  /// the predictor's projection go to it.
  DirectorCondensation* update() const { return update_.get(); }
  const Counts& counts() const { return counts_; }
  /// Hand the SNES over to another linear solver for good: the preconditioner's set-up dropped,
  /// the coupling correction detached, the line search basic (no manifold update).
  PetscErrorCode detach();

 private:
  /// Block Jacobi's block solver becomes the exact condensed solve.
  PetscErrorCode condense_blocks(Mat J);

  const Model& model_;
  SNES snes_ = nullptr;
  std::unique_ptr<DirectorCondensation> blocks_;  // exact condensed block solves
  // the manifold update of each rank's triads (line search); with ranks not coupled the block
  // solves are then the reduced solves alone
  std::unique_ptr<DirectorCondensation> update_;
  Counts counts_;
};

}  // namespace slidebeam
