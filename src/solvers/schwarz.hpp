// SPDX-License-Identifier: MIT
#pragma once
/// @file A linear solver path for big scenes beyond one direct LU, the default on more than one
/// rank (-sb_schwarz): GMRES preconditioned by Schwarz on the model's own subdomains.
///  - Default (-sb_schwarz_overlap 0): block Jacobi, one block per rank: its diagonal block of
///    the Jacobian (no copy), factored by PETSc's LU in the model's elimination order restricted
///    to the rank. Joint and support multipliers live with the points they constrain (DofMap),
///    so every block is regular; on the cable scenes GMRES needs 1-2 iterations.
///  - -sb_schwarz_overlap 1: restricted additive Schwarz whose subdomains add every unknown the
///    rank's rows couple to (from the Jacobian's current pattern), listed in elimination order
///    and left unsorted, so that the subdomain's LU in natural order is the model's order.
/// PETSc's default subdomains are sorted: they would need a pivoting LU (SuperLU) and more
/// iterations.

#include "model/model.hpp"

#include <petscsnes.h>

namespace slidebeam {

/// True if the options database holds key under the solver's prefix (e.g. -sb_ts_sub_pc_type,
/// or the copy of a plain -sub_pc_type) and configure_schwarz did not put it there.
bool user_sets_schwarz_option(const char* prefix, const char* key);

/// Whether to use the Schwarz path: -sb_schwarz [true|false] if given; otherwise on more than
/// one rank (where it beats MUMPS on the saddle-point systems, whose zero diagonals make MUMPS
/// delay nearly every multiplier pivot), unless the options name a KSP, PC or factor package
/// for the solver of `prefix` (plain or prefixed).
bool schwarz_requested(MPI_Comm comm, const char* prefix);
/// Set snes's KSP to GMRES and its PC to ASM on the model's subdomains (before
/// SNESSetFromOptions, so options still win), with sub-solvers PETSc LU in natural order unless
/// the options database names others (under the SNES's prefix: -sb_ts_sub_pc_type, ...).
PetscErrorCode configure_schwarz(SNES snes, const Model& model, Mat J);
/// ASM: (re)build the subdomains from J's pattern.
PetscErrorCode set_schwarz_subdomains(PC pc, const Model& model, Mat J);
/// How the block Jacobi path solves a step's linear system.
enum class SchwarzSolve {
  Blocks,     ///< ranks not coupled (or one rank owns all): one application of the exact blocks
  Corrected,  ///< ranks coupled: one application plus the exact coupling correction
  Krylov,     ///< GMRES iterates (ASM, -sb_schwarz_exact false, or a KSP the options name)
};
/// Before a solve with a freshly assembled J: after a PCReset (pattern_changed) set ksp's PC up
/// again; for block Jacobi attach the rank's elimination order to J's diagonal block (which a
/// new pattern may have replaced), and solve with one application (KSPPREONLY): while J couples
/// no two ranks the blocks' solve is exact; once it does, the coupling correction makes it exact
/// (CouplingCorrection, owned by ksp), or GMRES iterates (-sb_schwarz_exact; auto: the
/// correction unless a rank has many rows coupled to another). A KSP the options name stays.
/// `solve` (optional) receives which of these it is.
PetscErrorCode prepare_schwarz(KSP ksp, const Model& model, Mat J, bool pattern_changed,
                               SchwarzSolve* solve = nullptr);
/// The coupling correction prepare_schwarz composed with ksp (ranks coupled), or nullptr.
class CouplingCorrection* coupling_correction(KSP ksp);
/// Whether any entry of J couples unknowns owned by different ranks (collective).
PetscErrorCode ranks_coupled(Mat J, bool* coupled);

}  // namespace slidebeam
