// SPDX-License-Identifier: MIT
#pragma once
/// @file Newton on the director constraint manifold: the linear solve of serial time steps with
/// the orthonormality constraints eliminated per control point (a discrete null-space method).
///
/// A director triad has 12 coordinates and 6 multipliers per control point, but only 6 degrees
/// of freedom: a displacement u and a rotation w, dq = N' (u, w) with
/// N' = [I 0; 0 -[d1]x; 0 -[d2]x; 0 -[d3]x] spanning the null space of the constraint Jacobian
/// C at the end of the step. The force rows are projected with N (the same matrix built from the
/// directors of the constraint forces' Jacobian G(x_f), so N^T G(x_f)^T = 0 exactly): the
/// multipliers drop out, and the step Jacobian reduces to N^T J N', 6 unknowns per control point
/// instead of 18. Its LU costs about 10x less than that of the saddle-point system, and it needs
/// no pivoting (c0 M projected on the rotations is regular: rho I2, rho I3 > 0).
///
/// Each Newton iterate is kept on the manifold: after the update, every triad is replaced by its
/// closest orthonormal frame (polar decomposition; or, set_exponential_update, turned by the
/// exponential of the step's rotation), so the constraint rows stay at roundoff and
/// need no particular solution; the multipliers are then set so that the force rows have no
/// component along G(x_f)^T (least squares, exact because the residual is linear in them). The
/// converged solution is that of the full system; only the path to it changes.
///
/// Two modes. Manifold (serial steps, the fast LU path of TimeIntegrator): the preconditioner
/// is the condensed LU alone and the line search keeps the iterates on the manifold, as above.
/// Exact (parallel steps: the subdomain solve of block Jacobi inside GMRES on the full system):
/// an exact solve of the rank's diagonal block for any right-hand side, with a particular
/// solution for the constraint rows (dq = N' a + C^T (C C^T)^-1 b_lambda) and the multipliers
/// recovered from the force rows, dlambda = (G G^T)^-1 G (b_q - J dq); two products with the
/// block on top of the reduced triangular solves.
///
/// A third mode, Update, is the manifold update alone for a linear solve on the full system (a
/// pivoting LU, MUMPS on several ranks): the line search projects this rank's triads and sets
/// their multipliers as above. On the manifold the full system's step satisfies C dq = 0, so its
/// director part is N' a with the a of the condensed solve: the iterates are the same.
///
/// Used when the model has triads. Control points with prescribed directors (a clamp) and all
/// other unknowns (ANCF nodes, supports', joints' and sliders' extras) pass through unchanged.
/// -sb_condense_directors false turns it off.

#include "model/model.hpp"

#include <petscsnes.h>

#include <Eigen/Dense>

#include <vector>

namespace slidebeam {

class DirectorCondensation {
 public:
  enum class Mode { Manifold, Exact, Update };
  /// Manifold mode on the whole system (serial).
  DirectorCondensation(const Model& model, const std::vector<PetscInt>& elimination_order);
  /// Any mode; Exact and Update work on this rank's unknowns (local numbering).
  DirectorCondensation(const Model& model, const std::vector<PetscInt>& elimination_order, Mode mode);
  ~DirectorCondensation();
  DirectorCondensation(const DirectorCondensation&) = delete;
  DirectorCondensation& operator=(const DirectorCondensation&) = delete;

