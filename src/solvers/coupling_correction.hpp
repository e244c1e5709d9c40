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
/// factorisation. Each solve then costs one block application, one product with A, an
/// allgather of |I| numbers, a dense solve with S and Y = D^-1 P_I times w on each rank.
///
/// Installed as the KSP's post-solve of a KSPPREONLY block Jacobi solve (one block per rank):
/// PETSc's block Jacobi and its block solvers stay as they are.
///
/// The set-up's block solves cost about as much as 20 GMRES iterations at 24 interface unknowns
/// per cut and side, so where GMRES needs 1-2 iterations it is the cheaper exact solve. The
/// default (-sb_schwarz_exact auto) therefore lets GMRES iterate and watches it: once a solve
/// takes more than -sb_schwarz_exact_after iterations or fails, the correction takes over
/// from the next Jacobian on (a failed step is retried with it before MUMPS), for the rest of
/// the run, as long as no rank has more than -sb_schwarz_exact_max_interface interface unknowns (large steps, many ranks: where block Jacobi's iterations grow
/// with h and with the number of ranks). While watching, the same post-solve hook only counts.

#include <petscksp.h>

#include <Eigen/Dense>

#include <vector>

namespace slidebeam {

class CouplingCorrection {
 public:
  explicit CouplingCorrection(MPI_Comm comm) : comm_(comm) {}
  CouplingCorrection(const CouplingCorrection&) = delete;
  CouplingCorrection& operator=(const CouplingCorrection&) = delete;
  ~CouplingCorrection();

  /// Make ksp's solve exact: ksp is KSPPREONLY with PCBJACOBI, one block per rank, exact block
  /// solves. The set-up happens at the first solve with another matrix or after invalidate().
  PetscErrorCode attach(KSP ksp);
  /// Watch ksp's Krylov solves instead (auto mode): a solve slower than `after` iterations, or
  /// one that fails, makes exact_wanted() true, unless a rank has more than `max_interface`
  /// interface unknowns (then MUMPS takes over once a step fails).
  PetscErrorCode watch(KSP ksp, PetscInt after, PetscInt max_interface);
  /// Whether a watched Krylov solve asked for the exact correction.
  bool exact_wanted() const { return exact_wanted_; }
  /// Whether the last solve was corrected (false: watched, or not attached).
  bool exact() const { return exact_; }
  /// The matrix has new values (a fresh Jacobian): set up again at the next solve.
  void invalidate() { stale_ = true; }
  /// Remove the post-solve again (ranks no longer coupled).
  PetscErrorCode detach(KSP ksp);
  /// Interface unknowns of all ranks at the last set-up (0 before the first).
  PetscInt interface_size() const { return m_; }
  /// Set-ups so far (one per factorisation of the Jacobian).
  int setups() const { return setups_; }

 private:
  /// The ranks' coupling: this rank's off-rank entries (global row, column, value) and its
  /// interface unknowns (local numbering, sorted): rows with such entries, and columns that
  /// another rank's entries reach.
  struct Coupling {
    std::vector<PetscInt> rows, cols;
    std::vector<double> values;
    std::vector<PetscInt> interface;
  };
  PetscErrorCode find_coupling(Mat A, Coupling* c) const;  // collective
  PetscErrorCode largest_interface(Mat A, PetscInt* largest) const;  // over the ranks
  static PetscErrorCode post_solve(KSP ksp, Vec b, Vec x, void* ctx);
  PetscErrorCode setup(KSP ksp, Mat A);
  PetscErrorCode correct(Mat A, Vec b, Vec x);

  MPI_Comm comm_;
  PetscObjectId matrix_id_ = 0;
  bool stale_ = true;
  bool valid_ = false;                  // the last set-up's block solves succeeded
  bool exact_ = false;                  // attached (correcting), not watching
  bool exact_wanted_ = false;
  PetscInt watch_after_ = 0;
  PetscInt max_interface_ = 0;
  bool too_large_ = false;              // the interface was too large when a solve asked for the correction
  PetscInt lo_ = 0;                     // first row this rank owns
  std::vector<PetscInt> local_;         // this rank's interface unknowns (local numbering)
  std::vector<int> counts_, displs_;    // interface unknowns per rank, offsets into I
  PetscInt m_ = 0;                      // |I|
  Eigen::MatrixXd Y_;                   // D^-1 P_I on this rank: rows local, columns this rank's part of I
  Eigen::PartialPivLU<Eigen::MatrixXd> S_;
  std::vector<double> r_local_, r_all_; // work: (b - A y)_I
  Vec work_ = nullptr;
  int setups_ = 0;
};

}  // namespace slidebeam
