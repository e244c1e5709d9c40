// SPDX-License-Identifier: MIT
#pragma once
/// @file The exact parallel solve of block Jacobi on coupled ranks: one block application plus
/// a correction on the few unknowns through which the ranks couple (a capacitance, or Woodbury,
/// correction; exact substructuring on the separators).
///
/// Split the Jacobian by ranks, A = D + E: D = diag(A_11, ..., A_PP) the ranks' diagonal blocks,
/// which block Jacobi solves exactly, E the entries that couple two ranks. E is nonzero only in
/// the rows and columns of the interface I: the unknowns of a beam cut between two ranks (its
/// p = 2 control points next to the cut, with their multipliers) and those of joints and sliders
/// whose two sides lie on two ranks. With y = D^-1 b, the solution of A x = b is
///     x = y + D^-1 P_I w,   S w = (b - A y)_I,   S = P_I^T A D^-1 P_I = I + E_II (D^-1)_II,
/// exactly: b - A y = -E y vanishes outside I, and A D^-1 P_I w = P_I w + E D^-1 P_I w. S is
/// as small as the interface (tens of unknowns per cut), assembled and factored redundantly on
/// every rank; its set-up costs one block solve per interface unknown a rank owns, per
/// factorisation. Each solve then costs one block application, the product of the coupling
/// entries with y's values on the other ranks ((b - A y)_I = -(E y)_I, the blocks' solves being
/// exact), an allgather of |I| numbers, a dense solve with S and D^-1 P_I w on each rank (kept
/// as Y = D^-1 P_I; condensed, one more reduced solve, so that only Y's rows other ranks reach
/// are kept).
///
/// With director beams the blocks solve condensed (DirectorCondensation): the correction then
/// works in the same reduced coordinates, N^T on the rows and N' on the columns, and the solve
/// is the exact solve of the condensed system, the step serial runs take (use_condensation).
/// A beam cut then costs 12 interface unknowns per side (two control points, 6 each).
///
/// Installed as the KSP's post-solve of a KSPPREONLY block Jacobi solve (one block per rank):
/// PETSc's block Jacobi and its block solvers stay as they are. The set-up costs one block
/// solve per interface unknown at every new Jacobian, so -sb_schwarz_exact takes it only while
/// no rank has more than -sb_schwarz_exact_max_interface rows coupled to another rank (many
/// joints cut at once), and GMRES otherwise.

#include <petscksp.h>

#include <Eigen/Dense>

#include <vector>

namespace slidebeam {

class DirectorCondensation;

/// After one block application (KSPPREONLY) on several ranks: a block that failed on any rank
/// (KSPSolve_PREONLY knows it on its own rank only, where Newton would stop while the other
/// ranks go on) makes x NaN on every rank, so that every rank's Newton fails at the same place
/// (the SNES must allow linear solve failures). failed (optional): whether it did.
PetscErrorCode fail_on_every_rank(KSP ksp, Vec x, bool* failed = nullptr);

class CouplingCorrection {
 public:
  /// enabled: -sb_schwarz_exact; max_interface: -sb_schwarz_exact_max_interface.
  CouplingCorrection(MPI_Comm comm, bool enabled, PetscInt max_interface)
      : comm_(comm), enabled_(enabled), max_interface_(max_interface) {}
  CouplingCorrection(const CouplingCorrection&) = delete;
  CouplingCorrection& operator=(const CouplingCorrection&) = delete;
  ~CouplingCorrection();