  bool empty() const { return triads_.empty(); }
  /// Install on snes: KSP preonly with this preconditioner (the reduced LU), and the line
  /// search that keeps iterates on the manifold (Manifold mode).
  PetscErrorCode attach(SNES snes);
  /// attach again, after snes used another solver for a while (a fall-back to a pivoting LU),
  /// with the options read at the first attach.
  PetscErrorCode reattach(SNES snes);
  /// Install on snes the line search that keeps iterates on the manifold, and nothing else: the
  /// linear solve stays snes's own (Update mode; collective).
  PetscErrorCode attach_update(SNES snes);
  /// Make pc (a block's sub-preconditioner) this object's exact block solve (Exact mode).
  PetscErrorCode attach_to_block(PC pc);
  /// Constraint forces of the step act at x_f = (1 - theta) x_old + theta x and the residual is
  /// scaled by s (HHT): needed to set the multipliers in the line search.
  void set_force_state(Vec x_old, double theta, double scale) {
    x_old_ = x_old;
    theta_ = theta;
    scale_ = scale;
  }
  /// Replace every triad of x by its closest orthonormal frame.
  PetscErrorCode project(Vec x) const;
  /// Iterates turn each triad by the exponential of the step's rotation w (instead of taking the
  /// closest frame of d + w x d, which turns by atan|w|). Static solves: a load step's first
  /// iterate turns by tenths of a radian, where the two differ by a few percent.
  void set_exponential_update(bool on) { exponential_ = on; }
  /// Keep the multipliers of the Newton step instead of setting them by least squares (Update
  /// mode only: the step must carry them, as a solve of the full system does).
  void set_newton_multipliers(bool on) { newton_multipliers_ = on; }
  /// The line search halves a step that makes |F| grow, up to 6 times (off by default; the time
  /// integrator's retry of a failed step, -sb_backtrack). Not as a rule: a Newton iteration that
  /// converges often grows |F| first (large rotations in a load step: the roll-up's first load
  /// step took 73 iterations halved; a stiff rail at a large time step), and halved it fails.
  void set_backtrack(bool on) { backtrack_ = on; }
  /// The SNES's Jacobian was just rebuilt: the next direction is a fresh Jacobian's, which the
  /// line search may shorten (an old Jacobian's growing step calls for a rebuild instead).
  void jacobian_rebuilt() { ++rebuilds_; }
  /// Exact mode: apply the reduced solve alone (no particular solution for the constraint rows,
  /// no multipliers), as in Manifold mode. Right when the block solve is the whole linear solve
  /// (ranks not coupled) and a line search keeps the iterates on the manifold and sets the
  /// multipliers (an Update-mode object on the same SNES): the two products with the block go.
  /// Set before the block is set up (its exact solve's data is built only when needed).
  void set_manifold_apply(bool on) { manifold_apply_ = on; }
  /// Number of reduced unknowns.
  PetscInt reduced_size() const { return n_red_; }
  /// Exact mode with the manifold apply, after the block's set-up (the coupling correction):
  /// the reduced rows that full row `row` (local) contributes to in N^T b, with their weights,
  /// into out (replaced; empty for a triad's multiplier rows).
  void reduced_weights(PetscInt row, std::vector<std::pair<PetscInt, double>>* out) const;
  /// The inverse: the full rows (local) whose reduced_weights reach reduced row `reduced`, into
  /// out (replaced): a triad's position row, its 9 director rows for a rotation row, or the
  /// unknown itself.
  void full_rows(PetscInt reduced, std::vector<PetscInt>* out) const;
  /// ... y = N' Jr^-1 e_j: the block's reduced solve of the unit vector of reduced unknown j,
  /// in full coordinates (0 on the triads' multipliers), as the manifold apply returns it.
  PetscErrorCode solve_reduced_unit(PetscInt j, Vec y);
  /// ... y = N' Jr^-1 r for the reduced right-hand side r whose nonzeros are values at reduced
  /// unknowns rows, in full coordinates.
  PetscErrorCode solve_reduced(const std::vector<PetscInt>& rows, const std::vector<PetscScalar>& values, Vec y);

 private:
  struct Group {      // a row/column group of the full system
    PetscInt first;   // first full unknown
    int size;         // full unknowns: 12 (triad coordinates) or 1
    int triad;        // index into triads_, or -1
    PetscInt base;    // first reduced unknown (6 for a triad, 1 otherwise)
  };
  using Mat9x3 = Eigen::Matrix<double, 9, 3>;

  static PetscErrorCode pc_setup(PC pc);
  static PetscErrorCode pc_apply(PC pc, Vec b, Vec y);
  static PetscErrorCode line_search(SNESLineSearch ls, void* ctx);
  PetscErrorCode setup(Mat J, bool* ok);
  PetscErrorCode build_pattern(Mat J);
  PetscErrorCode apply(Vec b, Vec y);
  PetscErrorCode apply_exact(Mat A, Vec b, Vec y);
  PetscErrorCode search(SNESLineSearch ls);
  /// -sb_corotate_jacobian from the options database (at attach).
  PetscErrorCode read_options();
  PetscErrorCode install_line_search(SNES snes);
  /// One trial of the line search: W = X - lambda Y on the manifold, its multipliers set, F =
  /// F(W); norms = |F|, |W|, |W - X|.
  PetscErrorCode trial(SNES snes, Vec X, Vec Y, double lambda, Vec W, Vec F, PetscReal* norms);
  int red_size(const Group& g) const { return g.triad >= 0 ? 6 : 1; }
  /// y's part of group G from the reduced solution a, with the set-up's N' (not co-rotated).
  void expand(const Group& G, const PetscScalar* a, PetscScalar* yy) const;

  std::vector<PetscInt> triads_;       // first unknown of each triad's block (owned, serial)
  std::vector<Group> groups_;
  std::vector<int> group_of_;          // full unknown -> group (-1: a triad's multiplier)
  PetscInt n_ = 0, n_red_ = 0;
  // reduced matrix: per row group the column groups it couples to (sorted by reduced index) and
  // their offsets within a reduced row
  std::vector<std::vector<int>> adj_;
  std::vector<std::vector<PetscInt>> col_offset_;
  std::vector<PetscInt> row_ptr_;      // CSR row pointers of the reduced matrix
  // The cached pattern belongs to one matrix object in one nonzero state. Block Jacobi makes a
  // new block matrix when the Jacobian's pattern changes, and a new object's state counter can
  // equal the old one's, so the object's id is part of the key.
  PetscObjectId pattern_id_ = 0;
  PetscObjectState pattern_state_ = -1;
  Mat Jr_ = nullptr, F_ = nullptr;
  bool symbolic_done_ = false;
  bool factored_ = false;              // the last set-up gave factors (apply needs them)
  bool blocked_ = false;               // Jr_ is BAIJ with 6 x 6 blocks (triads only)
  Vec rr_ = nullptr, a_ = nullptr;     // reduced right-hand side and solution
  std::vector<Mat9x3> S_, Sp_;         // rotation columns of N (force state) and N' (end state)
  // Co-rotated reuse (Manifold mode): the triads (columns d1, d2, d3, end state) of the
  // factored Jacobian, and the SNES whose current iterate the solve rotates the factors to.
  std::vector<Eigen::Matrix3d> triad_at_setup_;
  double scale_at_setup_ = 1.0;        // the residual's scale s when the factored Jacobian was built
  SNES snes_ = nullptr;
  PetscBool corotate_ = PETSC_TRUE;
  std::vector<Eigen::Matrix3d> rotation_;  // work: R per triad in apply()
  Mode mode_ = Mode::Manifold;
  // Exact mode: per triad C^T (C C^T)^-1 and (G G^T)^-1 G on the directors, and work vectors
  std::vector<Eigen::Matrix<double, 9, 6>> Cpinv_;
  std::vector<Eigen::Matrix<double, 6, 9>> Gpinv_;
  Mat block_ = nullptr;                // the block of the last set-up (not owned)
  Vec p_ = nullptr, t_ = nullptr;
  // line search state
  bool exponential_ = false;
  bool backtrack_ = false;             // set_backtrack
  long rebuilds_ = 0, rebuilds_seen_ = 0;  // jacobian_rebuilt() calls; as of the last line search
  Vec f_best_ = nullptr;               // backtracking: F of the best trial
  bool newton_multipliers_ = false;
  bool manifold_apply_ = false;
  Vec x_old_ = nullptr;
  double theta_ = 1.0, scale_ = 1.0;
};

}  // namespace slidebeam