  /// Make ksp's solve exact: ksp is KSPPREONLY with PCBJACOBI, one block per rank, exact block
  /// solves. The set-up happens at the first solve with another matrix or after invalidate().
  PetscErrorCode attach(KSP ksp);
  /// The matrix has new values (a fresh Jacobian): set up again at the next solve.
  void invalidate() { stale_ = true; }
  /// Whether the correction is to solve with A: enabled, and no rank has more than
  /// max_interface rows coupled to another rank (collective; counted again when A's nonzero
  /// pattern changes).
  PetscErrorCode applies_to(Mat A, bool* yes);
  /// The most rows of a rank coupled to another rank, as applies_to last counted them.
  PetscInt coupled_rows() const { return largest_; }
  /// Remove the post-solve again (ranks no longer coupled).
  PetscErrorCode detach(KSP ksp);
  /// Solve in the blocks' reduced coordinates: the blocks apply condensation's reduced solve
  /// alone (DirectorCondensation, Exact mode with the manifold apply), and the correction
  /// works on N^T's rows, so the solve is the exact solve of the condensed system N^T A N',
  /// the step of the serial manifold Newton; a line search sets the multipliers. nullptr:
  /// the blocks' exact solves of the full system. Set before each solve with a new matrix.
  void use_condensation(DirectorCondensation* condensation) { condensation_ = condensation; }

 private:
  /// The ranks' coupling: this rank's off-rank entries (global row, column, value) and its
  /// interface unknowns (local numbering, sorted): rows with such entries, and columns that
  /// another rank's entries reach.
  struct Coupling {
    std::vector<PetscInt> rows, cols;
    std::vector<double> values;
    std::vector<PetscInt> interface;
    std::vector<PetscInt> coupled_rows;  // local rows with off-rank entries
    std::vector<PetscInt> referenced;    // local unknowns other ranks' entries reach
  };
  PetscErrorCode find_coupling(Mat A, Coupling* c) const;  // collective
  static PetscErrorCode post_solve(KSP ksp, Vec b, Vec x, void* ctx);
  PetscErrorCode setup(KSP ksp, Mat A);
  // the blocks' exact solves of the full system, or their condensed solves
  PetscErrorCode setup_full(KSP ksp, Mat A, const Coupling& coupling);
  PetscErrorCode setup_reduced(Mat A, const Coupling& coupling);
  PetscErrorCode correct(Mat A, Vec x);
  /// The interface's layout over the ranks from this rank's count: counts_, displs_, m_.
  PetscErrorCode lay_out(int mine);

  MPI_Comm comm_;
  bool enabled_;
  PetscInt max_interface_;
  PetscObjectId matrix_id_ = 0;
  bool stale_ = true;
  PetscObjectState counted_state_ = -1;  // applies_to: A's nonzero state when counted
  PetscObjectId counted_id_ = 0;
  PetscInt largest_ = 0;                 // ... the most rows a rank had coupled to another
  bool valid_ = false;                  // the last set-up's block solves succeeded
  PetscInt lo_ = 0;                     // first row this rank owns
  std::vector<PetscInt> local_;         // this rank's interface unknowns (local numbering)
  std::vector<int> counts_, displs_;    // interface unknowns per rank, offsets into I
  PetscInt m_ = 0;                      // |I|
  Eigen::MatrixXd Y_;                   // D^-1 P_I on this rank: rows local, columns this rank's part of I (full solves)
  Vec work_ = nullptr;                  // reduced mode: a reduced solve's result, in full coordinates
  DirectorCondensation* condensation_ = nullptr;
  // reduced mode: per interface unknown of this rank (a reduced row), the full local rows of
  // N^T's row and their weights
  std::vector<std::vector<std::pair<PetscInt, double>>> reduced_rows_;
  Eigen::PartialPivLU<Eigen::MatrixXd> S_;
  std::vector<double> r_local_, r_all_; // work: (b - A y)_I
  // (b - A y) = -E y on this rank's coupled rows (local numbering, sorted): y's values at the
  // off-rank columns of A's off-diagonal block, gathered by ghost_scatter_ into ghosts_
  std::vector<PetscInt> coupled_rows_;
  std::vector<double> coupled_residual_;
  VecScatter ghost_scatter_ = nullptr;
  Vec ghosts_ = nullptr;
};

}  // namespace slidebeam
